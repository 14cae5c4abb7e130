#include "reproject/image.hpp"

#include <cstdint>
#include <cstring>
#include <limits>
#include <new>

#include "src/memory.hpp"

namespace reproject {
namespace {

constexpr std::size_t kRowAlignment = 64;  // bytes: a cache line, and one AVX-512 vector
constexpr std::ptrdiff_t kFloatsPerLine = kRowAlignment / sizeof(float);

}  // namespace

Image::Image(int width, int height, int channels, ColorLayout layout) noexcept {
  (void)allocate_pixels(width, height, channels, layout);
}

Status Image::create(int width, int height, int channels, ColorLayout layout, Image* out) noexcept {
  if (out == nullptr) return Status(StatusCode::null_pointer, "Image::create: null output");
  Image image;
  Status status = image.allocate_pixels(width, height, channels, layout);
  *out = static_cast<Image&&>(image);
  return status;
}

Status Image::allocate_pixels(int width, int height, int channels, ColorLayout layout) noexcept {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4)
    return Status(StatusCode::invalid_size, "Image::create: %dx%d with %d channels (sizes >= 1, channels 1..4)", width,
                  height, channels);
  if (layout == ColorLayout::interleaved_rgba) channels = 4;
  const int floats_per_pixel = layout == ColorLayout::interleaved_rgba ? 4 : 1;
  const int planes = layout == ColorLayout::interleaved_rgba ? 1 : channels;
  const std::uint64_t row = static_cast<std::uint64_t>(width) * floats_per_pixel;
  const std::uint64_t stride = (row + kFloatsPerLine - 1) / kFloatsPerLine * kFloatsPerLine;
  // Below 2^31 * 4 * 16 floats a row, times 2^31 rows, times 4 planes: checked, not trusted.
  const std::uint64_t floats = stride * static_cast<std::uint64_t>(height);
  if (floats / static_cast<std::uint64_t>(height) != stride ||
      floats > std::numeric_limits<std::size_t>::max() / sizeof(float) / static_cast<std::uint64_t>(planes) ||
      floats > static_cast<std::uint64_t>(std::numeric_limits<std::ptrdiff_t>::max()))
    return Status(StatusCode::invalid_size, "Image::create: %dx%d with %d planes is beyond the address range", width,
                  height, planes);
  const std::size_t bytes = static_cast<std::size_t>(floats) * static_cast<std::size_t>(planes) * sizeof(float);
  float* data = static_cast<float*>(detail::allocate(bytes, kRowAlignment));
  if (data == nullptr) return detail::out_of_memory("Image::create", "the image's pixels");
  std::memset(data, 0, bytes);
  data_ = data;
  width_ = width;
  height_ = height;
  channels_ = channels;
  layout_ = layout;
  stride_ = static_cast<std::ptrdiff_t>(stride);
  return Status();
}

std::size_t Image::bytes() const noexcept {
  const int planes = layout_ == ColorLayout::interleaved_rgba ? 1 : channels_;
  return static_cast<std::size_t>(plane_size()) * static_cast<std::size_t>(planes) * sizeof(float);
}

Image::~Image() { detail::deallocate(data_, bytes(), kRowAlignment); }

Image::Image(const Image& other) noexcept
    : Image(other.width_, other.height_, other.channels_ == 0 ? 1 : other.channels_, other.layout_) {
  if (data_ != nullptr && other.data_ != nullptr) {
    const int planes = layout_ == ColorLayout::interleaved_rgba ? 1 : channels_;
    std::memcpy(data_, other.data_, static_cast<std::size_t>(plane_size()) * static_cast<std::size_t>(planes) * sizeof(float));
  }
}

Image& Image::operator=(const Image& other) noexcept {
  if (this != &other) *this = Image(other);
  return *this;
}

Image::Image(Image&& other) noexcept
    : data_(other.data_), width_(other.width_), height_(other.height_), channels_(other.channels_),
      layout_(other.layout_), stride_(other.stride_) {
  other.data_ = nullptr;
  other.width_ = other.height_ = other.channels_ = 0;
  other.stride_ = 0;
}

Image& Image::operator=(Image&& other) noexcept {
  if (this != &other) {
    this->~Image();
    new (this) Image(static_cast<Image&&>(other));
  }
  return *this;
}

FloatPlane Image::plane(int c) const noexcept {
  return FloatPlane{plane_data(c), width_, height_, stride_};
}

MutableFloatPlane Image::mutable_plane(int c) noexcept {
  return MutableFloatPlane{plane_data(c), width_, height_, stride_};
}

ColorView Image::color() const noexcept {
  if (layout_ == ColorLayout::interleaved_rgba) return ColorView::rgba(data_, width_, height_, stride_);
  ColorView view;
  view.channels = channels_;
  for (int c = 0; c < channels_; ++c) view.plane[c] = plane(c);
  return view;
}

MutableColorView Image::mutable_color() noexcept {
  if (layout_ == ColorLayout::interleaved_rgba) return MutableColorView::rgba(data_, width_, height_, stride_);
  MutableColorView view;
  view.channels = channels_;
  for (int c = 0; c < channels_; ++c) view.plane[c] = mutable_plane(c);
  return view;
}

}  // namespace reproject
