// Errors are values: every public call that can fail returns a Status.
// Nothing in the library throws across the API, and building a Status never allocates.
#pragma once

#include <cstddef>

namespace reproject {

enum class StatusCode : int {
  ok = 0,
  null_pointer,      // a required buffer pointer is null
  invalid_size,      // a negative width or height, or a guard band that leaves no target columns
  invalid_stride,    // a row stride smaller than the row (in elements)
  size_mismatch,     // buffers that must agree in size, channel count or layout do not
  aliasing,          // an output buffer overlaps an input buffer or another output
  invalid_decoder,   // depth decoder parameters out of range (near <= 0, far <= near, non-finite, ...)
  invalid_model,     // parallax model parameters non-finite or degenerate (convergence <= 0, ...)
  invalid_option,    // an Options field out of range (negative threshold, steps < 1, ...)
  cancelled,         // Options::cancel was set while the call ran: its outputs are unspecified
  out_of_memory,     // the allocator (reproject/memory.hpp) had no memory: nothing written, nothing kept
};

// Short stable name of a code, e.g. "invalid_stride".
const char* to_string(StatusCode code) noexcept;

// [[nodiscard]]: a call whose Status is dropped is a compile warning, wherever a function returns
// one by value.
class [[nodiscard]] Status {
 public:
  Status() noexcept = default;  // ok
  // printf-style message, in the C99 dialect on every platform (%td, %zu, %lld; src/status.cpp);
  // truncated to fit the fixed buffer.
  Status(StatusCode code, const char* format, ...) noexcept
#if defined(__MINGW32__) && !defined(__clang__)
      // GCC's `printf` means msvcrt's dialect on MinGW; the message is formatted by MinGW's own
      // C99 printf, which `gnu_printf` describes.
      __attribute__((format(gnu_printf, 3, 4)))
#elif defined(__GNUC__)
      __attribute__((format(printf, 3, 4)))
#endif
      ;

  bool ok() const noexcept { return code_ == StatusCode::ok; }
  explicit operator bool() const noexcept { return ok(); }
  StatusCode code() const noexcept { return code_; }
  // Human-readable: what was wrong and with which value. "ok" when ok.
  const char* message() const noexcept { return ok() ? "ok" : message_; }

 private:
  StatusCode code_ = StatusCode::ok;
  char message_[192] = {};
};

}  // namespace reproject
