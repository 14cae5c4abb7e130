// Raw buffers: an engine's bytes with no header (imageio.hpp). The size is all a reader can
// check, so it is checked exactly, before anything is allocated.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <utility>

#include "imageio/file_util.hpp"
#include "imageio/imageio.hpp"
#include "imageio/os.hpp"

namespace reproject::io {
namespace {

using detail::failure;
using detail::quote_path;

bool little_endian_machine() noexcept {
  const std::uint16_t one = 1;
  std::uint8_t first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// Files hold little-endian words; memory holds the machine's. A no-op on little-endian machines.
void to_or_from_little_endian(std::uint8_t* data, std::size_t bytes, int word_bytes) noexcept {
  if (word_bytes <= 1 || little_endian_machine()) return;
  for (std::size_t i = 0; i + static_cast<std::size_t>(word_bytes) <= bytes; i += static_cast<std::size_t>(word_bytes)) {
    for (int a = 0, b = word_bytes - 1; a < b; ++a, --b) std::swap(data[i + a], data[i + b]);
  }
}

IoStatus bad_word_size(int word_bytes) {
  return failure(IoError::invalid_argument, "raw words of " + std::to_string(word_bytes) + " bytes (1, 2 or 4)");
}

IoStatus check_size(const std::string& path, std::FILE* file, std::uint64_t bytes, const std::string& what) {
  os::FileStatus info;
  if (!os::file_status(file, &info)) return detail::read_error(path, errno);
  if (info.directory) return detail::read_error(path, EISDIR);
  if (!info.regular) {
    return failure(IoError::unsupported, quote_path(path) + " is not a regular file: a raw buffer's size cannot be checked");
  }
  const std::uint64_t size = static_cast<std::uint64_t>(info.size);
  if (size != bytes) {
    return failure(IoError::size_mismatch, quote_path(path) + " holds " + std::to_string(size) + " bytes, but " + what +
                                               " is " + std::to_string(bytes) + " bytes");
  }
  return {};
}

}  // namespace

IoStatus check_raw_size(const std::string& path, std::uint64_t bytes, const std::string& what) {
  try {
    detail::InputFile file;
    if (IoStatus status = file.open(path); !status) return status;
    return check_size(path, file.get(), bytes, what);
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  }
}

IoStatus read_raw(const std::string& path, std::uint64_t bytes, int word_bytes, const std::string& what,
                  std::vector<std::uint8_t>* out) {
  if (out == nullptr) return failure(IoError::invalid_argument, "read_raw: null output");
  out->clear();
  if (word_bytes != 1 && word_bytes != 2 && word_bytes != 4) return bad_word_size(word_bytes);
  try {
    detail::InputFile file;
    if (IoStatus status = file.open(path); !status) return status;
    if (IoStatus status = check_size(path, file.get(), bytes, what); !status) return status;
    std::vector<std::uint8_t> data(static_cast<std::size_t>(bytes));
    errno = 0;
    const std::size_t got = std::fread(data.data(), 1, data.size(), file.get());
    if (got != data.size()) {
      if (std::ferror(file.get()) != 0) return detail::read_error(path, errno);
      // The file shrank between the size check and the read.
      return failure(IoError::truncated, quote_path(path) + " is truncated: " + std::to_string(got) + " of " +
                                             std::to_string(bytes) + " bytes");
    }
    to_or_from_little_endian(data.data(), data.size(), word_bytes);
    *out = std::move(data);
    return {};
  } catch (const std::bad_alloc&) {
    out->clear();
    return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  }
}

IoStatus write_raw(const std::string& path, const std::uint8_t* data, std::size_t row_bytes, int height,
                   std::ptrdiff_t stride, int word_bytes) {
  if (word_bytes != 1 && word_bytes != 2 && word_bytes != 4) return bad_word_size(word_bytes);
  if (data == nullptr || row_bytes == 0 || height < 1 || stride < static_cast<std::ptrdiff_t>(row_bytes)) {
    return failure(IoError::invalid_argument, "cannot write " + quote_path(path) + ": an empty or inconsistent buffer");
  }
  try {
    detail::ReplacingFile file;
    if (IoStatus status = file.create(path); !status) return status;
    std::vector<std::uint8_t> row(data, data + row_bytes);
    for (int y = 0; y < height; ++y) {
      std::memcpy(row.data(), data + static_cast<std::ptrdiff_t>(y) * stride, row_bytes);
      to_or_from_little_endian(row.data(), row.size(), word_bytes);
      errno = 0;
      if (std::fwrite(row.data(), 1, row.size(), file.get()) != row.size()) {
        const int code = errno;
        return failure(IoError::write_failed, "cannot write " + quote_path(path) + ": " +
                                                  (code != 0 ? detail::system_error_text(code) : "unknown error"));
      }
    }
    return file.commit();
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory writing " + quote_path(path));
  }
}

}  // namespace reproject::io
