// Small frames for the analytic tests: one or a few rows whose depth is a function of the column,
// colour that reveals which source x a target pixel was read from, and a runner that fills the
// outputs with sentinels first so a test can tell "written" from "untouched".
//
// Nothing here calls into the kernels except run(): the expected answers of the tests are
// computed from the formulas below (in double), never from the code under test.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "reproject/reproject.hpp"

namespace rptest {

// Values no kernel produces by accident: outputs are pre-filled with them.
constexpr float kUntouched = -7777.25f;
constexpr std::uint8_t kUntouchedStatus = 0xA5;

// Colour of source column j in channel c. Channel 0 is the column index itself, so a target pixel's
// colour is the source x it was interpolated at. The other channels are distinct, non-linear in j,
// so an interpolation between the wrong pair of columns shows up.
float column_color(int channel, int column);
// Linear interpolation of column_color between floor(x) and floor(x)+1, x clamped to
// [0, width - 1] (DESIGN §2), in double.
double color_at(int channel, double x, int width);

// A source frame: planar (1-4 planes) or interleaved RGBA colour holding column_color, and a depth
// plane. All planes use stride = width + pad (interleaved colour: 4 * width + pad); the padding is
// filled with garbage that a kernel must never read into a result.
struct SourceFrame {
  int width = 0;
  int height = 0;
  int channels = 0;
  reproject::ColorLayout layout = reproject::ColorLayout::planar;
  std::ptrdiff_t stride = 0;        // depth and planar colour
  std::ptrdiff_t color_stride = 0;  // planar: == stride; interleaved: 4 * width + pad
  std::vector<float> depth;
  std::vector<float> color[4];  // interleaved: color[0] only

  float& depth_at(int x, int y) { return depth[static_cast<std::size_t>(y * stride + x)]; }
  float depth_at(int x, int y) const { return depth[static_cast<std::size_t>(y * stride + x)]; }
  // Sets every pixel of row y to depth_of(x) (rounded to float once).
  void set_depth_row(int y, const std::function<double(int x)>& depth_of);
  void set_depth(const std::function<double(int x, int y)>& depth_of);

  reproject::SourceView view() const;
};

SourceFrame make_source(int width, int height, int channels = 2,
                        reproject::ColorLayout layout = reproject::ColorLayout::planar, int pad = 0);

// The outputs, all pre-filled with kUntouched / kUntouchedStatus, padding included.
struct TargetFrame {
  int width = 0;
  int height = 0;
  int channels = 0;
  reproject::ColorLayout layout = reproject::ColorLayout::planar;
  std::ptrdiff_t stride = 0;        // depth, source_x, status and planar colour
  std::ptrdiff_t color_stride = 0;  // planar: == stride; interleaved: 4 * width + pad
  std::vector<float> color[4];
  std::vector<float> depth;
  std::vector<float> source_x;
  std::vector<std::uint8_t> status;
  bool want_depth = true;
  bool want_status = true;
  bool want_source_x = true;

  float color_at(int c, int x, int y) const;
  float depth_at(int x, int y) const { return depth[static_cast<std::size_t>(y * stride + x)]; }
  float x_at(int x, int y) const { return source_x[static_cast<std::size_t>(y * stride + x)]; }
  int status_at(int x, int y) const { return status[static_cast<std::size_t>(y * stride + x)]; }

  // True when no element outside [0, width) of any row (nor beyond the last row) was written.
  bool padding_untouched() const;
  // True when nothing at all was written.
  bool all_untouched() const;

  reproject::TargetView view();
};

TargetFrame make_target(int width, int height, int channels = 2,
                        reproject::ColorLayout layout = reproject::ColorLayout::planar, int pad = 3);

struct RunResult {
  reproject::Status status;
  TargetFrame out;
};

// Reprojects `source` into a fresh target of width source.width - 2 * options.guard with the same
// channels and layout (outputs pre-filled with the sentinels).
RunResult run(const SourceFrame& source, const reproject::DepthDecoder& decoder,
        const reproject::ParallaxModel& model, const reproject::Options& options, int pad = 3,
        bool want_depth = true, bool want_status = true, bool want_source_x = true);

// The depth table of DESIGN §3 in double, independent of DepthDecoder's float fast path.
double ref_inverse_depth(reproject::DepthEncoding encoding, double near_plane, double far_plane,
                         double stored);
// Its inverse: the stored value for inverse depth w (w = 0 is infinity).
double ref_stored_value(reproject::DepthEncoding encoding, double near_plane, double far_plane,
                        double inverse_depth);

// Encoding + near/far in one value, so a test can loop over them.
struct Encoding {
  reproject::DepthEncoding encoding = reproject::DepthEncoding::linear;
  double near_plane = 0.0;
  double far_plane = 0.0;

  reproject::DepthDecoder decoder() const;
  double w(double stored) const { return ref_inverse_depth(encoding, near_plane, far_plane, stored); }
  // Stored value for w, rounded to float as a depth buffer holds it.
  float stored(double w) const {
    return static_cast<float>(ref_stored_value(encoding, near_plane, far_plane, w));
  }
  const char* name() const { return reproject::to_string(encoding); }
};

// A row's parallax per column in double, from the float values actually stored: p = a + b w.
std::vector<double> ref_parallax_row(const SourceFrame& source, int y, const Encoding& encoding,
                                     const reproject::ParallaxModel& model);
// The parallax row interpolated at x, clamped to the edge values beyond the row (docs/BEHAVIOUR.md "The exact answer").
double interp_clamped(const std::vector<double>& p, double x);

// The output depth at x (docs/BEHAVIOUR.md, the resolve stage): the stored values interpolated linearly, in
// 1/d then inverted for linear depth (a plane stays a plane); x clamped to the row.
double depth_interp(const SourceFrame& source, int y, const Encoding& encoding, double x);
// A stored depth value of source column `column` of row y, as a double.
inline double stored_depth(const SourceFrame& source, int column, int y) { return source.depth_at(column, y); }

// Collects per-pixel mismatches so a failing test prints a count and the first few cases instead
// of thousands of assertion lines.
class Tally {
 public:
  void fail(const char* format, ...)
#if defined(__GNUC__)
      __attribute__((format(printf, 2, 3)))
#endif
      ;
  int count() const { return count_; }
  const std::string& report() const { return report_; }

 private:
  int count_ = 0;
  std::string report_;
};

}  // namespace rptest
