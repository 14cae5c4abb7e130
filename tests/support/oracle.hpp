// The test oracle: a plain gather implementation of DESIGN §5's definition, in double precision,
// independent of the kernels (no padded rows, no sweep). The forward sweep (`exact`) must agree
// with it on every pixel: that agreement is the project's ground truth.
#pragma once

#include <vector>

#include "reproject/reproject.hpp"

namespace reproject {
namespace testing {

struct OracleRay {
  double x = 0.0;         // x*, source columns
  bool clipped = false;
  PixelStatus status = PixelStatus::hit;
};

// One row's surface: the decoded, cleaned parallax of each source column, and the ray limits.
struct OracleRow {
  std::vector<double> parallax;
  double s = -1.0;      // sign(b), -1 when b <= 0
  double p_near = 0.0;  // the ray's near end
  double p_far = 0.0;   // and far end (a)
  double hole_threshold = 1.0;
};

// The surface's parallax at a continuous source position, clamped to the edge values beyond the row.
double oracle_parallax(const OracleRow& row, double x);

// The first crossing for target column `target` (source columns, guard included): march from
// x_near = target - p_near towards x_far = target - p_far over every linear piece of
// g(x) = s ((target - x) - P(x)), and classify it as the resolve stage defines.
OracleRay oracle_ray(const OracleRow& row, double target);

}  // namespace testing
}  // namespace reproject
