#include "imageio/file_util.hpp"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>
#if defined(_WIN32)
#include <mutex>
#endif

#include "imageio/os.hpp"

namespace reproject::io {

const char* to_string(IoError error) noexcept {
  switch (error) {
    case IoError::none: return "none";
    case IoError::invalid_argument: return "invalid_argument";
    case IoError::open_failed: return "open_failed";
    case IoError::read_failed: return "read_failed";
    case IoError::not_this_format: return "not_this_format";
    case IoError::truncated: return "truncated";
    case IoError::corrupt: return "corrupt";
    case IoError::unsupported: return "unsupported";
    case IoError::out_of_memory: return "out_of_memory";
    case IoError::write_failed: return "write_failed";
    case IoError::size_mismatch: return "size_mismatch";
  }
  return "unknown";
}

// ---- the registry of temporary files ----
//
// A fixed table of malloc'd C strings, each slot an atomic pointer: a signal handler may read it
// at any moment, so nothing here locks, and a name is taken out of its slot before it is freed.
namespace {
constexpr int kTemporarySlots = 256;
std::atomic<char*> temporary_slots[kTemporarySlots];
}  // namespace

void track_temporary(const std::string& path) {
  char* copy = strdup(path.c_str());
  if (copy == nullptr) return;  // untracked: only a signal's clean-up would miss it
  for (std::atomic<char*>& slot : temporary_slots) {
    char* expected = nullptr;
    if (slot.compare_exchange_strong(expected, copy)) return;
  }
  std::free(copy);
}

void untrack_temporary(const std::string& path) {
  for (std::atomic<char*>& slot : temporary_slots) {
    char* name = slot.load();
    if (name != nullptr && path == name && slot.compare_exchange_strong(name, nullptr)) {
      std::free(name);
      return;
    }
  }
}

#if defined(_WIN32)
namespace {
std::mutex creation;    // create_temporary against the clean-up
bool cleaned = false;   // remove_temporary_files has run: create nothing more
}  // namespace
#endif

std::FILE* create_temporary(const std::string& path, bool* exists, std::string* error) {
#if defined(_WIN32)
  std::lock_guard<std::mutex> hold(creation);
  if (cleaned) {
    *exists = false;
    *error = "the program is being interrupted";
    return nullptr;
  }
#endif
  // Tracked before it exists: a signal between the creation and the tracking would otherwise
  // leave the file behind (CI once caught one). The name carries our pid, so what the handler
  // might unlink in that window is never another process's file.
  track_temporary(path);
  std::FILE* file = os::create_new(path, exists, error);
  if (file == nullptr) untrack_temporary(path);
  return file;
}

void remove_temporary_files() noexcept {
#if defined(_WIN32)
  // Another thread than the program's (the console handler): it waits for a creation under way.
  std::lock_guard<std::mutex> hold(creation);
  cleaned = true;
#endif
  // Files first; then directories (rmdir fails on a file and on a non-empty directory), newest
  // first, so that a nest of directories created one inside the other goes from the inside.
  for (std::atomic<char*>& slot : temporary_slots) {
    if (const char* name = slot.load()) os::remove_file(name);
  }
  for (int i = kTemporarySlots - 1; i >= 0; --i) {
    if (const char* name = temporary_slots[i].load()) os::remove_directory(name);
  }
}

namespace detail {

IoStatus read_error(const std::string& path, int code) {
  return failure(IoError::read_failed,
                 "cannot read " + quote_path(path) + ": " + (code != 0 ? system_error_text(code) : "unknown error"));
}

std::string size_text(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

IoStatus failure(IoError error, std::string message) {
  IoStatus status;
  status.error = error;
  status.message = std::move(message);
  return status;
}

std::string quote_path(const std::string& path) { return "'" + path + "'"; }

std::string system_error_text(int code) { return std::strerror(code); }

InputFile::~InputFile() {
  if (file_ != nullptr) std::fclose(file_);
}

IoStatus refuse_standard_input(const std::string& path) {
  if (path != "-") return {};
  return failure(IoError::unsupported, "'-' is not a regular file (standard input is not read): inputs are read from "
                                       "regular files only; ./- names a file called -");
}

IoStatus InputFile::open(const std::string& path) {
  // Only regular files are read: their size is known before a byte is read (the readers check
  // headers against it), and reading one never blocks. os::open_input learns what the path is
  // before any read, without blocking on a FIFO or a pipe (docs/CLI.md).
  if (IoStatus status = refuse_standard_input(path); !status) return status;
  os::Input in = os::open_input(path);
  if (in.kind == os::Kind::missing) return failure(IoError::open_failed, "cannot open " + quote_path(path) + ": " + in.error);
  if (in.kind != os::Kind::regular) {
    return failure(in.kind == os::Kind::directory ? IoError::read_failed : IoError::unsupported,
                   quote_path(path) + " is not a regular file (" + os::describe(in.kind) +
                       "): inputs are read from regular files only");
  }
  file_ = in.file;
  return {};
}

namespace {

// A name no other writer (thread, process) is likely to pick at the same moment; exclusive
// creation ("x") turns the unlikely collision into a retry instead of a shared file.
std::string temporary_name(const std::string& destination, int attempt) {
  static std::atomic<unsigned> counter{0};
  const auto ticks = static_cast<unsigned long long>(
      std::chrono::steady_clock::now().time_since_epoch().count());
  const unsigned serial = counter.fetch_add(1, std::memory_order_relaxed);
  return destination + ".tmp" + std::to_string(os::process_id()) + "-" +
         std::to_string(ticks % 1000000007ULL) + "-" + std::to_string(serial) + "-" + std::to_string(attempt);
}

}  // namespace

ReplacingFile::~ReplacingFile() { discard(); }

void ReplacingFile::discard() noexcept {
  if (file_ != nullptr) {
    std::fclose(file_);
    file_ = nullptr;
  }
  if (!temporary_.empty()) {
    os::remove_file(temporary_.c_str());
    untrack_temporary(temporary_);
    temporary_.clear();
  }
}

IoStatus ReplacingFile::create(const std::string& destination) {
  discard();
  destination_ = destination;
  std::string error = "unknown error";
  for (int attempt = 0; attempt < 8; ++attempt) {
    std::string name = temporary_name(destination, attempt);
    bool exists = false;
    file_ = create_temporary(name, &exists, &error);
    if (file_ != nullptr) {
      temporary_ = std::move(name);
      return {};
    }
    if (!exists) break;
  }
  return failure(IoError::write_failed, "cannot create a temporary file next to " + quote_path(destination) + ": " + error);
}

IoStatus ReplacingFile::commit() {
  if (file_ == nullptr) return failure(IoError::write_failed, "no file open for " + quote_path(destination_));
  errno = 0;
  const bool flushed = std::fflush(file_) == 0 && std::ferror(file_) == 0;
  int code = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!closed && code == 0) code = errno;
  if (!flushed || !closed) {
    discard();
    return failure(IoError::write_failed, "cannot write " + quote_path(destination_) + ": " +
                                              (code != 0 ? system_error_text(code) : "unknown error"));
  }
  // Replaces an existing destination atomically (POSIX rename; Windows MoveFileExW).
  if (std::string error; !os::replace_file(temporary_, destination_, &error)) {
    discard();
    return failure(IoError::write_failed, "cannot rename the temporary file onto " + quote_path(destination_) + ": " + error);
  }
  untrack_temporary(temporary_);
  temporary_.clear();
  return {};
}

std::uint32_t quantise(float value, std::uint32_t max_value) noexcept {
  if (!(value > 0.0f)) return 0;  // also NaN
  const float top = static_cast<float>(max_value);
  if (value >= top) return max_value;
  return static_cast<std::uint32_t>(std::round(value));
}

IoStatus check_writable(const ColorView& color) {
  const bool interleaved = color.layout == ColorLayout::interleaved_rgba;
  if (interleaved ? color.channels != 4 : (color.channels < 1 || color.channels > 4)) {
    return failure(IoError::invalid_argument,
                   "cannot write an image of " + std::to_string(color.channels) +
                       " channels (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA; interleaved is RGBA)");
  }
  const int planes = interleaved ? 1 : color.channels;
  const std::ptrdiff_t floats_per_pixel = interleaved ? 4 : 1;
  const int width = color.plane[0].width;
  const int height = color.plane[0].height;
  if (width < 1 || height < 1) {
    return failure(IoError::invalid_argument, "cannot write an empty image (" + std::to_string(width) +
                                                  "x" + std::to_string(height) + ")");
  }
  for (int c = 0; c < planes; ++c) {
    const FloatPlane& plane = color.plane[c];
    if (plane.data == nullptr) {
      return failure(IoError::invalid_argument, "plane " + std::to_string(c) + " has no data");
    }
    if (plane.width != width || plane.height != height) {
      return failure(IoError::size_mismatch, "size mismatch: plane " + std::to_string(c) + " is " +
                                                 size_text(plane.width, plane.height) + ", plane 0 is " +
                                                 size_text(width, height));
    }
    if (plane.stride < floats_per_pixel * width) {
      return failure(IoError::invalid_argument, "plane " + std::to_string(c) + " has stride " +
                                                    std::to_string(plane.stride) + " < row of " +
                                                    std::to_string(floats_per_pixel * width) + " floats");
    }
  }
  return {};
}

IoStatus check_packed(const ColorView& packed, int channels, ColorFormat format) {
  const bool same = packed.format == format || (format == ColorFormat::rgba8 && packed.format == ColorFormat::rgba8_srgb);
  if (!same || packed.layout != ColorLayout::interleaved_rgba) {
    return failure(IoError::invalid_argument, std::string("the pixels are ") + to_string(packed.format) + ", not " +
                                                  to_string(format));
  }
  if (channels < 1 || channels > 4) {
    return failure(IoError::invalid_argument, "cannot write " + std::to_string(channels) +
                                                  " channels (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA)");
  }
  const int width = packed.pixels.width;
  const int height = packed.pixels.height;
  if (width < 1 || height < 1) {
    return failure(IoError::invalid_argument, "cannot write an empty image (" + size_text(width, height) + ")");
  }
  if (packed.pixels.data == nullptr) return failure(IoError::invalid_argument, "the pixels have no data");
  const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(width) * bytes_per_pixel(format);
  if (packed.pixels.stride < row) {
    return failure(IoError::invalid_argument, "the pixels have stride " + std::to_string(packed.pixels.stride) +
                                                  " < row of " + std::to_string(row) + " bytes");
  }
  return {};
}

}  // namespace detail
}  // namespace reproject::io
