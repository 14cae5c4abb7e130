// What the file-reader harnesses share: the input goes to a scratch file (the readers take a
// path), one per process so that parallel fuzzing jobs never share it; and the checks every
// reader's contract implies (imageio.hpp): a failure is one of the errors a readable file can
// cause, has a message, and leaves the output empty; a success gives planes of the stated size.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "imageio/imageio.hpp"

namespace reproject::fuzz {

[[noreturn]] inline void fail(const char* harness, const char* what) {
  std::fprintf(stderr, "%s: check failed: %s\n", harness, what);
  std::abort();
}
#define FUZZ_CHECK(condition)                            \
  do {                                                   \
    if (!(condition)) ::reproject::fuzz::fail(kHarness, #condition); \
  } while (0)

// Writes the input to this process's scratch file, named with `extension` (the by-extension
// readers dispatch on it), and returns its path. Removed at exit.
inline const std::string& write_scratch(const char* extension, const std::uint8_t* data, std::size_t size) {
  static const std::string path = [extension] {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir != nullptr && *dir != '\0' ? dir : "/tmp") + "/reproject-fuzz." +
           std::to_string(static_cast<long>(getpid())) + extension;
  }();
  static const bool registered = [] { return std::atexit([] { std::remove(path.c_str()); }) == 0; }();
  (void)registered;
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) fail("fuzz", "cannot create the scratch file");
  const bool written = std::fwrite(data, 1, size, file) == size;
  if (std::fclose(file) != 0 || !written) fail("fuzz", "cannot write the scratch file");
  return path;
}

// A failed read of an existing, readable file: only its content can be at fault.
inline bool content_error(io::IoError error) {
  return error == io::IoError::not_this_format || error == io::IoError::truncated || error == io::IoError::corrupt ||
         error == io::IoError::unsupported || error == io::IoError::out_of_memory;
}

// The planes of a loaded image agree with it: positive size, strides covering the rows.
inline bool consistent(const Image& image) {
  if (image.empty()) return false;
  if (image.width() <= 0 || image.height() <= 0 || image.channels() < 1 || image.channels() > 4) return false;
  for (int c = 0; c < image.channels(); ++c) {
    const FloatPlane plane = image.plane(c);
    if (plane.data == nullptr || plane.width != image.width() || plane.height != image.height() ||
        plane.stride < plane.width)
      return false;
  }
  return true;
}

// Reads every value of every plane: ASan then proves the planes really are that large.
inline float touch_all(const Image& image) {
  float sum = 0.0f;
  for (int c = 0; c < image.channels(); ++c) {
    const FloatPlane plane = image.plane(c);
    for (int y = 0; y < plane.height; ++y)
      for (int x = 0; x < plane.width; ++x) sum += plane.row(y)[x] * 0.0f;
  }
  return sum;
}

}  // namespace reproject::fuzz
