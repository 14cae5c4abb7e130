// The scalar reference of the per-row parallax decode every method shares (docs/DESIGN.md §3–§4)
// and of the near limit's pass over the depth: a stored depth value to its parallax p = a + b w,
// made total for every float. Compiled twice, like every scalar reference (kernels/kernel_table.hpp).
// Its SIMD twin: kernels/decode_simd.hpp.
#include <algorithm>

#include "kernels/depth_formats.hpp"
#include "kernels/kernel_table.hpp"

namespace reproject::detail {
inline namespace REPROJECT_SCALAR_COPY {
namespace {

// The decoded parallax of a stored depth value, made total (docs/BEHAVIOUR.md "Non-finite and
// out-of-range depth"): NaN or farther than infinity -> p_far; nearer than L -> s * L.
template <class Fma>
inline float raw_parallax(const Frame& f, float depth) noexcept {
  return f.affine ? madd<Fma>(f.decode_scale, depth, f.decode_offset) : madd<Fma>(f.b, 1.0f / depth, f.a);
}
inline float clean_parallax(const Frame& f, float p) noexcept {
  const float key = f.s * p;
  if (!(key >= f.key_far)) return f.p_far;  // also NaN
  if (key > f.limit) return f.s * f.limit;
  return p;
}
// + 0: a zero parallax is +0, never -0, so that a pair's left eye (the mirror model) can take the
// right eye's row as 0 - p bit for bit (run_pair_rows); no output depends on the sign of a zero.
template <class Fma>
inline float decode_parallax(const Frame& f, float depth) noexcept {
  return clean_parallax(f, raw_parallax<Fma>(f, depth)) + 0.0f;
}

}  // namespace

template <class Fma>
void decode_parallax_columns(const Frame& f, const std::uint8_t* depth, float* parallax, float* stored, int begin,
                             int end) {
  for (int i = begin; i < end; ++i) {
    const float d = depth_value(f, depth, i);
    parallax[i] = decode_parallax<Fma>(f, d);
    if (stored) stored[i] = d;
  }
}

template <class Fma>
float nearest_key_in_columns(const Frame& f, const std::uint8_t* depth, int begin, int end, float nearest) {
  for (int i = begin; i < end; ++i) nearest = std::max(nearest, f.s * decode_parallax<Fma>(f, depth_value(f, depth, i)));
  return nearest;
}

template void decode_parallax_columns<Fused>(const Frame&, const std::uint8_t*, float*, float*, int, int);
template void decode_parallax_columns<Unfused>(const Frame&, const std::uint8_t*, float*, float*, int, int);
template float nearest_key_in_columns<Fused>(const Frame&, const std::uint8_t*, int, int, float);
template float nearest_key_in_columns<Unfused>(const Frame&, const std::uint8_t*, int, int, float);

}  // inline namespace REPROJECT_SCALAR_COPY
}  // namespace reproject::detail
