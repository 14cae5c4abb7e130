// Internal: the reason a factory refused its parameters, carried in a quiet NaN's payload.
// DepthDecoder and ParallaxModel hold only their floats (the public headers are the contract), so
// an invalid one stores NaN, which no caller can mistake for a plausible value, and its validate()
// reads back from that NaN which parameter was wrong.
#pragma once

#include <cstdint>
#include <cstring>

namespace reproject::detail {

// A quiet NaN (exponent all ones, top mantissa bit set) with `reason` in the low payload bits.
template <class Reason>
float nan_with_reason(Reason reason) noexcept {
  const std::uint32_t bits = 0x7FC00000u | static_cast<std::uint32_t>(reason);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// The reason a nan_with_reason() value carries, or Reason::none for any other value (`last` is
// the enum's last reason).
template <class Reason>
Reason reason_in(float value, Reason last) noexcept {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  if ((bits & 0x7FC00000u) != 0x7FC00000u) return Reason::none;
  const std::uint32_t code = bits & 0xFFu;
  return code <= static_cast<std::uint32_t>(last) ? static_cast<Reason>(code) : Reason::none;
}

}  // namespace reproject::detail
