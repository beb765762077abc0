// Fixture for LayeringTest.
#include "results/results_store.hpp"
#include "engine/model/arm_model.hpp"
#include "base/did_you_mean.hpp"
