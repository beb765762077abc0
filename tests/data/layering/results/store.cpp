// Fixture for LayeringTest.
#include "engine/model/arm_model.hpp"
#include <sqlite3.h>
