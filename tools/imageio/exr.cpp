// OpenEXR through the OpenEXR 3 C++ library.
//
// OpenEXR reports errors by throwing (Iex::BaseExc, a std::exception). Everything that calls into
// it runs inside the try blocks of read_exr / write_exr and friends, which turn exceptions into
// IoStatus values. The library reads and writes through our own stream classes over the stdio
// files of file_util, for three reasons:
//  * a missing file, an unreadable file and a short file are told apart (open_failed, read_failed,
//    truncated) instead of all being "an exception from OpenEXR";
//  * writes go to the ReplacingFile, so a failed write leaves the destination untouched;
//  * OutputFile writes its table of line offsets in its destructor and swallows any error there;
//    the output stream remembers a failed write so that such a file is not committed.
#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfLineOrder.h>
#include <ImfOutputFile.h>
#include <ImfVersion.h>
#include <Iex.h>
#include <half.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
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

// ---- streams ----

// Reads from an open stdio file. A short read throws (as OpenEXR's own streams do) after noting
// whether the file ended or the system failed, which the caller turns into the IoError.
class FileInput final : public Imf::IStream {
 public:
  FileInput(std::FILE* file, const std::string& path) : Imf::IStream(path.c_str()), file_(file) {}

  bool read(char c[], int n) override {
    if (n < 0) throw Iex::ArgExc("negative read size");
    errno = 0;
    const std::size_t got = std::fread(c, 1, static_cast<std::size_t>(n), file_);
    if (got == static_cast<std::size_t>(n)) return true;
    if (std::ferror(file_) != 0) {
      system_error_ = errno != 0 ? errno : EIO;
      throw Iex::IoExc("read error");
    }
    ended_ = true;
    throw Iex::InputExc("unexpected end of file");
  }
  std::uint64_t tellg() override {
    const std::int64_t position = os::tell(file_);
    if (position < 0) throw Iex::IoExc("cannot tell the file position");
    return static_cast<std::uint64_t>(position);
  }
  void seekg(std::uint64_t position) override {
    // Seeking past the end succeeds; the read that follows reports the truncation. An offset
    // beyond any possible file (a damaged or cut offset table: the system refuses the seek) is
    // reported as the file ending too.
    if (!os::seek(file_, position)) {
      ended_ = true;
      throw Iex::InputExc("an offset beyond the end of the file");
    }
  }
  void clear() override { std::clearerr(file_); }

  bool ended() const noexcept { return ended_; }
  int system_error() const noexcept { return system_error_; }

 private:
  std::FILE* file_;
  bool ended_ = false;
  int system_error_ = 0;
};

class FileOutput final : public Imf::OStream {
 public:
  FileOutput(std::FILE* file, const std::string& path) : Imf::OStream(path.c_str()), file_(file) {}

  void write(const char c[], int n) override {
    if (n < 0) throw Iex::ArgExc("negative write size");
    errno = 0;
    if (std::fwrite(c, 1, static_cast<std::size_t>(n), file_) == static_cast<std::size_t>(n)) return;
    fail(errno);
    throw Iex::IoExc("write error");
  }
  std::uint64_t tellp() override {
    const std::int64_t position = os::tell(file_);
    if (position < 0) {
      fail(errno);
      throw Iex::IoExc("cannot tell the file position");
    }
    return static_cast<std::uint64_t>(position);
  }
  void seekp(std::uint64_t position) override {
    if (!os::seek(file_, position)) {
      fail(errno);
      throw Iex::IoExc("cannot seek");
    }
  }

  bool failed() const noexcept { return failed_; }
  int system_error() const noexcept { return system_error_; }

 private:
  void fail(int code) noexcept {
    if (failed_) return;
    failed_ = true;
    system_error_ = code;
  }
  std::FILE* file_;
  bool failed_ = false;
  int system_error_ = 0;
};

// ---- channel names ----

struct ChannelInfo {
  std::string name;
  Imf::PixelType type = Imf::FLOAT;
  int x_sampling = 1;
  int y_sampling = 1;
};

// The layer of "a.b.Z" is "a.b"; of "Z" it is "".
std::string layer_of(const std::string& name) {
  const std::size_t dot = name.rfind('.');
  return dot == std::string::npos ? std::string() : name.substr(0, dot);
}
std::string last_component(const std::string& name) {
  const std::size_t dot = name.rfind('.');
  return dot == std::string::npos ? name : name.substr(dot + 1);
}
std::string lower(std::string text) {
  for (char& c : text) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return text;
}
std::string join_name(const std::string& layer, const char* component) {
  return layer.empty() ? std::string(component) : layer + "." + component;
}
std::string name_list(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + ("'" + name + "'");
  return text.empty() ? "none" : text;
}

struct ChannelSet {
  std::vector<ChannelInfo> channels;  // sorted by name, as OpenEXR keeps them

  const ChannelInfo* find(const std::string& name) const {
    for (const ChannelInfo& channel : channels) {
      if (channel.name == name) return &channel;
    }
    return nullptr;
  }
  bool has(const std::string& layer, const char* component) const {
    return find(join_name(layer, component)) != nullptr;
  }
  std::vector<std::string> names() const {
    std::vector<std::string> result;
    for (const ChannelInfo& channel : channels) result.push_back(channel.name);
    return result;
  }
};

// The colour channels of `layer`: R, G, B (+ A), else Y (+ A); empty when it has neither.
std::vector<std::string> color_channels_of(const ChannelSet& set, const std::string& layer) {
  std::vector<std::string> names;
  if (set.has(layer, "R") && set.has(layer, "G") && set.has(layer, "B")) {
    names = {join_name(layer, "R"), join_name(layer, "G"), join_name(layer, "B")};
  } else if (set.has(layer, "Y")) {
    names = {join_name(layer, "Y")};
  } else {
    return names;
  }
  if (set.has(layer, "A")) names.push_back(join_name(layer, "A"));
  return names;
}

// Picks the colour channels per the rule in imageio.hpp. An empty `names` with an ok status means
// the file has no colour.
IoStatus choose_color(const ChannelSet& set, const ExrReadOptions& options, const std::string& path,
                      std::string* layer, std::vector<std::string>* names) {
  if (options.color_layer) {
    *layer = *options.color_layer;
    *names = color_channels_of(set, *layer);
    if (names->empty()) {
      return failure(IoError::unsupported,
                     quote_path(path) + ": unsupported channel layout: no colour channels (" +
                         join_name(*layer, "R") + ", " + join_name(*layer, "G") + ", " + join_name(*layer, "B") +
                         " or " + join_name(*layer, "Y") + "); channels: " + name_list(set.names()));
    }
    return {};
  }
  layer->clear();
  names->clear();
  if (set.has("", "R") && set.has("", "G") && set.has("", "B")) {
    *names = color_channels_of(set, "");
    return {};
  }
  std::vector<std::string> layers;
  for (const ChannelInfo& channel : set.channels) {
    const std::string candidate = layer_of(channel.name);
    if (candidate.empty() || last_component(channel.name) != "R") continue;
    if (set.has(candidate, "G") && set.has(candidate, "B")) layers.push_back(candidate);
  }
  if (layers.size() > 1) {
    std::vector<std::string> combined;
    for (const std::string& candidate : layers) {
      if (last_component(candidate) == "Combined") combined.push_back(candidate);
    }
    if (combined.size() != 1) {
      return failure(IoError::unsupported,
                     quote_path(path) + ": unsupported channel layout: several colour layers (" + name_list(layers) +
                         ") and no single 'Combined' one; name one in ExrReadOptions::color_layer");
    }
    layers = combined;
  }
  if (layers.size() == 1) {
    *layer = layers.front();
    *names = color_channels_of(set, *layer);
    return {};
  }
  if (set.has("", "Y")) *names = color_channels_of(set, "");
  return {};
}

// Picks the depth channel per the rule in imageio.hpp. An empty `name` with an ok status means the
// file has none.
IoStatus choose_depth(const ChannelSet& set, const ExrReadOptions& options, const std::string& path,
                      std::string* name) {
  name->clear();
  if (options.depth_channel) {
    if (options.depth_channel->empty()) return {};
    if (set.find(*options.depth_channel) == nullptr) {
      return failure(IoError::unsupported, quote_path(path) + ": unsupported channel layout: no channel '" +
                                               *options.depth_channel + "'; channels: " + name_list(set.names()));
    }
    *name = *options.depth_channel;
    return {};
  }
  if (set.find("Z") != nullptr) {
    *name = "Z";
    return {};
  }
  std::vector<std::string> top;          // "depth" in any case
  std::vector<std::string> depth_layer;  // "*.Depth.Z", "*.depth.depth", ...
  std::vector<std::string> other;        // "*.Z", "*.depth" elsewhere
  for (const ChannelInfo& channel : set.channels) {
    const std::string last = last_component(channel.name);
    if (last != "Z" && lower(last) != "depth") continue;
    const std::string layer = layer_of(channel.name);
    if (layer.empty()) {
      top.push_back(channel.name);
      continue;
    }
    // A Z beside an X or Y is a vector's component (Blender's Normal, Vector, Position passes),
    // and Blender's Mist pass keeps a 0..1 fog factor in Z: neither is a depth.
    if (set.has(layer, "X") || set.has(layer, "Y")) continue;
    const std::string kind = lower(last_component(layer));
    if (kind == "depth") {
      depth_layer.push_back(channel.name);
    } else if (kind != "mist") {
      other.push_back(channel.name);
    }
  }
  for (const std::vector<std::string>* step : {&top, &depth_layer, &other}) {
    if (step->empty()) continue;
    if (step->size() > 1) {
      return failure(IoError::unsupported, quote_path(path) + ": unsupported channel layout: several depth channels (" +
                                               name_list(*step) + "); name one in ExrReadOptions::depth_channel");
    }
    *name = step->front();
    return {};
  }
  return {};
}

// ---- reading ----

enum class Purpose { any, color, depth };

IoStatus unsupported_sampling(const std::string& path, const ChannelInfo& channel) {
  return failure(IoError::unsupported, quote_path(path) + ": unsupported channel layout: channel '" + channel.name +
                                           "' is subsampled (" + std::to_string(channel.x_sampling) + "x" +
                                           std::to_string(channel.y_sampling) + ")");
}

// The colour channels `names` (1 Y, 2 Y A, 3 R G B, 4 R G B A; all half) as rgba16f, straight
// from the file's halves: OpenEXR writes each channel into its place in the interleaved pixels.
IoStatus read_packed_color(const std::string& path, Imf::InputFile& file, const Imath::Box2i& window,
                           const std::string& layer, const std::vector<std::string>& names, bool all_half,
                           PackedColor* out) {
  if (!all_half) {
    return failure(IoError::unsupported, quote_path(path) + ": the colour channels are not all half (" +
                                             name_list(names) + "): read it as floats");
  }
  const int width = window.max.x - window.min.x + 1;
  const int height = window.max.y - window.min.y + 1;
  const bool grey = names.size() <= 2;
  const bool alpha = names.size() == 2 || names.size() == 4;
  const std::size_t pixel = 4 * sizeof(half);
  auto read_rows = [&](std::uint8_t* base, int y0, int y1) {
    const Imath::Box2i rows(Imath::V2i(window.min.x, y0), Imath::V2i(window.max.x, y1));
    const std::size_t row_bytes = pixel * static_cast<std::size_t>(width);
    Imf::FrameBuffer frame;
    const int color_slots = grey ? 1 : 3;  // grey goes to R and is copied to G and B below
    for (int c = 0; c < color_slots; ++c) {
      frame.insert(names[static_cast<std::size_t>(c)],
                   Imf::Slice::Make(Imf::HALF, base + c * sizeof(half), rows, pixel, row_bytes));
    }
    // A channel the file lacks is filled with the slice's fill value: an absent alpha is opaque.
    const std::string alpha_name = alpha ? names.back() : join_name(layer, "A");
    frame.insert(alpha_name, Imf::Slice::Make(Imf::HALF, base + 3 * sizeof(half), rows, pixel, row_bytes, 1, 1, 1.0));
    file.setFrameBuffer(frame);
    file.readPixels(y0, y1);
    if (grey) {
      for (int y = 0; y <= y1 - y0; ++y) {
        std::uint8_t* p = base + static_cast<std::size_t>(y) * row_bytes;
        for (int x = 0; x < width; ++x, p += pixel) {
          std::memcpy(p + sizeof(half), p, sizeof(half));
          std::memcpy(p + 2 * sizeof(half), p, sizeof(half));
        }
      }
    }
  };
  // As read_exr_file: the row stored last first, into a one-row buffer, so that a file cut
  // short fails before the image is allocated.
  {
    const int y = file.header().lineOrder() == Imf::DECREASING_Y ? window.min.y : window.max.y;
    std::vector<std::uint8_t> row(pixel * static_cast<std::size_t>(width));
    read_rows(row.data(), y, y);
  }
  PackedColor packed;
  packed.width = width;
  packed.height = height;
  packed.channels = static_cast<int>(names.size());
  packed.format = ColorFormat::rgba16f;
  packed.bytes.resize(pixel * static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  read_rows(packed.bytes.data(), window.min.y, window.max.y);
  *out = std::move(packed);
  return {};
}

// Reads the planes the purpose wants; with `info_only`, only says what they would be; with
// `packed`, reads the colour as rgba16f instead (read_packed_color).
IoStatus read_exr_file(const std::string& path, LoadedImage* out, const ExrReadOptions& options, Purpose purpose,
                       FileInput* stream, ImageInfo* info_only, PackedColor* packed) {
  Imf::InputFile file(*stream);
  const Imf::Header& header = file.header();
  const Imath::Box2i window = header.dataWindow();
  const long long width = static_cast<long long>(window.max.x) - window.min.x + 1;
  const long long height = static_cast<long long>(window.max.y) - window.min.y + 1;
  if (width < 1 || height < 1) {
    return failure(IoError::corrupt, quote_path(path) + " is a damaged OpenEXR file: empty data window");
  }
  if (static_cast<unsigned long long>(width) * static_cast<unsigned long long>(height) > detail::kMaxPixels) {
    return failure(IoError::unsupported, quote_path(path) + ": image of " + std::to_string(width) + "x" +
                                             std::to_string(height) + " pixels exceeds the " +
                                             std::to_string(detail::kMaxPixels) + "-pixel limit");
  }

  ChannelSet set;
  for (Imf::ChannelList::ConstIterator it = header.channels().begin(); it != header.channels().end(); ++it) {
    set.channels.push_back({it.name(), it.channel().type, it.channel().xSampling, it.channel().ySampling});
  }

  std::string color_layer;
  std::vector<std::string> color_names;
  if (purpose != Purpose::depth) {
    if (IoStatus status = choose_color(set, options, path, &color_layer, &color_names); !status) return status;
  }
  std::string depth_name;
  if (IoStatus status = choose_depth(set, options, path, &depth_name); !status) return status;
  // A depth file may be a single channel of any name (a renderer's "Y", a tool's "disparity").
  if (purpose == Purpose::depth && depth_name.empty() && set.channels.size() == 1 && !options.depth_channel) {
    depth_name = set.channels.front().name;
  }

  if (purpose == Purpose::color && color_names.empty()) {
    return failure(IoError::unsupported, quote_path(path) + ": unsupported channel layout: no colour channels "
                                                            "(R, G, B or Y, top level or in one layer); channels: " +
                                             name_list(set.names()));
  }
  if (purpose == Purpose::depth && depth_name.empty()) {
    return failure(IoError::unsupported, quote_path(path) + ": unsupported channel layout: no depth channel "
                                                            "(Z, depth, *.Depth.Z, *.Z, or a single channel); "
                                                            "channels: " + name_list(set.names()));
  }
  if (color_names.empty() && depth_name.empty()) {
    return failure(IoError::unsupported, quote_path(path) + ": unsupported channel layout: neither colour "
                                                            "(R, G, B or Y) nor depth (Z, depth, *.Z) channels; "
                                                            "channels: " + name_list(set.names()));
  }

  bool all_half = true, color_half = true;
  std::vector<const ChannelInfo*> wanted;
  for (const std::string& name : color_names) wanted.push_back(set.find(name));
  if (!depth_name.empty()) wanted.push_back(set.find(depth_name));
  for (const ChannelInfo* channel : wanted) {
    if (channel->x_sampling != 1 || channel->y_sampling != 1) return unsupported_sampling(path, *channel);
    if (channel->type != Imf::HALF) all_half = false;
  }
  for (const std::string& name : color_names) color_half = color_half && set.find(name)->type == Imf::HALF;
  const bool depth_half = !depth_name.empty() && set.find(depth_name)->type == Imf::HALF;

  const int w = static_cast<int>(width);
  const int h = static_cast<int>(height);
  if (info_only != nullptr) {
    const int channels = purpose == Purpose::depth ? 1 : static_cast<int>(color_names.size());
    const bool half = purpose == Purpose::depth ? depth_half : color_half;
    *info_only = ImageInfo{w, h, channels, FileFormat::exr, half ? 16 : 32};
    return {};
  }
  if (packed != nullptr) return read_packed_color(path, file, window, color_layer, color_names, color_half, packed);

  // Every slice is float: OpenEXR converts half and uint channels while reading. `rows` is the
  // part of the data window that `color` and `depth` hold.
  auto read_rows = [&](Image* color, Image* depth, int y0, int y1) {
    const Imath::Box2i rows(Imath::V2i(window.min.x, y0), Imath::V2i(window.max.x, y1));
    Imf::FrameBuffer frame;
    const std::size_t x_stride = sizeof(float);
    for (std::size_t c = 0; c < color_names.size(); ++c) {
      frame.insert(color_names[c], Imf::Slice::Make(Imf::FLOAT, color->plane_data(static_cast<int>(c)), rows, x_stride,
                                                    static_cast<std::size_t>(color->stride()) * sizeof(float)));
    }
    if (!depth_name.empty()) {
      frame.insert(depth_name, Imf::Slice::Make(Imf::FLOAT, depth->plane_data(), rows, x_stride,
                                                static_cast<std::size_t>(depth->stride()) * sizeof(float)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(y0, y1);
  };
  auto allocate = [&](int rows, Image* color, Image* depth) {
    if (!color_names.empty()) *color = Image(w, rows, static_cast<int>(color_names.size()));
    if (!depth_name.empty()) *depth = Image(w, rows, 1);
    return (color_names.empty() || !color->empty()) && (depth_name.empty() || !depth->empty());
  };

  // The last row stored first (the bottom one, unless the file stores them bottom to top), into
  // a one-row band: a file cut short, or whose data window promises more than it stores, fails
  // here, before the image is allocated. (OpenEXR still allocates what it needs to decompress the
  // chunk that row is in.)
  {
    const int y = header.lineOrder() == Imf::DECREASING_Y ? window.min.y : window.max.y;
    Image color_row, depth_row;
    if (!allocate(1, &color_row, &depth_row)) {
      return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
    }
    read_rows(&color_row, &depth_row, y, y);
  }
  Image color;
  Image depth;
  if (!allocate(h, &color, &depth)) return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  read_rows(&color, &depth, window.min.y, window.max.y);

  out->bit_depth = all_half ? 16 : 32;
  out->format = FileFormat::exr;
  if (purpose == Purpose::depth) {
    out->image = std::move(depth);
  } else {
    out->image = std::move(color);
    out->depth = std::move(depth);
    out->color_layer = color_names.empty() ? std::string() : color_layer;
  }
  out->depth_channel = depth_name;
  return {};
}

// Opens `path`, checks the magic number, and reads; every exception becomes an IoStatus.
IoStatus read_exr_checked(const std::string& path, LoadedImage* out, const ExrReadOptions& options, Purpose purpose,
                          ImageInfo* info_only = nullptr, PackedColor* packed = nullptr) {
  if (out == nullptr) return failure(IoError::invalid_argument, "read_exr: null output");
  *out = LoadedImage{};
  detail::InputFile file;
  if (IoStatus status = file.open(path); !status) return status;

  char magic[4] = {};
  errno = 0;
  const std::size_t got = std::fread(magic, 1, sizeof magic, file.get());
  if (got < sizeof magic && std::ferror(file.get()) != 0) return detail::read_error(path, errno);
  if (got == 0) return failure(IoError::not_this_format, quote_path(path) + " is not an OpenEXR file: it is empty");
  static const unsigned char kMagic[4] = {0x76, 0x2f, 0x31, 0x01};  // 20000630, little-endian
  if (std::memcmp(magic, kMagic, got) != 0) {
    return failure(IoError::not_this_format, quote_path(path) + " is not an OpenEXR file (no EXR magic number)");
  }
  if (got < sizeof magic) {
    return failure(IoError::truncated, quote_path(path) + " is truncated: the file ends inside the EXR magic number");
  }
  std::rewind(file.get());

  FileInput stream(file.get(), path);
  IoStatus status;
  try {
    status = read_exr_file(path, out, options, purpose, &stream, info_only, packed);
  } catch (const std::bad_alloc&) {
    status = failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  } catch (const std::exception& error) {
    if (stream.system_error() != 0) {
      status = detail::read_error(path, stream.system_error());
    } else if (stream.ended()) {
      status = failure(IoError::truncated, quote_path(path) + " is truncated: the file ends before the EXR does (" +
                                               error.what() + ")");
    } else {
      status = failure(IoError::corrupt, quote_path(path) + " is a damaged or unsupported OpenEXR file (OpenEXR: " +
                                             error.what() + ")");
    }
  } catch (...) {
    status = failure(IoError::corrupt, quote_path(path) + " is a damaged OpenEXR file (unknown error)");
  }
  if (!status) {
    *out = LoadedImage{};
    if (packed != nullptr) *packed = PackedColor{};
  }
  return status;
}

// ---- writing ----

Imf::PixelType pixel_type(ExrPixelType type) noexcept { return type == ExrPixelType::half ? Imf::HALF : Imf::FLOAT; }

// Channel c of `color` as a tightly packed half plane (OpenEXR does not convert when writing: a
// slice must have its channel's type).
std::vector<half> to_half(const ColorView& color, int c, int width, int height) {
  std::vector<half> values(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      values[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] =
          half(detail::sample(color, c, x, y));
    }
  }
  return values;
}

IoStatus write_frame(const std::string& path, const Imf::Header& header, const Imf::FrameBuffer& frame, int height);

IoStatus write_exr_file(const std::string& path, const ColorView& color, const FloatPlane* depth,
                        const ExrWriteOptions& options) {
  const bool has_color = color.channels != 0;
  if (!has_color && depth == nullptr) {
    return failure(IoError::invalid_argument, "cannot write " + quote_path(path) + ": neither colour nor depth given");
  }
  if (has_color) {
    if (IoStatus status = detail::check_writable(color); !status) {
      status.message = "cannot write " + quote_path(path) + ": " + status.message;
      return status;
    }
  }
  ColorView depth_view;  // the depth plane as a one-channel view, to share the checks and helpers
  if (depth != nullptr) {
    depth_view = ColorView::planar({*depth});
    if (IoStatus status = detail::check_writable(depth_view); !status) {
      status.message = "cannot write " + quote_path(path) + ": depth: " + status.message;
      return status;
    }
    if (has_color && (depth->width != color.width() || depth->height != color.height())) {
      return failure(IoError::size_mismatch, "cannot write " + quote_path(path) + ": size mismatch: depth is " +
                                                 detail::size_text(depth->width, depth->height) + ", colour is " +
                                                 detail::size_text(color.width(), color.height()));
    }
  }
  const int width = has_color ? color.width() : depth->width;
  const int height = has_color ? color.height() : depth->height;

  std::vector<std::string> names;
  if (has_color) {
    static const char* const kGrey[] = {"Y", "A"};
    static const char* const kRgba[] = {"R", "G", "B", "A"};
    const char* const* components = color.channels <= 2 ? kGrey : kRgba;
    for (int c = 0; c < color.channels; ++c) names.push_back(join_name(options.color_layer, components[c]));
  }
  if (depth != nullptr) {
    if (options.depth_channel.empty()) {
      return failure(IoError::invalid_argument, "cannot write " + quote_path(path) + ": empty depth channel name");
    }
    if (std::find(names.begin(), names.end(), options.depth_channel) != names.end()) {
      return failure(IoError::invalid_argument, "cannot write " + quote_path(path) + ": depth channel name '" +
                                                    options.depth_channel + "' is also a colour channel");
    }
  }

  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  Imf::FrameBuffer frame;
  std::vector<std::vector<half>> halves;  // must outlive writePixels
  halves.reserve(5);
  // OpenEXR only reads from a frame buffer it writes; its Slice takes a char*, hence const_cast.
  auto add = [&](const std::string& name, const ColorView& view, int c, ExrPixelType type) {
    header.channels().insert(name, Imf::Channel(pixel_type(type)));
    if (type == ExrPixelType::half) {
      halves.push_back(to_half(view, c, width, height));
      frame.insert(name, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves.back().data()), sizeof(half),
                                    sizeof(half) * static_cast<std::size_t>(width)));
    } else if (view.layout == ColorLayout::interleaved_rgba) {
      char* base = reinterpret_cast<char*>(const_cast<float*>(view.plane[0].data) + c);
      frame.insert(name, Imf::Slice(Imf::FLOAT, base, 4 * sizeof(float),
                                    static_cast<std::size_t>(view.plane[0].stride) * sizeof(float)));
    } else {
      char* base = reinterpret_cast<char*>(const_cast<float*>(view.plane[c].data));
      frame.insert(name, Imf::Slice(Imf::FLOAT, base, sizeof(float),
                                    static_cast<std::size_t>(view.plane[c].stride) * sizeof(float)));
    }
  };
  for (int c = 0; c < static_cast<int>(names.size()); ++c) add(names[static_cast<std::size_t>(c)], color, c, options.color_type);
  if (depth != nullptr) add(options.depth_channel, depth_view, 0, options.depth_type);

  return write_frame(path, header, frame, height);
}

// Writes `frame` under `header` to `path` (all or nothing, through a ReplacingFile).
IoStatus write_frame(const std::string& path, const Imf::Header& header, const Imf::FrameBuffer& frame, int height) {
  detail::ReplacingFile file;
  if (IoStatus status = file.create(path); !status) return status;
  FileOutput stream(file.get(), path);
  try {
    // The scope ends before the commit: OutputFile's destructor writes the line offset table.
    Imf::OutputFile output(stream, header);
    output.setFrameBuffer(frame);
    output.writePixels(height);
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory writing " + quote_path(path));
  } catch (const std::exception& error) {
    if (stream.failed()) {
      const int code = stream.system_error();
      return failure(IoError::write_failed, "cannot write " + quote_path(path) + ": " +
                                                (code != 0 ? detail::system_error_text(code) : "unknown error"));
    }
    return failure(IoError::write_failed, "cannot write " + quote_path(path) + " (OpenEXR: " + error.what() + ")");
  }
  if (stream.failed()) {  // in the destructor, which reports nothing
    const int code = stream.system_error();
    return failure(IoError::write_failed, "cannot write " + quote_path(path) + ": " +
                                              (code != 0 ? detail::system_error_text(code) : "unknown error"));
  }
  return file.commit();
}

// The first `channels` of rgba16f pixels as half channels, straight from the interleaved buffer.
IoStatus write_exr_packed_file(const std::string& path, const ColorView& packed, int channels,
                               const ExrWriteOptions& options) {
  if (IoStatus status = detail::check_packed(packed, channels, ColorFormat::rgba16f); !status) {
    status.message = "cannot write " + quote_path(path) + ": " + status.message;
    return status;
  }
  const int width = packed.width();
  const int height = packed.height();
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  Imf::FrameBuffer frame;
  // Grey is R (the reader repeats Y into R, G and B); grey + alpha is R and A.
  static const char* const kNames[5][4] = {{}, {"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  static const int kSlot[5][4] = {{}, {0}, {0, 3}, {0, 1, 2}, {0, 1, 2, 3}};
  // OpenEXR only reads from a frame buffer it writes; its Slice takes a char*, hence const_cast.
  char* base = reinterpret_cast<char*>(const_cast<std::uint8_t*>(packed.pixels.data));
  for (int c = 0; c < channels; ++c) {
    const std::string name = join_name(options.color_layer, kNames[channels][c]);
    header.channels().insert(name, Imf::Channel(Imf::HALF));
    frame.insert(name, Imf::Slice(Imf::HALF, base + kSlot[channels][c] * sizeof(half), 4 * sizeof(half),
                                  static_cast<std::size_t>(packed.pixels.stride)));
  }
  return write_frame(path, header, frame, height);
}

// The part of reading outside read_exr_file's own try block can only throw std::bad_alloc (while
// building a message or a name list).
IoStatus read_exr_safely(const std::string& path, LoadedImage* out, const ExrReadOptions& options, Purpose purpose,
                         ImageInfo* info_only = nullptr, PackedColor* packed = nullptr) {
  try {
    return read_exr_checked(path, out, options, purpose, info_only, packed);
  } catch (const std::bad_alloc&) {
    if (out != nullptr) *out = LoadedImage{};
    if (packed != nullptr) *packed = PackedColor{};
    return failure(IoError::out_of_memory, "out of memory reading " + quote_path(path));
  }
}

}  // namespace

namespace detail {

IoStatus read_exr_color(const std::string& path, LoadedImage* out) {
  return read_exr_safely(path, out, ExrReadOptions{}, Purpose::color);
}

IoStatus read_exr_depth(const std::string& path, LoadedImage* out) {
  return read_exr_safely(path, out, ExrReadOptions{}, Purpose::depth);
}

IoStatus read_exr_info(const std::string& path, bool depth, ImageInfo* out) {
  LoadedImage unused;
  return read_exr_safely(path, &unused, ExrReadOptions{}, depth ? Purpose::depth : Purpose::color, out);
}

}  // namespace detail

IoStatus read_exr_packed(const std::string& path, PackedColor* out) {
  if (out == nullptr) return failure(IoError::invalid_argument, "read_exr_packed: null output");
  *out = PackedColor{};
  LoadedImage unused;
  ExrReadOptions options;
  options.depth_channel = "";  // colour only
  return read_exr_safely(path, &unused, options, Purpose::color, nullptr, out);
}

IoStatus write_exr_packed(const std::string& path, const ColorView& packed, int channels, const ExrWriteOptions& options) {
  try {
    return write_exr_packed_file(path, packed, channels, options);
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory writing " + quote_path(path));
  } catch (const std::exception& error) {
    return failure(IoError::write_failed, error.what());
  }
}

IoStatus read_exr(const std::string& path, LoadedImage* out, const ExrReadOptions& options) {
  return read_exr_safely(path, out, options, Purpose::any);
}

IoStatus write_exr(const std::string& path, const ColorView& color, const FloatPlane* depth,
                   const ExrWriteOptions& options) {
  try {
    return write_exr_file(path, color, depth, options);
  } catch (const std::bad_alloc&) {
    return failure(IoError::out_of_memory, "out of memory writing " + quote_path(path));
  } catch (const std::exception& error) {
    return failure(IoError::write_failed, error.what());
  }
}

}  // namespace reproject::io
