// The front end that picks a format by the file name's extension.
//
// The extension, not the content, decides: a tool that writes "out.exr" must get an EXR, and a
// reader that was promised a PNG should say "not a PNG" rather than quietly decode something else.
#include <exception>
#include <new>

#include "imageio/file_util.hpp"
#include "imageio/imageio.hpp"

namespace reproject::io {
namespace {

using detail::failure;
using detail::quote_path;

IoStatus unknown_extension(const std::string& path) {
  return failure(IoError::not_this_format,
                 quote_path(path) + ": unknown image file extension (.png, .pfm or .exr)");
}

// An input whose name says no format: "-" (standard input, which is not read) or another extension.
IoStatus unknown_input(const std::string& path) {
  if (IoStatus status = detail::refuse_standard_input(path); !status) return status;
  return unknown_extension(path);
}

IoStatus read_image_file(const std::string& path, LoadedImage* out) {
  switch (format_from_path(path)) {
    case FileFormat::png: return read_png(path, out);
    case FileFormat::pfm: return read_pfm(path, out);
    case FileFormat::exr: return detail::read_exr_color(path, out);
    case FileFormat::unknown: break;
  }
  *out = LoadedImage{};
  return unknown_input(path);
}

// A depth read through the colour readers must be one grey plane.
IoStatus require_one_channel(const std::string& path, LoadedImage* out, const char* what) {
  const int channels = out->image.channels();
  if (channels == 1) return {};
  *out = LoadedImage{};
  return failure(IoError::unsupported, quote_path(path) + ": unsupported channel layout: a depth " + what +
                                           " must have 1 channel, this one has " + std::to_string(channels));
}

IoStatus read_depth_file(const std::string& path, LoadedImage* out) {
  switch (format_from_path(path)) {
    case FileFormat::png: {
      if (IoStatus status = read_png(path, out); !status) return status;
      return require_one_channel(path, out, "PNG (grey)");
    }
    case FileFormat::pfm: {
      if (IoStatus status = read_pfm(path, out); !status) return status;
      return require_one_channel(path, out, "PFM (Pf)");
    }
    case FileFormat::exr: return detail::read_exr_depth(path, out);
    case FileFormat::unknown: break;
  }
  *out = LoadedImage{};
  return unknown_input(path);
}

// The header phase of read_image_file / read_depth_file: the same errors, no pixel decoded.
IoStatus read_info_file(const std::string& path, bool depth, ImageInfo* out) {
  *out = ImageInfo{};
  IoStatus status;
  const char* what = "";
  switch (format_from_path(path)) {
    case FileFormat::png: status = detail::read_png_info(path, out); what = "PNG (grey)"; break;
    case FileFormat::pfm: status = detail::read_pfm_info(path, out); what = "PFM (Pf)"; break;
    case FileFormat::exr: return detail::read_exr_info(path, depth, out);
    case FileFormat::unknown: return unknown_input(path);
  }
  if (status && depth && out->channels != 1) {
    const int channels = out->channels;
    *out = ImageInfo{};
    return failure(IoError::unsupported, quote_path(path) + ": unsupported channel layout: a depth " + what +
                                             " must have 1 channel, this one has " + std::to_string(channels));
  }
  if (!status) *out = ImageInfo{};
  return status;
}

IoStatus out_of_memory_reading(const std::string& path) {
  return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
}

IoStatus read_info(const std::string& path, bool depth, ImageInfo* out) {
  if (out == nullptr) return failure(IoError::invalid_argument, "read_image_info: null output");
  try {
    return read_info_file(path, depth, out);
  } catch (const std::bad_alloc&) {
    *out = ImageInfo{};
    return out_of_memory_reading(path);
  } catch (const std::exception& error) {
    *out = ImageInfo{};
    return failure(IoError::read_failed, error.what());
  }
}

}  // namespace

IoStatus read_image_info(const std::string& path, ImageInfo* out) { return read_info(path, false, out); }
IoStatus read_depth_info(const std::string& path, ImageInfo* out) { return read_info(path, true, out); }

const char* to_string(FileFormat format) noexcept {
  switch (format) {
    case FileFormat::unknown: return "unknown";
    case FileFormat::png: return "png";
    case FileFormat::pfm: return "pfm";
    case FileFormat::exr: return "exr";
  }
  return "unknown";
}

FileFormat format_from_path(const std::string& path) {
  // The extension is what follows the last '.' of the last path component.
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.rfind('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return FileFormat::unknown;
  std::string extension = path.substr(dot + 1);
  for (char& c : extension) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  if (extension == "png") return FileFormat::png;
  if (extension == "pfm") return FileFormat::pfm;
  if (extension == "exr") return FileFormat::exr;
  return FileFormat::unknown;
}

IoStatus read_image(const std::string& path, LoadedImage* out) {
  if (out == nullptr) return failure(IoError::invalid_argument, "read_image: null output");
  try {
    return read_image_file(path, out);
  } catch (const std::bad_alloc&) {
    *out = LoadedImage{};
    return out_of_memory_reading(path);
  }
}

IoStatus write_image(const std::string& path, const ColorView& color, const WriteOptions& options) {
  try {
    switch (format_from_path(path)) {
      case FileFormat::png: return write_png(path, color, options.png_bit_depth == 0 ? 8 : options.png_bit_depth);
      case FileFormat::pfm: return write_pfm(path, color, options.pfm_byte_order);
      case FileFormat::exr: return write_exr(path, color, nullptr, options.exr);
      case FileFormat::unknown: break;
    }
    return unknown_extension(path);
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory writing " + quote_path(path));
  }
}

IoStatus read_depth(const std::string& path, LoadedImage* out) {
  if (out == nullptr) return failure(IoError::invalid_argument, "read_depth: null output");
  try {
    return read_depth_file(path, out);
  } catch (const std::bad_alloc&) {
    *out = LoadedImage{};
    return out_of_memory_reading(path);
  }
}

IoStatus write_depth(const std::string& path, const FloatPlane& depth, const WriteOptions& options) {
  try {
    const ColorView view = ColorView::planar({depth});
    switch (format_from_path(path)) {
      case FileFormat::png: return write_png(path, view, options.png_bit_depth == 0 ? 16 : options.png_bit_depth);
      case FileFormat::pfm: return write_pfm(path, view, options.pfm_byte_order);
      case FileFormat::exr: return write_exr(path, ColorView{}, &depth, options.exr);
      case FileFormat::unknown: break;
    }
    return unknown_extension(path);
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory writing " + quote_path(path));
  }
}

}  // namespace reproject::io
