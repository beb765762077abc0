#pragma once
// Fixture for LayeringTest: every include below but the last points the wrong way.
#include "runner/spec/sweep_spec.hpp"
#include <nlohmann/json.hpp>
#include "engine/experiment/run_experiment.hpp"
#include <Simbody.h>
#include "engine/model/arm_model.hpp"
