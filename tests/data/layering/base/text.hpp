// Fixture: base/ may include the standard library only.
#include <string>
#include "engine/io/number_text.hpp"
