// Image files for the tests and the tools (not part of the kernel library): PNG through libpng.
// Pixels are planar reproject::Image float planes holding the stored integer values
// (0..255 or 0..65535), never rescaled, gamma-corrected or colour-managed.
//
// Every function reports failure as a value and nothing throws out of it. Writers build the file
// under a temporary name next to the destination and rename it into place only once it is
// complete, so a failed write leaves neither a partial file nor a changed destination.
#pragma once

#include <cstdint>
#include <string>

#include "reproject/image.hpp"

namespace reproject::io {

enum class IoError : std::uint8_t {
  none = 0,
  invalid_argument,  // a null output, an empty image, an unsupported channel count or bit depth
  open_failed,       // the file cannot be opened (missing, no permission, ...)
  read_failed,       // reading failed (an I/O error, a directory, ...)
  not_this_format,   // the file is not of the format read (e.g. no PNG signature)
  truncated,         // the file ends before the image does
  corrupt,           // the format's decoder rejected the data (CRC error, bad chunk, ...)
  unsupported,       // valid data this reader does not handle (e.g. larger than the size limit)
  out_of_memory,
  write_failed,      // creating, writing or renaming the output failed
};
const char* to_string(IoError error) noexcept;

// The result of every call: ok, or what went wrong with which file.
struct IoStatus {
  IoError error = IoError::none;
  std::string message;  // empty when ok; else a sentence naming the file

  bool ok() const noexcept { return error == IoError::none; }
  explicit operator bool() const noexcept { return ok(); }
};

// A decoded image: planar float planes with the stored values, and the bits per stored sample.
struct LoadedImage {
  Image image;        // 1 plane grey, 2 grey + alpha, 3 RGB, 4 RGBA
  int bit_depth = 0;  // 8 or 16 for PNG: values lie in 0 .. 2^bit_depth - 1
};

// Reads a PNG file: 8- and 16-bit grey, grey + alpha, RGB and RGBA as stored. Other forms are
// expanded by libpng to one of these: palette to RGB (RGBA if it has a transparency chunk),
// 1/2/4-bit grey to 8 bits (scaled to 0..255), a tRNS colour key to an alpha plane.
// Interlaced files are de-interlaced. Ancillary data (gamma, colour profile, text) is ignored.
// On failure `*out` is left empty.
IoStatus read_png(const std::string& path, LoadedImage* out);

// Writes `color` as an 8- or 16-bit PNG: 1 channel grey, 2 grey + alpha, 3 RGB, 4 RGBA (planar or
// interleaved RGBA). Values are rounded to the nearest integer and clamped to
// 0 .. 2^bit_depth - 1; NaN is written as 0. An existing file at `path` is replaced.
IoStatus write_png(const std::string& path, const ColorView& color, int bit_depth = 8);

}  // namespace reproject::io
