// Fixture for LayeringTest: the CSV layer may use the engine's I/O and the store, none of the runner's other folders.
#include "engine/io/number_text.hpp"
#include "results/results_store.hpp"
#include "runner/spec/sweep_spec.hpp"
#include "runner/execution/job_kind.hpp"
