// PFM (portable float map), written by hand: the format is a three-line text header and raw
// 32-bit floats.
//
// The header is "PF" or "Pf", width, height and scale, separated by whitespace (in practice one
// newline each). Exactly one whitespace byte follows the scale, then the pixel data: rows from the
// bottom of the image to the top, each left to right, RGB interleaved for "PF". The sign of the
// scale gives the byte order; its magnitude is a brightness hint that nobody agrees on, so it is
// neither applied nor kept.
//
// Bytes are assembled into 32-bit words explicitly, so the code does not depend on the host's byte
// order; the words are then reinterpreted as IEEE floats with memcpy, so every value, NaN payloads
// included, round-trips bit for bit.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <vector>

#include "imageio/file_util.hpp"
#include "imageio/imageio.hpp"
#include "imageio/os.hpp"

namespace reproject::io {
namespace {

using detail::failure;
using detail::quote_path;

// Long enough for any width, height or scale a sane writer produces ("-1.000000", "1e-10").
constexpr std::size_t kMaxToken = 64;

bool is_space(int c) noexcept { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

enum class TokenResult { ok, end_of_file, io_error, too_long };

// Reads one whitespace-delimited header token and consumes exactly one delimiter after it: after
// the scale that delimiter is the single byte before the pixel data, which may itself look like
// whitespace to a greedier reader.
TokenResult read_token(std::FILE* file, std::string* token) {
  token->clear();
  int c = std::fgetc(file);
  while (c != EOF && is_space(c)) c = std::fgetc(file);
  while (c != EOF && !is_space(c)) {
    if (token->size() == kMaxToken) return TokenResult::too_long;
    token->push_back(static_cast<char>(c));
    c = std::fgetc(file);
  }
  if (c == EOF) return std::ferror(file) != 0 ? TokenResult::io_error : TokenResult::end_of_file;
  return TokenResult::ok;
}

// A positive decimal integer that fits in int; false for anything else ("+3", "3x", "0", "1e3").
bool parse_dimension(const std::string& text, int* value) {
  if (text.empty() || text.size() > 9) return false;  // 9 digits: well inside int
  long long v = 0;
  for (char ch : text) {
    if (ch < '0' || ch > '9') return false;
    v = v * 10 + (ch - '0');
  }
  if (v < 1) return false;
  *value = static_cast<int>(v);
  return true;
}

bool parse_scale(const std::string& text, double* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE) return false;
  *value = v;
  return true;
}

std::uint32_t load_word(const unsigned char* bytes, ByteOrder order) noexcept {
  if (order == ByteOrder::little) {
    return static_cast<std::uint32_t>(bytes[0]) | (static_cast<std::uint32_t>(bytes[1]) << 8) |
           (static_cast<std::uint32_t>(bytes[2]) << 16) | (static_cast<std::uint32_t>(bytes[3]) << 24);
  }
  return (static_cast<std::uint32_t>(bytes[0]) << 24) | (static_cast<std::uint32_t>(bytes[1]) << 16) |
         (static_cast<std::uint32_t>(bytes[2]) << 8) | static_cast<std::uint32_t>(bytes[3]);
}

void store_word(std::uint32_t word, ByteOrder order, unsigned char* bytes) noexcept {
  for (int i = 0; i < 4; ++i) {
    const int shift = order == ByteOrder::little ? 8 * i : 8 * (3 - i);
    bytes[i] = static_cast<unsigned char>((word >> shift) & 0xFFu);
  }
}

float word_to_float(std::uint32_t word) noexcept {
  float value;
  std::memcpy(&value, &word, sizeof value);
  return value;
}

std::uint32_t float_to_word(float value) noexcept {
  std::uint32_t word;
  std::memcpy(&word, &value, sizeof word);
  return word;
}

IoStatus header_failure(TokenResult result, const std::string& path, const char* what) {
  switch (result) {
    case TokenResult::end_of_file:
      return failure(IoError::truncated, quote_path(path) + " is truncated: the file ends inside the PFM header (" +
                                             what + ")");
    case TokenResult::io_error: return detail::read_error(path, errno);
    default:
      return failure(IoError::corrupt, quote_path(path) + " is not a valid PFM file: the " + what + " is too long");
  }
}

IoStatus pixel_data_truncated(const std::string& path, unsigned long long got, unsigned long long total, int width,
                              int height, int channels) {
  return failure(IoError::truncated, quote_path(path) + " is truncated: " + std::to_string(got) + " of " +
                                         std::to_string(total) + " bytes of pixel data (" +
                                         detail::size_text(width, height) + ", " + std::to_string(channels) +
                                         (channels == 1 ? " channel)" : " channels)"));
}

struct PfmHeader {
  int width = 0;
  int height = 0;
  int channels = 0;
  ByteOrder order = ByteOrder::little;
};

// Reads and checks the header, leaving `f` at the first pixel byte. Checked besides the syntax:
// the size limit, and that the file (when it is a regular file, whose size is known) holds every
// pixel the header promises, so that no reader allocates for data the file does not have.
IoStatus read_pfm_header(std::FILE* f, const std::string& path, PfmHeader* header) {
  // Magic: 'P', then 'F' or 'f', then whitespace.
  unsigned char magic[3] = {};
  errno = 0;
  const std::size_t got = std::fread(magic, 1, sizeof magic, f);
  if (got < sizeof magic && std::ferror(f) != 0) return detail::read_error(path, errno);
  if (got == 0) return failure(IoError::not_this_format, quote_path(path) + " is not a PFM file: it is empty");
  const bool magic_ok = magic[0] == 'P' && (got < 2 || magic[1] == 'F' || magic[1] == 'f') &&
                        (got < 3 || is_space(magic[2]));
  if (!magic_ok) {
    return failure(IoError::not_this_format, quote_path(path) + " is not a PFM file (no \"PF\" or \"Pf\" header)");
  }
  if (got < sizeof magic) {
    return failure(IoError::truncated, quote_path(path) + " is truncated: the file ends inside the PFM header");
  }
  const int channels = magic[1] == 'F' ? 3 : 1;

  std::string token;
  int width = 0;
  int height = 0;
  double scale = 0.0;
  if (TokenResult r = read_token(f, &token); r != TokenResult::ok) return header_failure(r, path, "width");
  if (!parse_dimension(token, &width)) {
    return failure(IoError::corrupt, quote_path(path) + " is not a valid PFM file: bad width \"" + token + "\"");
  }
  if (TokenResult r = read_token(f, &token); r != TokenResult::ok) return header_failure(r, path, "height");
  if (!parse_dimension(token, &height)) {
    return failure(IoError::corrupt, quote_path(path) + " is not a valid PFM file: bad height \"" + token + "\"");
  }
  if (TokenResult r = read_token(f, &token); r != TokenResult::ok) return header_failure(r, path, "scale");
  // Zero or non-finite: no sign to take the byte order from.
  if (!parse_scale(token, &scale) || scale == 0.0 || !std::isfinite(scale)) {
    return failure(IoError::corrupt,
                   quote_path(path) + " is not a valid PFM file: bad scale \"" + token + "\" (nonzero, finite)");
  }

  if (static_cast<unsigned long long>(width) * static_cast<unsigned long long>(height) > detail::kMaxPixels) {
    return failure(IoError::unsupported, quote_path(path) + ": image of " + detail::size_text(width, height) +
                                             " pixels exceeds the " + std::to_string(detail::kMaxPixels) +
                                             "-pixel limit");
  }
  const unsigned long long total = 4ULL * static_cast<unsigned long long>(width) * height * channels;
  os::FileStatus info;
  const std::int64_t position = os::tell(f);
  if (os::file_status(f, &info) && info.regular && position >= 0) {
    const unsigned long long available =
        info.size > position ? static_cast<unsigned long long>(info.size - position) : 0ULL;
    if (available < total) return pixel_data_truncated(path, available, total, width, height, channels);
  }
  header->width = width;
  header->height = height;
  header->channels = channels;
  header->order = scale < 0.0 ? ByteOrder::little : ByteOrder::big;
  return {};
}

IoStatus read_pfm_file(const std::string& path, LoadedImage* out) {
  detail::InputFile file;
  if (IoStatus status = file.open(path); !status) return status;
  std::FILE* f = file.get();
  PfmHeader header;
  if (IoStatus status = read_pfm_header(f, path, &header); !status) return status;
  const int width = header.width, height = header.height, channels = header.channels;

  // Straight into the image, one row at a time: the only large allocation is the image itself.
  Image image(width, height, channels);
  if (image.empty()) return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  const std::size_t row_bytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels) * 4;
  std::vector<unsigned char> row(row_bytes);
  for (int file_row = 0; file_row < height; ++file_row) {
    errno = 0;
    const std::size_t read = std::fread(row.data(), 1, row_bytes, f);
    if (read < row_bytes) {
      if (std::ferror(f) != 0) return detail::read_error(path, errno);
      return pixel_data_truncated(path, static_cast<unsigned long long>(file_row) * row_bytes + read,
                                  static_cast<unsigned long long>(row_bytes) * height, width, height, channels);
    }
    const int y = height - 1 - file_row;  // the file starts at the bottom row
    for (int c = 0; c < channels; ++c) {
      float* target = image.mutable_plane(c).row(y);
      for (int x = 0; x < width; ++x) {
        target[x] = word_to_float(load_word(row.data() + 4 * (static_cast<std::size_t>(x) * channels + c), header.order));
      }
    }
  }
  out->image = std::move(image);
  out->bit_depth = 32;
  out->format = FileFormat::pfm;
  return {};
}

IoStatus write_pfm_file(const std::string& path, const ColorView& color, ByteOrder order) {
  if (IoStatus status = detail::check_writable(color); !status) {
    status.message = "cannot write " + quote_path(path) + ": " + status.message;
    return status;
  }
  if (color.channels != 1 && color.channels != 3) {
    return failure(IoError::unsupported, "cannot write " + quote_path(path) +
                                             ": unsupported channel layout: PFM holds 1 (Pf) or 3 (PF) channels, "
                                             "the image has " + std::to_string(color.channels));
  }
  const int width = color.width();
  const int height = color.height();
  const int channels = color.channels;

  // Encode before touching the file system, as the PNG writer does.
  char header[64];
  const int header_size = std::snprintf(header, sizeof header, "%s\n%d %d\n%s\n", channels == 3 ? "PF" : "Pf",
                                        width, height, order == ByteOrder::little ? "-1.0" : "1.0");
  const std::size_t row_bytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(channels) * 4;
  std::vector<unsigned char> bytes(row_bytes * static_cast<std::size_t>(height));
  for (int file_row = 0; file_row < height; ++file_row) {
    const int y = height - 1 - file_row;
    unsigned char* target = bytes.data() + static_cast<std::size_t>(file_row) * row_bytes;
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c) {
        store_word(float_to_word(detail::sample(color, c, x, y)), order, target);
        target += 4;
      }
    }
  }

  detail::ReplacingFile file;
  if (IoStatus status = file.create(path); !status) return status;
  errno = 0;
  if (std::fwrite(header, 1, static_cast<std::size_t>(header_size), file.get()) !=
          static_cast<std::size_t>(header_size) ||
      std::fwrite(bytes.data(), 1, bytes.size(), file.get()) != bytes.size()) {
    const int code = errno;
    return failure(IoError::write_failed, "cannot write " + quote_path(path) + ": " +
                                              (code != 0 ? detail::system_error_text(code) : "unknown error"));
  }
  return file.commit();
}

}  // namespace

IoStatus read_pfm(const std::string& path, LoadedImage* out) {
  if (out == nullptr) return failure(IoError::invalid_argument, "read_pfm: null output");
  *out = LoadedImage{};
  try {
    IoStatus status = read_pfm_file(path, out);
    if (!status) *out = LoadedImage{};
    return status;
  } catch (const std::bad_alloc&) {
    *out = LoadedImage{};
    return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  } catch (const std::exception& error) {
    *out = LoadedImage{};
    return failure(IoError::read_failed, error.what());
  }
}

namespace detail {

IoStatus read_pfm_info(const std::string& path, ImageInfo* out) {
  InputFile file;
  if (IoStatus status = file.open(path); !status) return status;
  PfmHeader header;
  if (IoStatus status = read_pfm_header(file.get(), path, &header); !status) return status;
  *out = ImageInfo{header.width, header.height, header.channels, FileFormat::pfm, 32};
  return {};
}

}  // namespace detail

IoStatus write_pfm(const std::string& path, const ColorView& color, ByteOrder order) {
  try {
    return write_pfm_file(path, color, order);
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory writing " + quote_path(path));
  } catch (const std::exception& error) {
    return failure(IoError::write_failed, error.what());
  }
}

}  // namespace reproject::io
