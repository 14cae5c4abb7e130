// Reading inputs and writing outputs all or nothing (see OutputSet in cli.hpp). The formats are
// imageio's; this file only normalises colour and stages the writes.
#if defined(_WIN32)
#ifndef NOMINMAX
#define NOMINMAX  // windows.h would define min and max as macros
#endif
#include <windows.h>
// windows.h defines near and far as empty macros (16-bit pointers): names of ours.
#undef near
#undef far
#endif

#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "cli.hpp"
#include "imageio/os.hpp"

namespace reproject::cli {
namespace fs = std::filesystem;

namespace {

const char* format_list() { return ".png, .pfm or .exr"; }

// Whether `path`'s extension (what follows the last '.' of its last component) is `extension`,
// ignoring case.
bool has_extension(const std::string& path, const char* extension) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.rfind('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return false;
  const std::string ext = path.substr(dot + 1);
  if (ext.size() != std::strlen(extension)) return false;
  for (std::size_t i = 0; i < ext.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(ext[i])) != extension[i]) return false;
  }
  return true;
}

}  // namespace

namespace {

// An input that cannot be read: out of memory is the machine's limit (exit 1), anything else the
// file's fault (exit 3); imageio's message names the file either way.
[[noreturn]] void input_failure(const io::IoStatus& status) {
  fail(status.error == io::IoError::out_of_memory ? kExitRuntime : kExitInput, status.message);
}

}  // namespace

bool is_raw_path(const std::string& path) { return has_extension(path, "raw"); }

io::ImageInfo color_info(const std::string& path) {
  io::ImageInfo info;
  if (io::IoStatus s = io::read_image_info(path, &info); !s) input_failure(s);
  return info;
}

io::ImageInfo depth_info(const std::string& path) {
  io::ImageInfo info;
  if (io::IoStatus s = io::read_depth_info(path, &info); !s) input_failure(s);
  return info;
}

std::string size_text(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

ColorImage read_color(const std::string& path) {
  io::LoadedImage loaded;
  if (io::IoStatus s = io::read_image(path, &loaded); !s) input_failure(s);
  ColorImage out;
  out.format = loaded.format;
  out.bit_depth = loaded.bit_depth;
  out.image = std::move(loaded.image);
  if (out.format == io::FileFormat::png) {
    // Integers to 0..1, so that one PSNR peak and one picture scale fit every input.
    const float inv = 1.0f / static_cast<float>((1u << out.bit_depth) - 1u);
    for (int c = 0; c < out.image.channels(); ++c) {
      for (int y = 0; y < out.image.height(); ++y) {
        float* row = out.image.plane_data(c) + y * out.image.stride();
        for (int x = 0; x < out.image.width(); ++x) row[x] *= inv;
      }
    }
  }
  return out;
}

io::LoadedImage read_depth_file(const std::string& path) {
  io::LoadedImage loaded;
  if (io::IoStatus s = io::read_depth(path, &loaded); !s) input_failure(s);
  return loaded;
}

void check_output_path(const char* flag, const std::string& path) {
  if (io::format_from_path(path) == io::FileFormat::unknown) {
    fail(kExitUsage, std::string("--") + flag + ": '" + path + "' has no known image extension (" + format_list() + ")");
  }
}

void check_distinct_outputs(const Flags& flags, const std::vector<const char*>& names) {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (!flags.has(names[i])) continue;
    for (std::size_t j = i + 1; j < names.size(); ++j) {
      if (flags.has(names[j]) && same_destination(flags.text(names[i]), flags.text(names[j]))) {
        fail(kExitUsage, std::string("--") + names[i] + " and --" + names[j] + " name the same file '" + flags.text(names[i]) + "'");
      }
    }
  }
}

bool same_file(const std::string& a, const std::string& b) { return io::os::same_file(a, b); }

bool same_destination(const std::string& a, const std::string& b) {
  if (same_file(a, b)) return true;
  std::error_code ea, eb;
  const fs::path pa = io::os::to_path(a), pb = io::os::to_path(b);
  const fs::path ca = fs::weakly_canonical(pa, ea), cb = fs::weakly_canonical(pb, eb);
  if (ea || eb) return pa.lexically_normal() == pb.lexically_normal();
  return ca == cb;
}

// ---- Signals -----------------------------------------------------------------------------------

namespace {

// While commit() renames, a signal must not remove the files it is moving: the handler then only
// notes the signal, and commit() acts on it once the set is complete (or rolled back).
std::atomic<bool> committing{false};
std::atomic<bool> interrupted{false};
#if !defined(_WIN32)
std::atomic<int> deferred_signal{0};
#endif

#if defined(_WIN32)
// Windows runs a console control handler on a thread of its own, while the command goes on: the
// handler asks the command to stop (interrupted, read by the library as Options::cancel and by
// the tool between steps) and gives it time to unwind through its own clean-up, which also closes
// the files it is writing (an open file cannot be deleted). After a close event Windows ends the
// process 5 s later whatever the handler does; 3 s are left to the command.
BOOL WINAPI on_console_event(DWORD) {
  interrupted.store(true);
  for (int waited_ms = 0; waited_ms < 3000 || committing.load(); waited_ms += 10) Sleep(10);
  io::remove_temporary_files();  // the writers' files are opened so that they can be deleted open
  ExitProcess(kExitInterrupted);
}
#else
void die_of(int signal_number) {
  io::remove_temporary_files();
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);  // blocked while the handler runs: delivered when it returns
}

extern "C" void on_terminating_signal(int signal_number) {
  if (committing.load()) {
    deferred_signal.store(signal_number);
    return;
  }
  die_of(signal_number);
}
#endif

// After commit(): the signal that came during it (POSIX), or the interruption (Windows).
void act_on_deferred_signal() {
#if !defined(_WIN32)
  if (const int signal_number = deferred_signal.exchange(0)) die_of(signal_number);
#endif
  fail_if_interrupted();
}

}  // namespace

void remove_temporaries_on_signals() {
#if defined(_WIN32)
  SetConsoleCtrlHandler(on_console_event, TRUE);
#else
  struct sigaction action = {};
  action.sa_handler = on_terminating_signal;
  sigemptyset(&action.sa_mask);
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaction(signal_number, &action, nullptr);
#endif
}

const std::atomic<bool>* interruption() { return &interrupted; }

void fail_if_interrupted() {
  if (interrupted.load()) fail(kExitInterrupted, "interrupted");
}

// ---- OutputSet --------------------------------------------------------------------------------

OutputSet::~OutputSet() {
  if (committed_) return;
  for (const Staged& s : staged_) {
    io::os::remove_file(s.temporary.c_str());
    io::untrack_temporary(s.temporary);
  }
  // Innermost first: remove() only removes empty directories, so a directory that held
  // anything before (or that someone else wrote into meanwhile) stays.
  for (auto it = created_dirs_.rbegin(); it != created_dirs_.rend(); ++it) {
    io::os::remove_directory(it->c_str());
    io::untrack_temporary(*it);
  }
}

void OutputSet::input(const std::string& flag, const std::string& path) { inputs_.push_back({flag, path}); }

void OutputSet::inputs(const Flags& flags, const std::vector<const char*>& names) {
  for (const char* name : names) {
    if (flags.has(name)) input(name, flags.text(name));
  }
}

void OutputSet::outputs(const Flags& flags, const std::vector<const char*>& names) {
  for (const char* name : names) {
    if (flags.has(name)) expect(name, flags.text(name));
  }
}

void OutputSet::make_directory(const std::string& dir) {
  std::error_code error;
  if (fs::is_directory(io::os::to_path(dir), error)) return;
  // Remember every level this call creates, outermost first; a file where a level should be is
  // reported as such (create_directories would only say "Not a directory" or "File exists").
  std::vector<std::string> missing;
  for (fs::path p = io::os::to_path(dir); !p.empty(); p = p.parent_path()) {
    const fs::file_status status = fs::status(p, error);
    if (fs::exists(status)) {
      if (!fs::is_directory(status)) fail(kExitOutput, "'" + io::os::from_path(p) + "' exists and is not a directory");
      break;
    }
    missing.insert(missing.begin(), io::os::from_path(p));
    if (p == p.parent_path()) break;
  }
  for (const std::string& level : missing) {
    // Tracked before it is created (removed, when still empty, if a signal ends the command), so
    // that no moment exists where it is there but unknown to the signal handler.
    io::track_temporary(level);
    const bool created = fs::create_directory(io::os::to_path(level), error);
    if (!created) io::untrack_temporary(level);  // failed, or someone else made it meanwhile: not ours
    if (error) fail(kExitOutput, "cannot create the directory '" + dir + "': " + error.message());
    if (created) created_dirs_.push_back(level);
  }
}

// "dir/name.png" -> "dir/name.reproject-<what><pid>-<n>.png": same directory (so the final
// rename does not cross file systems) and same extension (imageio picks the format by it).
std::string OutputSet::sibling(const std::string& path, const char* what, std::size_t n) {
  const fs::path p = io::os::to_path(path);
  const std::string name = io::os::from_path(p.stem()) + ".reproject-" + what + std::to_string(io::os::process_id()) +
                           "-" + std::to_string(n) + io::os::from_path(p.extension());
  return io::os::from_path(p.parent_path() / io::os::to_path(name));
}

void OutputSet::expect(const std::string& flag, const std::string& path) {
  for (const auto& in : inputs_) {
    if (same_file(in.second, path)) {
      fail(kExitUsage, "--" + flag + ": '" + path + "' is the input --" + in.first + " '" + in.second +
                           "' (an output must not replace an input)");
    }
  }
  for (const Staged& s : staged_) {
    if (same_destination(s.destination, path)) fail(kExitUsage, "'" + path + "' is named as more than one output");
  }
  // Only regular files are replaced: a rename would put a file in place of a device or a pipe.
  const io::os::Kind kind = io::os::kind_of(path);
  if (kind != io::os::Kind::missing && kind != io::os::Kind::regular) {
    fail(kExitOutput, "cannot write '" + path + "': it is " + (kind == io::os::Kind::directory ? "a directory" : "not a regular file"));
  }
  // Reserve the temporary file now: that proves the directory exists and is writable before any
  // work is done, and the name stays ours until commit() or the destructor.
  // Tracked before it exists, as in make_directory (the name carries our pid).
  const std::string temporary = sibling(path, "tmp", staged_.size());
  bool exists = false;
  std::string error;
  std::FILE* reserved = io::create_temporary(temporary, &exists, &error);
  if (reserved == nullptr) fail(kExitOutput, "cannot write '" + path + "': " + error);
  std::fclose(reserved);
  staged_.push_back({temporary, path, false});
}

const std::string& OutputSet::stage(const std::string& path) {
  for (Staged& s : staged_) {
    if (s.destination == path && !s.written) {
      s.written = true;
      return s.temporary;
    }
  }
  fail(kExitRuntime, "internal error: output '" + path + "' was not checked before the work");
}

void OutputSet::check(const io::IoStatus& status, const std::string& path, const std::string& temporary) {
  if (status) return;
  // imageio names the file it wrote, which is our temporary one: name the destination instead.
  std::string message = status.message;
  for (std::size_t at = message.find(temporary); at != std::string::npos; at = message.find(temporary, at)) {
    message.replace(at, temporary.size(), path);
    at += path.size();
  }
  fail(status.error == io::IoError::out_of_memory ? kExitRuntime : kExitOutput, message);
}

void OutputSet::color(const std::string& path, const ColorView& color, int png_bits, bool exr_half) {
  const io::FileFormat format = io::format_from_path(path);
  const std::string& temporary = stage(path);
  io::WriteOptions options;
  if (exr_half) options.exr.color_type = io::ExrPixelType::half;
  if (format == io::FileFormat::png) {
    // 0..1 back to the file's integers.
    const float scale = static_cast<float>((1u << png_bits) - 1u);
    Image scaled(color.width(), color.height(), color.channels);
    if (scaled.empty()) fail(kExitRuntime, "out of memory writing '" + path + "'");
    for (int c = 0; c < color.channels; ++c) {
      for (int y = 0; y < color.height(); ++y) {
        const float* src = color.plane[c].row(y);
        float* dst = scaled.plane_data(c) + y * scaled.stride();
        for (int x = 0; x < color.width(); ++x) dst[x] = src[x] * scale;
      }
    }
    options.png_bit_depth = png_bits;
    check(io::write_image(temporary, scaled.color(), options), path, temporary);
    return;
  }
  ColorView view = color;
  if (format == io::FileFormat::pfm && (view.channels == 2 || view.channels == 4)) {
    view.channels -= 1;  // PFM has no alpha: write grey or RGB
  }
  check(io::write_image(temporary, view, options), path, temporary);
}

void OutputSet::packed_color(const std::string& path, const ColorView& packed, int channels) {
  const std::string& temporary = stage(path);
  if (is_raw_path(path)) {
    const std::size_t row = static_cast<std::size_t>(packed.width()) * bytes_per_pixel(packed.format);
    // rgba16f: half words, little-endian in the file (as raw_word_bytes says).
    raw_to(path, temporary, packed.pixels.data, row, packed.height(), packed.pixels.stride,
           packed.format == ColorFormat::rgba16f ? 2 : 1);
    return;
  }
  switch (io::format_from_path(path)) {
    case io::FileFormat::png: check(io::write_png_packed(temporary, packed, channels), path, temporary); return;
    case io::FileFormat::exr: check(io::write_exr_packed(temporary, packed, channels), path, temporary); return;
    default: break;
  }
  fail(kExitRuntime, "internal error: no writer of " + std::string(to_string(packed.format)) + " for '" + path + "'");
}

void OutputSet::raw(const std::string& path, const std::uint8_t* data, std::size_t row_bytes, int height,
                    std::ptrdiff_t stride, int word_bytes) {
  raw_to(path, stage(path), data, row_bytes, height, stride, word_bytes);
}

void OutputSet::raw_to(const std::string& path, const std::string& temporary, const std::uint8_t* data,
                       std::size_t row_bytes, int height, std::ptrdiff_t stride, int word_bytes) {
  check(io::write_raw(temporary, data, row_bytes, height, stride, word_bytes), path, temporary);
}

void OutputSet::plane(const std::string& path, const FloatPlane& plane, int png_bits) {
  const std::string& temporary = stage(path);
  io::WriteOptions options;
  options.png_bit_depth = png_bits;
  check(io::write_depth(temporary, plane, options), path, temporary);
}

void OutputSet::picture(const std::string& path, const Image& picture) {
  const std::string& temporary = stage(path);
  io::WriteOptions options;
  options.png_bit_depth = 8;
  check(io::write_image(temporary, picture.color(), options), path, temporary);
}

void OutputSet::bytes(const std::string& path, const std::uint8_t* data, int width, int height) {
  Image grey(width, height, 1);
  if (grey.empty()) fail(kExitRuntime, "out of memory writing '" + path + "'");
  for (int y = 0; y < height; ++y) {
    float* row = grey.plane_data() + y * grey.stride();
    for (int x = 0; x < width; ++x) row[x] = data[static_cast<std::size_t>(y) * width + x];
  }
  const std::string& temporary = stage(path);
  io::WriteOptions options;
  options.png_bit_depth = 8;
  check(io::write_image(temporary, grey.color(), options), path, temporary);
}

void OutputSet::text(const std::string& path, const std::string& content) {
  const std::string& temporary = stage(path);
  errno = 0;
  std::FILE* file = io::os::open_file(temporary, "wb");
  bool ok = file != nullptr && std::fwrite(content.data(), 1, content.size(), file) == content.size();
  int code = errno;
  if (file != nullptr && std::fclose(file) != 0 && ok) {
    ok = false;
    code = errno;
  }
  if (!ok) fail(kExitOutput, "cannot write '" + path + "': " + (code != 0 ? std::strerror(code) : "unknown error"));
}

void OutputSet::commit() {
  // Each destination that exists keeps a hard link to its old content (a backup) until every
  // rename has succeeded, so that a failed rename can put every earlier one back. A new file
  // takes the mode of the one it replaces.
  struct Step {
    std::string backup;  // empty: no old file, or it could not be linked (no undo for that one)
    bool existed = false;
    bool renamed = false;
  };
  std::vector<Step> steps(staged_.size());
  std::string error_text;
  fail_if_interrupted();  // nothing renamed yet: the destructor removes the set
  committing.store(true);
  std::size_t done = 0;
  for (; done < staged_.size(); ++done) {
    const Staged& s = staged_[done];
    Step& step = steps[done];
    if (!s.written) {  // reserved but never written (a command's plan changed): not an output
      io::os::remove_file(s.temporary.c_str());
      io::untrack_temporary(s.temporary);
      continue;
    }
    if (io::os::kind_of(s.destination) == io::os::Kind::regular) {
      step.existed = true;
      io::os::copy_permissions(s.destination, s.temporary);
      const std::string backup = sibling(s.destination, "old", done);
      if (io::os::hard_link(s.destination, backup)) {
        step.backup = backup;
        io::track_temporary(backup);
      }
    }
    if (std::string error; !io::os::replace_file(s.temporary, s.destination, &error)) {
      error_text = "cannot rename a temporary file onto '" + s.destination + "': " + error;
      break;
    }
    step.renamed = true;
    io::untrack_temporary(s.temporary);
  }
  if (!error_text.empty()) {
    for (std::size_t i = 0; i < done; ++i) {  // undo; the order does not matter: distinct files
      if (!steps[i].renamed) continue;
      std::string ignored;
      if (!steps[i].backup.empty()) {
        io::os::replace_file(steps[i].backup, staged_[i].destination, &ignored);
      } else if (!steps[i].existed) {
        io::os::remove_file(staged_[i].destination.c_str());
      }
    }
    for (std::size_t i = done; i < staged_.size(); ++i) io::os::remove_file(staged_[i].temporary.c_str());
    if (done < staged_.size() && !steps[done].backup.empty()) io::os::remove_file(steps[done].backup.c_str());
  } else {
    committed_ = true;
    for (const Step& step : steps) {
      if (!step.backup.empty()) io::os::remove_file(step.backup.c_str());
    }
    for (auto it = created_dirs_.rbegin(); it != created_dirs_.rend(); ++it) io::untrack_temporary(*it);
  }
  for (const Step& step : steps) {
    if (!step.backup.empty()) io::untrack_temporary(step.backup);
  }
  committing.store(false);
  act_on_deferred_signal();
  if (!error_text.empty()) fail(kExitOutput, error_text);
}

}  // namespace reproject::cli
