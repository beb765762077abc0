// `armfarm lwpr export --db DB --job KEY -o FILE`: writes the model a job stored as a model file
// (what `lwpr inspect|predict`, `learning.initial_model` and any later armfarm read), checked by
// decoding it first; nothing is half-written under FILE.
#include "runner/cli/lwpr_model_input.hpp"
#include "runner/cli/subcommand.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>

namespace armfarm::cli {

RunFunction setup_lwpr_export(CLI::App& group) {
  auto input = std::make_shared<ModelInput>();
  auto output = std::make_shared<std::string>();
  CLI::App* app = group.add_subcommand("export", "Write a stored (or saved) model to a model file");
  add_model_input_options(*app, *input);
  app->add_option("-o,--output", *output, "Model file to write")->required();
  return [input, output] {
    const LoadedModel loaded = load_model_input(*input);
    const std::string temporary = *output + ".tmp";
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      if (!out) throw std::runtime_error(*output + ": cannot write");
      out.write(loaded.bytes.data(), static_cast<std::streamsize>(loaded.bytes.size()));
      out.flush();
      if (!out) {
        out.close();
        std::filesystem::remove(temporary);
        throw std::runtime_error(*output + ": cannot write");
      }
    }
    std::filesystem::rename(temporary, *output);
    std::printf("%s: %zu bytes from %s\n", output->c_str(), loaded.bytes.size(), loaded.source.c_str());
    return 0;
  };
}

}  // namespace armfarm::cli
