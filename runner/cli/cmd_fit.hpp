#pragma once
// `armfarm fit --learner lwpr|ssgpr`: batch-train a learner on a recorded CSV and report its
// test nMSE, size, speed and memory (the thesis's "creating LWPR models" phase, for either
// learner). `armfarm lwpr fit` is the same command with the learner fixed to LWPR
// (cmd_lwpr_fit.cpp); both register their options through add_fit_options().
#include <CLI/CLI.hpp>

#include <string>

namespace armfarm::cli {

struct FitOptions {
  std::string learner = "lwpr";  ///< a spelling of learner_kind_names()
  std::string train, test, params, save;
  int inputs = 0;
  int epochs = 1;
  long long shuffle = -1;
  bool json = false;
};

/// Every option but --learner.
void add_fit_options(CLI::App& app, FitOptions& options);

/// Runs the fit; 0 on success. Throws std::runtime_error (one line naming the file) for bad input.
int run_fit(const FitOptions& options);

}  // namespace armfarm::cli
