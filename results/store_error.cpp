#include "results/store_error.hpp"
