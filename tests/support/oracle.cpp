#include "support/oracle.hpp"

#include <cmath>

namespace reproject {
namespace testing {

double oracle_parallax(const OracleRow& row, double x) {
  const int last = static_cast<int>(row.parallax.size()) - 1;
  if (x <= 0.0) return row.parallax[0];
  if (x >= last) return row.parallax[last];
  const int j = static_cast<int>(std::floor(x));
  const double frac = x - j;
  return row.parallax[j] + frac * (row.parallax[j + 1] - row.parallax[j]);
}

OracleRay oracle_ray(const OracleRow& row, double target) {
  const int last = static_cast<int>(row.parallax.size()) - 1;
  auto gap = [&](double x) { return row.s * ((target - x) - oracle_parallax(row, x)); };
  const double x_near = target - row.p_near;
  const double x_far = target - row.p_far;

  OracleRay ray;
  double x_prev = x_near;
  double gap_prev = gap(x_near);
  if (gap_prev < 0.0) {
    ray.x = x_near;
    ray.clipped = true;
    ray.status = PixelStatus::clipped;
    return ray;
  }
  ray.x = x_far;
  if (gap_prev == 0.0) {
    ray.x = x_near;
  } else {
    // g is linear between consecutive integer columns, so test the piece ends in march order.
    const double step = row.s;  // the march goes towards x_far, i.e. in direction s
    double next = step < 0 ? std::ceil(x_near) - 1.0 : std::floor(x_near) + 1.0;
    bool found = false;
    while (!found) {
      const bool past_far = step < 0 ? next <= x_far : next >= x_far;
      const double x = past_far ? x_far : next;
      const double g = gap(x);
      if (g <= 0.0) {
        ray.x = x_prev + (x - x_prev) * gap_prev / (gap_prev - g);
        found = true;
      }
      if (past_far) break;
      x_prev = x;
      gap_prev = g;
      next += step;
    }
  }
  if (ray.x < 0.0 || ray.x > last) {
    ray.status = PixelStatus::outside;
  } else {
    const int j = static_cast<int>(std::floor(ray.x));
    const int j1 = j < last ? j + 1 : j;
    ray.status = row.parallax[j1] - row.parallax[j] > row.hole_threshold ? PixelStatus::hole : PixelStatus::hit;
  }
  return ray;
}

}  // namespace testing
}  // namespace reproject
