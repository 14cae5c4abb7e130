#include "reproject/status.hpp"

#include <cstdarg>
#include <cstdio>

namespace reproject {

Status::Status(StatusCode code, const char* format, ...) noexcept : code_(code) {
  va_list args;
  va_start(args, format);
  std::vsnprintf(message_, sizeof message_, format, args);
  va_end(args);
}

}  // namespace reproject
