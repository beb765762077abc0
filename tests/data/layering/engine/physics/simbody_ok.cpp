// Fixture for LayeringTest: Simbody is allowed here.
#include <Simbody.h>
