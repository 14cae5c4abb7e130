#include "reproject/status.hpp"

#include <cstdarg>
#include <cstdio>

namespace reproject {

const char* to_string(StatusCode code) noexcept {
  switch (code) {
    case StatusCode::ok: return "ok";
    case StatusCode::null_pointer: return "null_pointer";
    case StatusCode::invalid_size: return "invalid_size";
    case StatusCode::invalid_stride: return "invalid_stride";
    case StatusCode::size_mismatch: return "size_mismatch";
    case StatusCode::aliasing: return "aliasing";
    case StatusCode::invalid_decoder: return "invalid_decoder";
    case StatusCode::invalid_model: return "invalid_model";
    case StatusCode::invalid_option: return "invalid_option";
    case StatusCode::cancelled: return "cancelled";
  }
  return "unknown";
}

Status::Status(StatusCode code, const char* format, ...) noexcept : code_(code) {
  va_list args;
  va_start(args, format);
  std::vsnprintf(message_, sizeof message_, format, args);
  va_end(args);
}

}  // namespace reproject
