// Fixture for LayeringTest.
#include "engine/model/arm_model.hpp"
#include <sqlite3.h>
#include "base/did_you_mean.hpp"
