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
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <vector>

#include "imageio/file_util.hpp"
#include "imageio/imageio.hpp"
#include "imageio/os.hpp"

namespace reproject::io {
namespace {

using detail::failure;
using detail::quote_path;

constexpr std::size_t kSignatureSize = 8;
// Larger images than detail::kMaxPixels are refused.
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
  // libpng's own allocations fail with "Out of memory" (or "... Out of Memory"): not the file's fault.
  const bool memory = text != nullptr && (std::strstr(text, "ut of memory") != nullptr || std::strstr(text, "ut of Memory") != nullptr);
  record(static_cast<PngSession*>(png_get_error_ptr(png)), memory ? IoError::out_of_memory : IoError::corrupt,
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

// libpng refuses images wider or taller than its default user limits (1,000,000): the limits that
// matter are ours (kMaxPixels) and the library's (2^22 columns), so both are raised to PNG's own.
constexpr png_uint_32 kPngMaxDimension = 0x7fffffffu;

// deflate expands its input at most 1032:1 (RFC 1951's longest match per shortest code); a file
// whose every byte were image data could not inflate to more. The slack covers small streams.
constexpr unsigned long long kDeflateMaxRatio = 1032;
constexpr unsigned long long kDeflateSlack = 65536;

// The decoded layout after our transforms: always 8 or 16 bits, 1..4 channels.
struct PngLayout {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int channels = 0;
  int bit_depth = 0;
  std::size_t row_bytes = 0;
  std::size_t file_row_bytes = 0;  // one row as stored (before our transforms), filter byte excluded
  bool interlaced = false;
};

// Guarded (see the top of the file). Reads the header and asks libpng to expand every colour
// type to grey, grey + alpha, RGB or RGBA at 8 or 16 bits, keeping the stored values.
bool read_header(png_structp png, png_infop info, PngLayout* layout) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_set_sig_bytes(png, static_cast<int>(kSignatureSize));
  png_set_user_limits(png, kPngMaxDimension, kPngMaxDimension);
  png_read_info(png, info);
  layout->file_row_bytes = png_get_rowbytes(png, info);
  layout->interlaced = png_get_interlace_type(png, info) != PNG_INTERLACE_NONE;
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

// One decoded row (8- or 16-bit samples, interleaved) into row y of the image's planes.
void convert_row(const png_byte* source, const PngLayout& layout, Image* image, int y) noexcept {
  const int width = static_cast<int>(layout.width);
  for (int c = 0; c < layout.channels; ++c) {
    float* target = image->mutable_plane(c).row(y);
    if (layout.bit_depth == 8) {
      for (int x = 0; x < width; ++x) target[x] = static_cast<float>(source[x * layout.channels + c]);
    } else {
      for (int x = 0; x < width; ++x) {
        const png_byte* sample = source + 2 * (x * layout.channels + c);  // big-endian in the file
        target[x] = static_cast<float>((static_cast<unsigned>(sample[0]) << 8) | sample[1]);
      }
    }
  }
}

// One decoded 8-bit row into row y of packed RGBA8 bytes: grey repeated into R, G and B, a
// missing alpha opaque.
void pack_row(const png_byte* source, const PngLayout& layout, PackedColor* packed, int y) noexcept {
  std::uint8_t* target = packed->bytes.data() + static_cast<std::ptrdiff_t>(y) * packed->stride();
  const int width = static_cast<int>(layout.width);
  for (int x = 0; x < width; ++x, target += 4) {
    const png_byte* pixel = source + static_cast<std::ptrdiff_t>(x) * layout.channels;
    const bool grey = layout.channels <= 2;
    target[0] = pixel[0];
    target[1] = grey ? pixel[0] : pixel[1];
    target[2] = grey ? pixel[0] : pixel[2];
    target[3] = layout.channels == 2 ? pixel[1] : layout.channels == 4 ? pixel[3] : 255;
  }
}

// Where decoded rows go: planar floats (`Image`) or packed bytes (`PackedColor`).
using RowSink = void (*)(const png_byte* source, const PngLayout& layout, void* target, int y);
void to_floats(const png_byte* source, const PngLayout& layout, void* target, int y) {
  convert_row(source, layout, static_cast<Image*>(target), y);
}
void to_packed(const png_byte* source, const PngLayout& layout, void* target, int y) {
  pack_row(source, layout, static_cast<PackedColor*>(target), y);
}

// Guarded. A non-interlaced image, decoded one row at a time straight into `target`, then the
// chunks up to IEND (so truncation and CRC errors after the image data are reported too).
bool read_rows_into(png_structp png, png_bytep row, const PngLayout* layout, RowSink sink, void* target) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  for (png_uint_32 y = 0; y < layout->height; ++y) {
    png_read_row(png, row, nullptr);
    sink(row, *layout, target, static_cast<int>(y));
  }
  png_read_end(png, nullptr);
  return true;
}

// Guarded. An interlaced image: every pass refines every row, so the whole image is decoded at once.
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

// A PNG file whose header has been read and checked (open), ready to decode (read). The header
// checks come first so that nothing large is allocated for a file that cannot hold its image.
class PngReader {
 public:
  IoStatus open(const std::string& path);
  const PngLayout& layout() const noexcept { return layout_; }
  IoStatus read(LoadedImage* out);
  IoStatus read_packed(ColorFormat format, PackedColor* out);

 private:
  // Decodes every row into `target` through `sink`.
  IoStatus decode(RowSink sink, void* target);

  std::string path_;
  detail::InputFile file_;
  PngSession session_;
  std::unique_ptr<ReadStruct> reader_;
  PngLayout layout_;
};

IoStatus PngReader::open(const std::string& path) {
  path_ = path;
  if (IoStatus status = file_.open(path); !status) return status;

  png_byte signature[kSignatureSize] = {};
  errno = 0;
  const std::size_t got = std::fread(signature, 1, kSignatureSize, file_.get());
  if (got < kSignatureSize && std::ferror(file_.get()) != 0) return detail::read_error(path, errno);
  if (got == 0) return failure(IoError::not_this_format, quote_path(path) + " is not a PNG file: it is empty");
  if (png_sig_cmp(signature, 0, got) != 0) {
    return failure(IoError::not_this_format, quote_path(path) + " is not a PNG file (no PNG signature)");
  }
  if (got < kSignatureSize) {
    return failure(IoError::truncated, quote_path(path) + " is truncated: the file ends inside the PNG signature");
  }

  session_.file = file_.get();
  reader_ = std::make_unique<ReadStruct>(&session_);
  if (!reader_->ok()) return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  png_set_read_fn(reader_->png(), &session_, read_from_file);

  if (!read_header(reader_->png(), reader_->info(), &layout_)) return session_failure(session_, path);
  if ((layout_.bit_depth != 8 && layout_.bit_depth != 16) || layout_.channels < 1 || layout_.channels > 4) {
    return failure(IoError::unsupported, quote_path(path) + ": unsupported PNG layout after expansion (" +
                                             std::to_string(layout_.channels) + " channels of " +
                                             std::to_string(layout_.bit_depth) + " bits)");
  }
  if (static_cast<unsigned long long>(layout_.width) * layout_.height > kMaxPixels) {
    return failure(IoError::unsupported, quote_path(path) + ": image of " + std::to_string(layout_.width) + "x" +
                                             std::to_string(layout_.height) + " pixels exceeds the " +
                                             std::to_string(kMaxPixels) + "-pixel limit");
  }
  if (layout_.row_bytes < static_cast<std::size_t>(layout_.width) * layout_.channels * (layout_.bit_depth / 8)) {
    return failure(IoError::unsupported, quote_path(path) + ": unexpected row size from libpng");
  }
  os::FileStatus info;
  if (os::file_status(file_.get(), &info) && info.regular) {
    const unsigned long long raw = static_cast<unsigned long long>(layout_.height) * (layout_.file_row_bytes + 1);
    const unsigned long long size = static_cast<unsigned long long>(info.size);
    if (size * kDeflateMaxRatio + kDeflateSlack < raw) {
      return failure(IoError::truncated, quote_path(path) + " is truncated: a " + std::to_string(layout_.width) + "x" +
                                             std::to_string(layout_.height) + " PNG inflates to " +
                                             std::to_string(raw) + " bytes, more than a file of " +
                                             std::to_string(size) + " bytes can hold");
    }
  }
  return {};
}

IoStatus PngReader::decode(RowSink sink, void* target) {
  if (!layout_.interlaced) {
    std::vector<png_byte> row(layout_.row_bytes);
    if (!read_rows_into(reader_->png(), row.data(), &layout_, sink, target)) return session_failure(session_, path_);
  } else {
    std::vector<png_byte> pixels(layout_.row_bytes * layout_.height);
    std::vector<png_bytep> rows(layout_.height);
    for (png_uint_32 y = 0; y < layout_.height; ++y) rows[y] = pixels.data() + y * layout_.row_bytes;
    if (!read_rows(reader_->png(), rows.data())) return session_failure(session_, path_);
    for (png_uint_32 y = 0; y < layout_.height; ++y) sink(rows[y], layout_, target, static_cast<int>(y));
  }
  return {};
}

IoStatus PngReader::read_packed(ColorFormat format, PackedColor* out) {
  if (layout_.bit_depth != 8) {
    return failure(IoError::unsupported, quote_path(path_) + ": a " + std::to_string(layout_.bit_depth) +
                                             "-bit PNG is not 8-bit RGBA (read it as floats)");
  }
  PackedColor packed;
  packed.width = static_cast<int>(layout_.width);
  packed.height = static_cast<int>(layout_.height);
  packed.channels = layout_.channels;
  packed.format = format;
  packed.bytes.resize(static_cast<std::size_t>(packed.stride()) * layout_.height);
  if (IoStatus status = decode(to_packed, &packed); !status) return status;
  *out = std::move(packed);
  return {};
}

IoStatus PngReader::read(LoadedImage* out) {
  const int width = static_cast<int>(layout_.width);
  const int height = static_cast<int>(layout_.height);
  Image image(width, height, layout_.channels);
  if (image.empty()) return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path_));
  if (IoStatus status = decode(to_floats, &image); !status) return status;
  out->image = std::move(image);
  out->bit_depth = layout_.bit_depth;
  out->format = FileFormat::png;
  return {};
}

IoStatus read_png_file(const std::string& path, LoadedImage* out) {
  PngReader reader;
  if (IoStatus status = reader.open(path); !status) return status;
  return reader.read(out);
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
  png_set_user_limits(png, kPngMaxDimension, kPngMaxDimension);
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

IoStatus write_png_rows(const std::string& path, int width, int height, int channels, int bit_depth, png_bytepp rows);

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

  return write_png_rows(path, width, height, channels, bit_depth, rows.data());
}

// Writes the quantised rows (each width * channels samples of bit_depth bits, as PNG stores them).
IoStatus write_png_rows(const std::string& path, int width, int height, int channels, int bit_depth, png_bytepp rows) {
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
  if (!write_all(writer.png(), writer.info(), &header, rows)) {
    IoStatus status = session_failure(session, path);
    if (status.error == IoError::corrupt) {  // libpng refused what we gave it
      status = failure(IoError::write_failed, "cannot write " + quote_path(path) + ": libpng: " + session.libpng_message);
    }
    return status;  // `file` removes the temporary file
  }
  return file.commit();
}

// The first `channels` of each RGBA8 pixel, in PNG's order for that colour type.
IoStatus write_png_packed_file(const std::string& path, const ColorView& packed, int channels) {
  if (IoStatus status = detail::check_packed(packed, channels, ColorFormat::rgba8); !status) {
    status.message = "cannot write " + quote_path(path) + ": " + status.message;
    return status;
  }
  const int width = packed.width();
  const int height = packed.height();
  const std::size_t row_bytes = static_cast<std::size_t>(width) * channels;
  std::vector<png_byte> pixels(row_bytes * static_cast<std::size_t>(height));
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  // Grey is R (the reader repeats it into R, G and B); grey + alpha is R and A.
  static const int kPick[5][4] = {{}, {0}, {0, 3}, {0, 1, 2}, {0, 1, 2, 3}};
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* source = packed.pixels.row(y);
    png_byte* target = pixels.data() + static_cast<std::size_t>(y) * row_bytes;
    rows[static_cast<std::size_t>(y)] = target;
    for (int x = 0; x < width; ++x, source += 4) {
      for (int c = 0; c < channels; ++c) *target++ = source[kPick[channels][c]];
    }
  }
  return write_png_rows(path, width, height, channels, 8, rows.data());
}

}  // namespace

IoStatus read_png_packed(const std::string& path, ColorFormat format, PackedColor* out) {
  if (out == nullptr) return failure(IoError::invalid_argument, "read_png_packed: null output");
  *out = PackedColor{};
  if (format != ColorFormat::rgba8 && format != ColorFormat::rgba8_srgb) {
    return failure(IoError::invalid_argument, "read_png_packed: " + quote_path(path) + " read as " + to_string(format) +
                                                  " (rgba8 or rgba8_srgb)");
  }
  try {
    PngReader reader;
    if (IoStatus status = reader.open(path); !status) return status;
    return reader.read_packed(format, out);
  } catch (const std::bad_alloc&) {
    *out = PackedColor{};
    return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  } catch (const std::exception& error) {
    *out = PackedColor{};
    return failure(IoError::read_failed, error.what());
  }
}

IoStatus write_png_packed(const std::string& path, const ColorView& packed, int channels) {
  try {
    return write_png_packed_file(path, packed, channels);
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory writing " + quote_path(path));
  } catch (const std::exception& error) {
    return failure(IoError::write_failed, error.what());
  }
}

IoStatus read_png(const std::string& path, LoadedImage* out) {
  if (out == nullptr) return failure(IoError::invalid_argument, "read_png: null output");
  *out = LoadedImage{};
  try {
    return read_png_file(path, out);
  } catch (const std::bad_alloc&) {
    *out = LoadedImage{};
    return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  } catch (const std::exception& error) {
    *out = LoadedImage{};
    return failure(IoError::read_failed, error.what());
  }
}

namespace detail {

IoStatus read_png_info(const std::string& path, ImageInfo* out) {
  PngReader reader;
  if (IoStatus status = reader.open(path); !status) return status;
  const PngLayout& layout = reader.layout();
  *out = ImageInfo{static_cast<int>(layout.width), static_cast<int>(layout.height), layout.channels, FileFormat::png,
                   layout.bit_depth};
  return {};
}

}  // namespace detail

IoStatus write_png(const std::string& path, const ColorView& color, int bit_depth) {
  try {
    return write_png_file(path, color, bit_depth);
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory writing " + quote_path(path));
  } catch (const std::exception& error) {
    return failure(IoError::write_failed, error.what());
  }
}

}  // namespace reproject::io
