// The sRGB tables of kernels/color_formats.hpp, built once from the curve in double precision.
#include "kernels/color_formats.hpp"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace reproject::detail {
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
  for (int e = kSrgbLowestScaleExponent; e <= 0; ++e) {
    t.encode_scale[e - kSrgbLowestScaleExponent] = static_cast<float>(255.0 * 1.055 * std::pow(2.0, 5.0 * e / 12.0));
  }
  float threshold[257];
  for (int k = 1; k < 256; ++k) threshold[k] = srgb_threshold(k);
  threshold[256] = 2.0f;  // beyond every clamped value
  int byte = 0;
  for (int b = 0; b < kSrgbBuckets; ++b) {
    const float lowest = float_of_bits((kSrgbFirstBucket + static_cast<std::uint32_t>(b)) << kSrgbBucketShift);
    while (byte < 255 && threshold[byte + 1] <= lowest) ++byte;
    const std::uint32_t bucket_top = kSrgbFirstBucket + static_cast<std::uint32_t>(b);
    const std::uint32_t next = bits_of_float(threshold[byte + 1]);
    const std::int32_t step = (next >> kSrgbBucketShift) == bucket_top ? static_cast<std::int32_t>(next & kSrgbLowMask) : kSrgbNoStep;
    t.bucket[b] = byte << kSrgbStepBits | step;
    // The bucket must not hold a second threshold (kernels/color_formats.hpp); the shift is
    // chosen so that it never does, and this keeps it so.
    const float next_bucket = float_of_bits((kSrgbFirstBucket + static_cast<std::uint32_t>(b) + 1) << kSrgbBucketShift);
    if (byte + 2 <= 256 && threshold[byte + 2] < next_bucket && b + 1 < kSrgbBuckets) std::abort();
  }
  return t;
}

}  // namespace

const SrgbTables& srgb_tables() {
  static const SrgbTables tables = build_srgb_tables();
  return tables;
}

}  // namespace reproject::detail
