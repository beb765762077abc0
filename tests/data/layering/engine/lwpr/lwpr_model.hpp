#pragma once
// Fixture for LayeringTest: the cycle engine/lwpr -> engine/learning (the factory); the second include is allowed.
#include "engine/learning/learner_factory.hpp"
#include "engine/learner/learner.hpp"
