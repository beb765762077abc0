#pragma once
// Where the `armfarm lwpr inspect|predict|export` verbs take a learned model from: a saved model
// file (`armfarm lwpr fit --save`, `lwpr export`), or the model a job stored in a results
// database (learning.store_model), named by its key: `MODEL.lwpr` or `--db DB --job KEY`.
#include "engine/learner/learner.hpp"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

namespace armfarm::cli {

struct ModelInput {
  std::string file;
  std::string db;
  std::string job;
};

/// Registers the optional positional MODEL and --db/--job on `app`.
void add_model_input_options(CLI::App& app, ModelInput& input);

struct LoadedModel {
  std::string source;  ///< "FILE" or "DB job KEY", for messages and headers
  std::string bytes;   ///< the model file
  std::unique_ptr<Learner> learner;
};

/// Reads and decodes the model. Throws std::runtime_error with one line naming the file or the
/// database and job (wrong option combination, no such job or model, a corrupt file).
LoadedModel load_model_input(const ModelInput& input);

}  // namespace armfarm::cli
