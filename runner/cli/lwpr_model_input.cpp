#include "runner/cli/lwpr_model_input.hpp"

#include "engine/io/input_file.hpp"
#include "engine/learning/learner_model_file.hpp"
#include "runner/execution/stored_models.hpp"

#include <stdexcept>

namespace armfarm::cli {

void add_model_input_options(CLI::App& app, ModelInput& input) {
  app.add_option("model", input.file, "A saved model file (or give --db and --job)");
  app.add_option("--db", input.db, "Results database holding the model a job stored (learning.store_model)");
  app.add_option("--job", input.job, "Key (or a unique prefix) of the job whose model to use");
}

LoadedModel load_model_input(const ModelInput& input) {
  LoadedModel loaded;
  const bool from_file = !input.file.empty();
  if (from_file == (!input.db.empty() || !input.job.empty())) {
    throw std::runtime_error("give either a model file or --db DB --job KEY");
  }
  if (from_file) {
    loaded.source = input.file;
    loaded.bytes = read_input_file(input.file, InputFileKind::learner_model);
  } else {
    if (input.db.empty() || input.job.empty()) throw std::runtime_error("--db and --job go together");
    StoredModels models(input.db);
    try {
      const StoredModels::Resolved resolved = models.resolve({{"job", input.job}});
      loaded.source = input.db + " job " + resolved.job_key;
      loaded.bytes = models.find_bytes(resolved.hash);
    } catch (const std::runtime_error& error) {
      throw std::runtime_error(input.db + ": " + error.what());
    }
  }
  try {
    loaded.learner = decode_learner_model(loaded.bytes);
  } catch (const std::exception& error) {
    throw std::runtime_error(loaded.source + ": " + error.what());
  }
  return loaded;
}

}  // namespace armfarm::cli
