// The version string compiled into liblambert: what the library is, whatever headers a program
// was built with.
#include "lambert/version.h"

namespace lambert {

const char* version() { return LAMBERT_VERSION_STRING; }

}  // namespace lambert
