// `scanline` (DESIGN §6): from the near end, one source column a step to the far end; the first
// sample on or behind the surface ends the march and the crossing is intersected linearly with
// the previous sample. Samples sit on every integer column in between, so each bracket lies on
// one linear piece of the surface: exact to rounding inside the allowed range.
#include <cmath>

#include "kernels/frame.hpp"

namespace reproject {
namespace detail {

void search_row_scanline(const Frame& f, RowScratch& scratch) {
  const float* parallax = scratch.parallax;
  const int direction = f.s > 0.0f ? 1 : -1;
  for (int t = 0; t < f.target_width; ++t) {
    const float target = static_cast<float>(t + f.guard);
    const float x_near = target - f.p_near;
    const float x_far = target - f.p_far;
    float x_prev = x_near;
    float gap_prev = ray_gap(f, target, x_near, parallax_at(parallax, x_near));
    scratch.clipped[t] = gap_prev < 0.0f;
    if (gap_prev <= 0.0f) {  // behind at the near end: clipped; exactly on: a hit there
      scratch.source_x[t] = x_near;
      continue;
    }
    // Integer columns strictly between x_near and x_far, in march order, then x_far itself.
    const int first = direction < 0 ? static_cast<int>(std::ceil(x_near)) - 1 : static_cast<int>(std::floor(x_near)) + 1;
    const int end = direction < 0 ? static_cast<int>(std::floor(x_far)) : static_cast<int>(std::ceil(x_far));
    float x = x_far;  // if no sample is behind (only by rounding): the far end
    for (int j = first; direction < 0 ? j > end : j < end; j += direction) {
      const float column = static_cast<float>(j);
      const float gap = ray_gap(f, target, column, parallax[j]);
      if (gap <= 0.0f) {
        x = intersect(x_prev, gap_prev, column, gap);
        goto found;
      }
      x_prev = column;
      gap_prev = gap;
    }
    {
      const float gap = ray_gap(f, target, x_far, parallax_at(parallax, x_far));
      if (gap <= 0.0f) x = intersect(x_prev, gap_prev, x_far, gap);
    }
  found:
    scratch.source_x[t] = x;
  }
}

}  // namespace detail
}  // namespace reproject
