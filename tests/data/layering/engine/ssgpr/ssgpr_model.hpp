#pragma once
// Fixture for LayeringTest: one learner may not include another; engine/random is allowed.
#include "engine/lwpr/lwpr_params.hpp"
#include "engine/random/rng.hpp"
