// Reading inputs and writing outputs all or nothing (see OutputSet in cli.hpp). The formats are
// imageio's; this file only normalises colour and stages the writes.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "cli.hpp"

namespace reproject::cli {
namespace fs = std::filesystem;

namespace {

const char* format_list() { return ".png, .pfm or .exr"; }

}  // namespace

ColorImage read_color(const std::string& path) {
  io::LoadedImage loaded;
  if (io::IoStatus s = io::read_image(path, &loaded); !s) fail(kExitInput, s.message);
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
  if (io::IoStatus s = io::read_depth(path, &loaded); !s) fail(kExitInput, s.message);
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
    const fs::path a = fs::path(flags.text(names[i])).lexically_normal();
    for (std::size_t j = i + 1; j < names.size(); ++j) {
      if (flags.has(names[j]) && a == fs::path(flags.text(names[j])).lexically_normal()) {
        fail(kExitUsage, std::string("--") + names[i] + " and --" + names[j] + " name the same file '" + flags.text(names[i]) + "'");
      }
    }
  }
}

// ---- OutputSet --------------------------------------------------------------------------------

OutputSet::~OutputSet() {
  if (committed_) return;
  for (const Staged& s : staged_) {
    std::error_code ignored;
    fs::remove(s.temporary, ignored);
  }
  // Innermost first: remove() only removes empty directories, so a directory that held
  // anything before (or that someone else wrote into meanwhile) stays.
  for (auto it = created_dirs_.rbegin(); it != created_dirs_.rend(); ++it) {
    std::error_code ignored;
    fs::remove(*it, ignored);
  }
}

void OutputSet::make_directory(const std::string& dir) {
  std::error_code error;
  if (fs::is_directory(dir, error)) return;
  // Remember every level this call creates, outermost first.
  std::vector<std::string> missing;
  for (fs::path p = fs::path(dir); !p.empty() && !fs::exists(p, error); p = p.parent_path()) {
    missing.insert(missing.begin(), p.string());
    if (p == p.parent_path()) break;
  }
  if (!fs::create_directories(dir, error) && error) {
    fail(kExitOutput, "cannot create the directory '" + dir + "': " + error.message());
  }
  if (!fs::is_directory(dir, error)) fail(kExitOutput, "'" + dir + "' exists and is not a directory");
  created_dirs_.insert(created_dirs_.end(), missing.begin(), missing.end());
}

// "dir/name.png" -> "dir/name.reproject-tmp<pid>-<n>.png": same directory (so the final rename
// does not cross file systems) and same extension (imageio picks the format by it).
std::string OutputSet::stage(const std::string& path) {
  for (const Staged& s : staged_) {
    if (fs::path(s.destination).lexically_normal() == fs::path(path).lexically_normal()) {
      fail(kExitUsage, "'" + path + "' is named as more than one output");
    }
  }
  const fs::path p(path);
  const std::string temporary =
      (p.parent_path() / (p.stem().string() + ".reproject-tmp" + std::to_string(static_cast<long>(::getpid())) + "-" +
                          std::to_string(staged_.size()) + p.extension().string()))
          .string();
  staged_.push_back({temporary, path});
  return temporary;
}

void OutputSet::check(const io::IoStatus& status, const std::string& path) {
  if (status) return;
  // imageio names the file it wrote, which is our temporary one: name the destination instead.
  std::string message = status.message;
  const std::string& temporary = staged_.back().temporary;
  for (std::size_t at = message.find(temporary); at != std::string::npos; at = message.find(temporary, at)) {
    message.replace(at, temporary.size(), path);
    at += path.size();
  }
  fail(kExitOutput, message);
}

void OutputSet::color(const std::string& path, const ColorView& color, int png_bits) {
  const io::FileFormat format = io::format_from_path(path);
  const std::string temporary = stage(path);
  io::WriteOptions options;
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
    check(io::write_image(temporary, scaled.color(), options), path);
    return;
  }
  ColorView view = color;
  if (format == io::FileFormat::pfm && (view.channels == 2 || view.channels == 4)) {
    view.channels -= 1;  // PFM has no alpha: write grey or RGB
  }
  check(io::write_image(temporary, view, options), path);
}

void OutputSet::plane(const std::string& path, const FloatPlane& plane, int png_bits) {
  const std::string temporary = stage(path);
  io::WriteOptions options;
  options.png_bit_depth = png_bits;
  check(io::write_depth(temporary, plane, options), path);
}

void OutputSet::picture(const std::string& path, const Image& picture) {
  const std::string temporary = stage(path);
  io::WriteOptions options;
  options.png_bit_depth = 8;
  check(io::write_image(temporary, picture.color(), options), path);
}

void OutputSet::bytes(const std::string& path, const std::uint8_t* data, int width, int height) {
  Image grey(width, height, 1);
  if (grey.empty()) fail(kExitRuntime, "out of memory writing '" + path + "'");
  for (int y = 0; y < height; ++y) {
    float* row = grey.plane_data() + y * grey.stride();
    for (int x = 0; x < width; ++x) row[x] = data[static_cast<std::size_t>(y) * width + x];
  }
  const std::string temporary = stage(path);
  io::WriteOptions options;
  options.png_bit_depth = 8;
  check(io::write_image(temporary, grey.color(), options), path);
}

void OutputSet::text(const std::string& path, const std::string& content) {
  const std::string temporary = stage(path);
  std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
  file << content;
  file.close();
  if (!file) fail(kExitOutput, "cannot write '" + path + "'");
}

void OutputSet::commit() {
  for (const Staged& s : staged_) {
    std::error_code error;
    fs::rename(s.temporary, s.destination, error);
    if (error) fail(kExitOutput, "cannot rename a temporary file onto '" + s.destination + "': " + error.message());
  }
  committed_ = true;
}

}  // namespace reproject::cli
