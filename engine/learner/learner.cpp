// Out-of-line anchor for the Learner interface's vtable.
#include "engine/learner/learner.hpp"
