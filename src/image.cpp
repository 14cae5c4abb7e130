#include "reproject/image.hpp"

#include <cstring>
#include <new>

namespace reproject {
namespace {

constexpr std::size_t kRowAlignment = 64;  // bytes: a cache line, and one AVX-512 vector
constexpr std::ptrdiff_t kFloatsPerLine = kRowAlignment / sizeof(float);

}  // namespace

Image::Image(int width, int height, int channels, ColorLayout layout) noexcept {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4) return;
  if (layout == ColorLayout::interleaved_rgba) channels = 4;
  const int floats_per_pixel = layout == ColorLayout::interleaved_rgba ? 4 : 1;
  const int planes = layout == ColorLayout::interleaved_rgba ? 1 : channels;
  const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(width) * floats_per_pixel;
  const std::ptrdiff_t stride = (row + kFloatsPerLine - 1) / kFloatsPerLine * kFloatsPerLine;
  const std::size_t bytes = static_cast<std::size_t>(stride) * height * planes * sizeof(float);
  data_ = static_cast<float*>(::operator new(bytes, std::align_val_t(kRowAlignment), std::nothrow));
  if (data_ == nullptr) return;
  std::memset(data_, 0, bytes);
  width_ = width;
  height_ = height;
  channels_ = channels;
  layout_ = layout;
  stride_ = stride;
}

Image::~Image() {
  if (data_ != nullptr) ::operator delete(data_, std::align_val_t(kRowAlignment));
}

Image::Image(const Image& other) noexcept
    : Image(other.width_, other.height_, other.channels_ == 0 ? 1 : other.channels_, other.layout_) {
  if (data_ != nullptr && other.data_ != nullptr) {
    const int planes = layout_ == ColorLayout::interleaved_rgba ? 1 : channels_;
    std::memcpy(data_, other.data_, static_cast<std::size_t>(plane_size()) * planes * sizeof(float));
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
