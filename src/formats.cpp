// The public side of reproject/formats.hpp: the formats' sizes, and the conversions the
// kernels use (kernels/codes.hpp, kernels/color_formats.hpp, kernels/depth_formats.hpp), so that
// callers and tests convert exactly as the kernels do.
#include "reproject/formats.hpp"

#include <limits>

#include "kernels/color_formats.hpp"
#include "kernels/depth_formats.hpp"

namespace reproject {

int bytes_per_pixel(ColorFormat format) noexcept {
  switch (format) {
    case ColorFormat::rgba8:
    case ColorFormat::rgba8_srgb: return 4;
    case ColorFormat::rgba16f: return 8;
    case ColorFormat::float32: break;
  }
  return 0;
}
int bytes_per_pixel(DepthFormat format) noexcept {
  switch (format) {
    case DepthFormat::unorm16: return 2;
    case DepthFormat::float32:
    case DepthFormat::unorm24_s8:
    case DepthFormat::s8_unorm24:
    case DepthFormat::rgba8_packed_linear: return 4;
  }
  return 0;
}

namespace formats {

float half_to_float(std::uint16_t half) noexcept { return detail::half_to_float(half); }
std::uint16_t float_to_half(float value) noexcept { return detail::float_to_half(value); }
float srgb_to_linear(std::uint8_t byte) noexcept { return detail::srgb_tables().to_linear[byte]; }
std::uint8_t linear_to_srgb(float linear) noexcept { return detail::srgb_encode(detail::srgb_tables(), linear); }

float unorm_to_float(std::uint32_t code, int bits) noexcept {
  if (bits < 1 || bits > 24) return std::numeric_limits<float>::quiet_NaN();
  return detail::unorm_value(code, static_cast<float>((1u << bits) - 1u));
}
std::uint32_t float_to_unorm(float value, int bits) noexcept {
  if (bits < 1 || bits > 24) return 0;
  return detail::unorm_code(value, static_cast<float>((1u << bits) - 1u));
}
float packed_linear_value(const std::uint8_t rgb[3]) noexcept {
  const std::uint32_t word = rgb[0] | (static_cast<std::uint32_t>(rgb[1]) << 8) | (static_cast<std::uint32_t>(rgb[2]) << 16);
  return detail::unorm_value(detail::packed_code(word), detail::kPackedMax);
}
void pack_linear_value(float v, std::uint8_t rgb[3]) noexcept {
  const std::uint32_t word = detail::packed_word(detail::packed_code_of(v));
  rgb[0] = static_cast<std::uint8_t>(word);
  rgb[1] = static_cast<std::uint8_t>(word >> 8);
  rgb[2] = static_cast<std::uint8_t>(word >> 16);
}

}  // namespace formats
}  // namespace reproject
