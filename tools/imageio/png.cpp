// PNG through libpng.
//
// libpng reports errors by calling our error callback, which must not return: it longjmps back to
// the setjmp in the function that called into libpng. A longjmp that skips a C++ destructor is
// undefined behaviour, so the code is split in two layers:
//  * "guarded" functions (read_header, read_rows, write_all) hold the setjmp and call libpng; they
//    have only trivially destructible locals and return false when libpng failed;
//  * the ordinary C++ functions around them own every resource (file, libpng structs, buffers)
//    through destructors and turn the failure recorded in a PngSession into an IoStatus.
// The callbacks themselves (I/O, errors) only touch the plain PngSession, never throw and never
// hold objects with destructors.
#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <exception>
#include <new>
#include <vector>

#include "imageio/file_util.hpp"
#include "imageio/imageio.hpp"

namespace reproject::io {
namespace {

using detail::failure;
using detail::quote_path;

constexpr std::size_t kSignatureSize = 8;
// Larger images than detail::kMaxPixels are refused; libpng's own limits (1,000,000 rows and
// columns) apply as well.
using detail::kMaxPixels;

// What the callbacks know and report: plain data only (see the top of the file).
struct PngSession {
  std::FILE* file = nullptr;
  IoError error = IoError::none;
  int system_error = 0;     // errno of a failed read or write
  char libpng_message[192] = {};
};

void record(PngSession* session, IoError error, const char* text) noexcept {
  if (session->error != IoError::none) return;  // the first cause is the most specific one
  session->error = error;
  std::snprintf(session->libpng_message, sizeof session->libpng_message, "%s", text);
}

[[noreturn]] void on_png_error(png_structp png, png_const_charp text) {
  record(static_cast<PngSession*>(png_get_error_ptr(png)), IoError::corrupt,
         text != nullptr ? text : "unknown libpng error");
  png_longjmp(png, 1);
}

// Warnings concern ancillary data (profiles, text, ...) that we ignore anyway.
void on_png_warning(png_structp, png_const_charp) {}

void read_from_file(png_structp png, png_bytep data, std::size_t length) {
  auto* session = static_cast<PngSession*>(png_get_io_ptr(png));
  if (std::fread(data, 1, length, session->file) == length) return;
  if (std::ferror(session->file) != 0) {
    session->system_error = errno;
    record(session, IoError::read_failed, "I/O error");
  } else {
    record(session, IoError::truncated, "unexpected end of file");
  }
  png_error(png, "read failed");
}

void write_to_file(png_structp png, png_bytep data, std::size_t length) {
  auto* session = static_cast<PngSession*>(png_get_io_ptr(png));
  errno = 0;
  if (std::fwrite(data, 1, length, session->file) == length) return;
  session->system_error = errno;
  record(session, IoError::write_failed, "write failed");
  png_error(png, "write failed");
}

// Errors of the final flush surface when the file is committed.
void flush_file(png_structp png) { std::fflush(static_cast<PngSession*>(png_get_io_ptr(png))->file); }

IoStatus session_failure(const PngSession& session, const std::string& path) {
  const std::string system_text =
      session.system_error != 0 ? detail::system_error_text(session.system_error) : "unknown error";
  switch (session.error) {
    case IoError::read_failed: return failure(session.error, "cannot read " + quote_path(path) + ": " + system_text);
    case IoError::truncated:
      return failure(session.error, quote_path(path) + " is truncated: the file ends before the PNG does");
    case IoError::write_failed: return failure(session.error, "cannot write " + quote_path(path) + ": " + system_text);
    case IoError::out_of_memory: return failure(session.error, "out of memory reading " + quote_path(path));
    default:
      return failure(IoError::corrupt, quote_path(path) + " is a damaged PNG (libpng: " + session.libpng_message + ")");
  }
}

// ---- reading ----

// The decoded layout after our transforms: always 8 or 16 bits, 1..4 channels.
struct PngLayout {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int channels = 0;
  int bit_depth = 0;
  std::size_t row_bytes = 0;
};

// Guarded (see the top of the file). Reads the header and asks libpng to expand every colour
// type to grey, grey + alpha, RGB or RGBA at 8 or 16 bits, keeping the stored values.
bool read_header(png_structp png, png_infop info, PngLayout* layout) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_set_sig_bytes(png, static_cast<int>(kSignatureSize));
  png_read_info(png, info);
  const int color_type = png_get_color_type(png, info);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color_type == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(png, info) < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS) != 0) png_set_tRNS_to_alpha(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  layout->width = png_get_image_width(png, info);
  layout->height = png_get_image_height(png, info);
  layout->channels = png_get_channels(png, info);
  layout->bit_depth = png_get_bit_depth(png, info);
  layout->row_bytes = png_get_rowbytes(png, info);
  return true;
}

// Guarded. Reads the pixels, then the chunks up to IEND (so truncation and CRC errors after the
// image data are reported too).
bool read_rows(png_structp png, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_read_image(png, rows);
  png_read_end(png, nullptr);
  return true;
}

class ReadStruct {
 public:
  explicit ReadStruct(PngSession* session) noexcept {
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, session, on_png_error, on_png_warning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
  }
  ~ReadStruct() {
    if (png_ != nullptr) png_destroy_read_struct(&png_, info_ != nullptr ? &info_ : nullptr, nullptr);
  }
  ReadStruct(const ReadStruct&) = delete;
  ReadStruct& operator=(const ReadStruct&) = delete;
  bool ok() const noexcept { return png_ != nullptr && info_ != nullptr; }
  png_structp png() const noexcept { return png_; }
  png_infop info() const noexcept { return info_; }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

IoStatus read_png_file(const std::string& path, LoadedImage* out) {
  detail::InputFile file;
  if (IoStatus status = file.open(path); !status) return status;

  png_byte signature[kSignatureSize] = {};
  errno = 0;
  const std::size_t got = std::fread(signature, 1, kSignatureSize, file.get());
  if (got < kSignatureSize && std::ferror(file.get()) != 0) {
    const int code = errno;
    return failure(IoError::read_failed, "cannot read " + quote_path(path) + ": " +
                                             (code != 0 ? detail::system_error_text(code) : "unknown error"));
  }
  if (got == 0) return failure(IoError::not_this_format, quote_path(path) + " is not a PNG file: it is empty");
  if (png_sig_cmp(signature, 0, got) != 0) {
    return failure(IoError::not_this_format, quote_path(path) + " is not a PNG file (no PNG signature)");
  }
  if (got < kSignatureSize) {
    return failure(IoError::truncated, quote_path(path) + " is truncated: the file ends inside the PNG signature");
  }

  PngSession session;
  session.file = file.get();
  ReadStruct reader(&session);
  if (!reader.ok()) return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  png_set_read_fn(reader.png(), &session, read_from_file);

  PngLayout layout;
  if (!read_header(reader.png(), reader.info(), &layout)) return session_failure(session, path);
  if ((layout.bit_depth != 8 && layout.bit_depth != 16) || layout.channels < 1 || layout.channels > 4) {
    return failure(IoError::unsupported, quote_path(path) + ": unsupported PNG layout after expansion (" +
                                             std::to_string(layout.channels) + " channels of " +
                                             std::to_string(layout.bit_depth) + " bits)");
  }
  if (static_cast<unsigned long long>(layout.width) * layout.height > kMaxPixels) {
    return failure(IoError::unsupported, quote_path(path) + ": image of " + std::to_string(layout.width) + "x" +
                                             std::to_string(layout.height) + " pixels exceeds the " +
                                             std::to_string(kMaxPixels) + "-pixel limit");
  }
  const int bytes_per_sample = layout.bit_depth / 8;
  if (layout.row_bytes < static_cast<std::size_t>(layout.width) * layout.channels * bytes_per_sample) {
    return failure(IoError::unsupported, quote_path(path) + ": unexpected row size from libpng");
  }

  std::vector<png_byte> pixels(layout.row_bytes * layout.height);
  std::vector<png_bytep> rows(layout.height);
  for (png_uint_32 y = 0; y < layout.height; ++y) rows[y] = pixels.data() + y * layout.row_bytes;
  if (!read_rows(reader.png(), rows.data())) return session_failure(session, path);

  const int width = static_cast<int>(layout.width);
  const int height = static_cast<int>(layout.height);
  Image image(width, height, layout.channels);
  if (image.empty()) return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  for (int c = 0; c < layout.channels; ++c) {
    const MutableFloatPlane plane = image.mutable_plane(c);
    for (int y = 0; y < height; ++y) {
      const png_byte* source = rows[y];
      float* target = plane.row(y);
      if (bytes_per_sample == 1) {
        for (int x = 0; x < width; ++x) target[x] = static_cast<float>(source[x * layout.channels + c]);
      } else {
        for (int x = 0; x < width; ++x) {
          const png_byte* sample = source + 2 * (x * layout.channels + c);  // big-endian in the file
          target[x] = static_cast<float>((static_cast<unsigned>(sample[0]) << 8) | sample[1]);
        }
      }
    }
  }
  out->image = std::move(image);
  out->bit_depth = layout.bit_depth;
  out->format = FileFormat::png;
  return {};
}

// ---- writing ----

struct PngHeader {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int bit_depth = 0;
  int color_type = 0;
};

// Guarded. Writes the whole file through the session's write callback.
bool write_all(png_structp png, png_infop info, const PngHeader* header, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_set_IHDR(png, info, header->width, header->height, header->bit_depth, header->color_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

class WriteStruct {
 public:
  explicit WriteStruct(PngSession* session) noexcept {
    png_ = png_create_write_struct(PNG_LIBPNG_VER_STRING, session, on_png_error, on_png_warning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
  }
  ~WriteStruct() {
    if (png_ != nullptr) png_destroy_write_struct(&png_, info_ != nullptr ? &info_ : nullptr);
  }
  WriteStruct(const WriteStruct&) = delete;
  WriteStruct& operator=(const WriteStruct&) = delete;
  bool ok() const noexcept { return png_ != nullptr && info_ != nullptr; }
  png_structp png() const noexcept { return png_; }
  png_infop info() const noexcept { return info_; }

 private:
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

int color_type_for(int channels) noexcept {
  switch (channels) {
    case 1: return PNG_COLOR_TYPE_GRAY;
    case 2: return PNG_COLOR_TYPE_GRAY_ALPHA;
    case 3: return PNG_COLOR_TYPE_RGB;
    default: return PNG_COLOR_TYPE_RGB_ALPHA;
  }
}

IoStatus write_png_file(const std::string& path, const ColorView& color, int bit_depth) {
  if (bit_depth != 8 && bit_depth != 16) {
    return failure(IoError::invalid_argument,
                   "cannot write " + quote_path(path) + ": PNG bit depth " + std::to_string(bit_depth) + " (8 or 16)");
  }
  if (IoStatus status = detail::check_writable(color); !status) {
    status.message = "cannot write " + quote_path(path) + ": " + status.message;
    return status;
  }
  const int width = color.width();
  const int height = color.height();
  const int channels = color.channels;
  const int bytes_per_sample = bit_depth / 8;
  const std::uint32_t max_value = bit_depth == 8 ? 255u : 65535u;

  // Quantise before touching the file system: nothing below can fail for the pixels' sake.
  const std::size_t row_bytes = static_cast<std::size_t>(width) * channels * bytes_per_sample;
  std::vector<png_byte> pixels(row_bytes * static_cast<std::size_t>(height));
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    png_byte* target = pixels.data() + static_cast<std::size_t>(y) * row_bytes;
    rows[static_cast<std::size_t>(y)] = target;
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c) {
        const std::uint32_t value = detail::quantise(detail::sample(color, c, x, y), max_value);
        if (bytes_per_sample == 1) {
          *target++ = static_cast<png_byte>(value);
        } else {
          *target++ = static_cast<png_byte>(value >> 8);  // PNG stores 16-bit samples big-endian
          *target++ = static_cast<png_byte>(value & 0xFFu);
        }
      }
    }
  }

  detail::ReplacingFile file;
  if (IoStatus status = file.create(path); !status) return status;
  PngSession session;
  session.file = file.get();
  WriteStruct writer(&session);
  if (!writer.ok()) return failure(IoError::out_of_memory, "out of memory writing " + quote_path(path));
  png_set_write_fn(writer.png(), &session, write_to_file, flush_file);

  PngHeader header;
  header.width = static_cast<png_uint_32>(width);
  header.height = static_cast<png_uint_32>(height);
  header.bit_depth = bit_depth;
  header.color_type = color_type_for(channels);
  if (!write_all(writer.png(), writer.info(), &header, rows.data())) {
    IoStatus status = session_failure(session, path);
    if (status.error == IoError::corrupt) {  // libpng refused what we gave it
      status = failure(IoError::write_failed, "cannot write " + quote_path(path) + ": libpng: " + session.libpng_message);
    }
    return status;  // `file` removes the temporary file
  }
  return file.commit();
}

}  // namespace

IoStatus read_png(const std::string& path, LoadedImage* out) {
  if (out == nullptr) return failure(IoError::invalid_argument, "read_png: null output");
  *out = LoadedImage{};
  try {
    return read_png_file(path, out);
  } catch (const std::bad_alloc&) {
    *out = LoadedImage{};
    return failure(IoError::out_of_memory, "out of memory");
  } catch (const std::exception& error) {
    *out = LoadedImage{};
    return failure(IoError::read_failed, error.what());
  }
}

IoStatus write_png(const std::string& path, const ColorView& color, int bit_depth) {
  try {
    return write_png_file(path, color, bit_depth);
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory");
  } catch (const std::exception& error) {
    return failure(IoError::write_failed, error.what());
  }
}

}  // namespace reproject::io
