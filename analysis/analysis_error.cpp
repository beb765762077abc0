#include "analysis/analysis_error.hpp"
