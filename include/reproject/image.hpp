// Non-owning views with an explicit row stride (in elements), and an owning image whose rows are
// padded to 64 bytes. Row y of a view starts at data + y * stride.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <type_traits>

#include "reproject/formats.hpp"
#include "reproject/status.hpp"

namespace reproject {

template <class T>
struct PlaneView {
  T* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;  // elements between row starts, >= width (>= 4 * width for interleaved RGBA)

  T* row(int y) const noexcept { return data + static_cast<std::ptrdiff_t>(y) * stride; }
};

using FloatPlane = PlaneView<const float>;    // read-only float plane (depth, a colour channel)
using MutableFloatPlane = PlaneView<float>;   // writable float plane (output depth, source x)
using BytePlane = PlaneView<std::uint8_t>;    // writable byte plane (output status)

enum class ColorLayout : std::uint8_t {
  planar,            // 1..4 separate planes, one float per pixel each
  interleaved_rgba,  // one plane, 4 floats per pixel (R, G, B, A); width counts pixels
};

// Colour as 1-4 float planes, one interleaved float RGBA plane, or one plane of packed RGBA
// pixels in an engine format (ColorFormat). All planes have the same width and height; each
// keeps its own stride.
template <class T>
struct ColorViewT {
  using Byte = typename std::conditional<std::is_const<T>::value, const std::uint8_t, std::uint8_t>::type;
  using Pointer = typename std::conditional<std::is_const<T>::value, const void*, void*>::type;

  ColorLayout layout = ColorLayout::planar;
  int channels = 0;       // planar: 1..4 (number of planes used); interleaved_rgba: 4
  PlaneView<T> plane[4];  // float32: planar: plane[0..channels); interleaved_rgba: plane[0] only
  ColorFormat format = ColorFormat::float32;
  PlaneView<Byte> pixels;  // the packed formats (interleaved_rgba): the pixels' bytes, stride in bytes

  static ColorViewT planar(std::initializer_list<PlaneView<T>> planes) noexcept {
    ColorViewT view;
    for (const PlaneView<T>& p : planes) {
      if (view.channels == 4) break;
      view.plane[view.channels++] = p;
    }
    return view;
  }
  static ColorViewT rgba(T* data, int width, int height, std::ptrdiff_t stride) noexcept {
    ColorViewT view;
    view.layout = ColorLayout::interleaved_rgba;
    view.channels = 4;
    view.plane[0] = PlaneView<T>{data, width, height, stride};
    return view;
  }
  // RGBA pixels in a packed format (rgba8, rgba8_srgb, rgba16f): row y at data + y * stride_bytes.
  static ColorViewT packed(ColorFormat format, Pointer data, int width, int height, std::ptrdiff_t stride_bytes) noexcept {
    ColorViewT view;
    view.layout = ColorLayout::interleaved_rgba;
    view.channels = 4;
    view.format = format;
    view.pixels = PlaneView<Byte>{static_cast<Byte*>(data), width, height, stride_bytes};
    return view;
  }
  int width() const noexcept { return channels > 0 ? (format == ColorFormat::float32 ? plane[0].width : pixels.width) : 0; }
  int height() const noexcept { return channels > 0 ? (format == ColorFormat::float32 ? plane[0].height : pixels.height) : 0; }
};

using ColorView = ColorViewT<const float>;
using MutableColorView = ColorViewT<float>;

// Owning float image: `channels` planes (planar) or one RGBA plane (interleaved), each row padded to
// a multiple of 64 bytes and 64-byte aligned, in the library's memory (reproject/memory.hpp: the
// host's allocator, if set). Allocation failure leaves an empty image (empty() is true); nothing
// throws. Image::create says why it failed.
class Image {
 public:
  Image() noexcept = default;
  Image(int width, int height, int channels = 1, ColorLayout layout = ColorLayout::planar) noexcept;
  // The same, as a Status: invalid_size for a size < 1, channels outside 1..4 or a byte count
  // beyond the address range; out_of_memory when the allocator has none (out is then empty).
  static Status create(int width, int height, int channels, ColorLayout layout, Image* out) noexcept;
  ~Image();
  Image(const Image& other) noexcept;
  Image& operator=(const Image& other) noexcept;
  Image(Image&& other) noexcept;
  Image& operator=(Image&& other) noexcept;

  bool empty() const noexcept { return data_ == nullptr; }
  int width() const noexcept { return width_; }
  int height() const noexcept { return height_; }
  int channels() const noexcept { return channels_; }
  ColorLayout layout() const noexcept { return layout_; }
  std::ptrdiff_t stride() const noexcept { return stride_; }  // floats per row of one plane

  // Plane c (planar) or the interleaved plane (c == 0).
  float* plane_data(int c = 0) noexcept { return data_ + static_cast<std::ptrdiff_t>(c) * plane_size(); }
  const float* plane_data(int c = 0) const noexcept { return data_ + static_cast<std::ptrdiff_t>(c) * plane_size(); }
  FloatPlane plane(int c = 0) const noexcept;
  MutableFloatPlane mutable_plane(int c = 0) noexcept;
  ColorView color() const noexcept;
  MutableColorView mutable_color() noexcept;

 private:
  std::ptrdiff_t plane_size() const noexcept { return stride_ * height_; }
  std::size_t bytes() const noexcept;
  Status allocate_pixels(int width, int height, int channels, ColorLayout layout) noexcept;  // on an empty image
  float* data_ = nullptr;
  int width_ = 0;
  int height_ = 0;
  int channels_ = 0;
  ColorLayout layout_ = ColorLayout::planar;
  std::ptrdiff_t stride_ = 0;
};

}  // namespace reproject
