// Fixture for LayeringTest: a sampler reading JSON.
#include "runner/search/search_space.hpp"
#include "nlohmann/json.hpp"
