// Out-of-line anchor for the Learner interface's vtable.
#include "engine/learning/learner.hpp"
