#pragma once
// Fixture for LayeringTest: the interface below its implementations may not include them.
#include "engine/lwpr/lwpr_model.hpp"
