#include "reproject/status.hpp"

#include <cstdarg>
#include <cstdio>

namespace reproject {

Status::Status(StatusCode code, const char* format, ...) noexcept : code_(code) {
  va_list args;
  va_start(args, format);
#if defined(__MINGW32__)
  // MinGW-w64's own C99 printf, whatever __USE_MINGW_ANSI_STDIO says: msvcrt.dll's knows neither
  // %td nor %zu (docs/ARCHITECTURE.md, "Messages").
  __mingw_vsnprintf(message_, sizeof message_, format, args);
#else
  // glibc, and MSVC's Universal CRT (Visual Studio 2015 on): C99's dialect.
  std::vsnprintf(message_, sizeof message_, format, args);
#endif
  va_end(args);
}

}  // namespace reproject
