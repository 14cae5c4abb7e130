// The sRGB tables of kernels/pixel_formats.hpp, and the public conversions of reproject/formats.hpp
// (the same functions the kernels use).
#include "kernels/pixel_formats.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace reproject {
namespace detail {
namespace {

// The sRGB curve in double (IEC 61966-2-1).
double srgb_decode_exact(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}
double srgb_encode_exact(double linear) {
  return linear <= 0.0031308 ? linear * 12.92 : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

// The smallest positive float whose encoded value reaches byte k's lower rounding bound
// (k - 1/2) / 255: from there on, round(255 encode(x)) >= k.
float srgb_threshold(int k) {
  const double bound = (k - 0.5) / 255.0;
  std::uint32_t bits = bits_of_float(static_cast<float>(srgb_decode_exact(bound)));
  while (255.0 * srgb_encode_exact(float_of_bits(bits - 1)) >= k - 0.5) --bits;
  while (255.0 * srgb_encode_exact(float_of_bits(bits)) < k - 0.5) ++bits;
  return float_of_bits(bits);
}

SrgbTables build_srgb_tables() {
  SrgbTables t{};
  for (int byte = 0; byte < 256; ++byte) t.to_linear[byte] = static_cast<float>(srgb_decode_exact(byte / 255.0));
  float threshold[257];
  for (int k = 1; k < 256; ++k) threshold[k] = srgb_threshold(k);
  threshold[256] = 2.0f;  // beyond every clamped value
  int byte = 0;
  for (int b = 0; b < kSrgbBuckets; ++b) {
    const float lowest = float_of_bits((kSrgbFirstBucket + static_cast<std::uint32_t>(b)) << kSrgbBucketShift);
    while (byte < 255 && threshold[byte + 1] <= lowest) ++byte;
    t.bucket_byte[b] = byte;
    t.bucket_next[b] = threshold[byte + 1];
    // The bucket must not hold a second threshold (kernels/pixel_formats.hpp); the shift is
    // chosen so that it never does, and this keeps it so.
    const float next_bucket = float_of_bits((kSrgbFirstBucket + static_cast<std::uint32_t>(b) + 1) << kSrgbBucketShift);
    if (byte + 2 <= 256 && threshold[byte + 2] < next_bucket && b + 1 < kSrgbBuckets) __builtin_trap();
  }
  return t;
}

}  // namespace

const SrgbTables& srgb_tables() {
  static const SrgbTables tables = build_srgb_tables();
  return tables;
}

}  // namespace detail

namespace {
const char* const kColorFormatNames[kColorFormatCount] = {"float32", "rgba8", "rgba8_srgb", "rgba16f"};
const char* const kDepthFormatNames[kDepthFormatCount] = {"float32", "unorm16", "unorm24_s8", "s8_unorm24",
                                                          "rgba8_packed_linear"};
template <class E, int N>
bool parse_name(const char* const (&names)[N], const char* name, E* out) {
  if (name == nullptr) return false;
  for (int i = 0; i < N; ++i) {
    if (std::strcmp(name, names[i]) == 0) {
      if (out) *out = static_cast<E>(i);
      return true;
    }
  }
  return false;
}
}  // namespace

const char* to_string(ColorFormat format) noexcept {
  const unsigned i = static_cast<unsigned>(format);
  return i < static_cast<unsigned>(kColorFormatCount) ? kColorFormatNames[i] : "unknown";
}
const char* to_string(DepthFormat format) noexcept {
  const unsigned i = static_cast<unsigned>(format);
  return i < static_cast<unsigned>(kDepthFormatCount) ? kDepthFormatNames[i] : "unknown";
}
bool parse_color_format(const char* name, ColorFormat* out) noexcept { return parse_name(kColorFormatNames, name, out); }
bool parse_depth_format(const char* name, DepthFormat* out) noexcept { return parse_name(kDepthFormatNames, name, out); }

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
