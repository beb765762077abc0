// Fixture for LayeringTest: a folder missing from the engine table fails.
#include "engine/model/arm_model.hpp"
