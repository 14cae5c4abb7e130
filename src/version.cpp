// The library's version, for C++, the C interface, the Python package and the CLI. The string
// comes from the configured header (src/version_config.hpp.in), so the version is written once,
// in the top-level CMakeLists.txt.
#include "reproject/reproject.h"
#include "reproject/reproject.hpp"
#include "version_config.hpp"

namespace reproject {

const char* version() noexcept { return REPROJECT_VERSION_STRING; }

}  // namespace reproject

const char* reproject_version(void) { return reproject::version(); }
