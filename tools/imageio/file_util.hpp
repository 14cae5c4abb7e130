// Internal to reproject_imageio: pieces every format's reader and writer share.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

#include "imageio/imageio.hpp"

namespace reproject::io::detail {

IoStatus failure(IoError error, std::string message);
// "'path'" for messages.
std::string quote_path(const std::string& path);
// strerror(code) as a string.
std::string system_error_text(int code);
// read_failed: "cannot read 'path': <strerror(code)>".
IoStatus read_error(const std::string& path, int code);
// "WxH" for messages.
std::string size_text(int width, int height);

// Larger images are refused (unsupported) instead of attempting multi-GiB allocations.
constexpr unsigned long long kMaxPixels = 1ULL << 28;

// unsupported for the path "-": the readers do not take standard input (docs/CLI.md).
IoStatus refuse_standard_input(const std::string& path);

// An input file, opened only when it is a regular file: anything else (a FIFO, a device, a
// directory, "-") is refused before a byte is read, and opening never blocks (docs/CLI.md).
// Closes on destruction.
class InputFile {
 public:
  InputFile() = default;
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  IoStatus open(const std::string& path);
  std::FILE* get() const noexcept { return file_; }

 private:
  std::FILE* file_ = nullptr;
};

// A file written under a temporary name in the destination's directory and renamed onto the
// destination by commit(); destroyed uncommitted, it closes and deletes the temporary file, so the
// destination is either the complete new file or untouched.
class ReplacingFile {
 public:
  ReplacingFile() = default;
  ~ReplacingFile();
  ReplacingFile(const ReplacingFile&) = delete;
  ReplacingFile& operator=(const ReplacingFile&) = delete;

  IoStatus create(const std::string& destination);
  std::FILE* get() const noexcept { return file_; }
  // Flushes, closes and renames onto the destination. Any failure removes the temporary file.
  IoStatus commit();

 private:
  void discard() noexcept;
  std::FILE* file_ = nullptr;
  std::string destination_;
  std::string temporary_;
};

// Nearest integer in [0, max_value]; NaN gives 0. Ties round away from zero.
std::uint32_t quantise(float value, std::uint32_t max_value) noexcept;

// Checks that `color` can be written: 1-4 channels (4 when interleaved), a non-empty size, data
// present, strides covering the row, every plane the same size (else size_mismatch).
IoStatus check_writable(const ColorView& color);
// Checks that a packed view can be written: its format is `format` (rgba8 also takes
// rgba8_srgb: the same bytes), `channels` is 1..4, a non-empty size, data present, the stride
// covering the row.
IoStatus check_packed(const ColorView& packed, int channels, ColorFormat format);
// Sample c of pixel x in row y, whatever the layout.
inline float sample(const ColorView& color, int c, int x, int y) noexcept {
  if (color.layout == ColorLayout::interleaved_rgba) return color.plane[0].row(y)[4 * x + c];
  return color.plane[c].row(y)[x];
}

// The OpenEXR reader as read_image and read_depth use it (exr.cpp): the colour, with the depth
// channel when there is one; or only the depth channel (or the single channel), in out->image.
IoStatus read_exr_color(const std::string& path, LoadedImage* out);
IoStatus read_exr_depth(const std::string& path, LoadedImage* out);

// The header phase of each reader (read_image_info, read_depth_info): width, height and the
// channels the reader would return, with every check that needs no pixel.
IoStatus read_png_info(const std::string& path, ImageInfo* out);
IoStatus read_pfm_info(const std::string& path, ImageInfo* out);
IoStatus read_exr_info(const std::string& path, bool depth, ImageInfo* out);

}  // namespace reproject::io::detail
