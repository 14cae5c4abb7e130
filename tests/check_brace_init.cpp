// Compiled, never run (reproject_brace_init_check, with -Wall -Wextra -Werror): code that brace-
// initialises the public views by their leading members, as code written before a member was
// added does, must build without warnings (GCC's -Wmissing-field-initializers skips members
// that have a default, so every member of SourceView and TargetView has one).
#include "reproject/metrics.hpp"
#include "reproject/reproject.hpp"

namespace {

[[maybe_unused]] reproject::Status warp(const reproject::ColorView& color, const reproject::FloatPlane& depth,
                                        const reproject::MutableColorView& out) {
  const reproject::SourceView source{color, depth};
  const reproject::TargetView target{out};
  return reproject::reproject(source, reproject::DepthDecoder{}, reproject::ParallaxModel{}, reproject::Options{},
                              target);
}

[[maybe_unused]] reproject::Status score(const float* a, const float* b, int width, int height) {
  double value = 0.0;
  return reproject::ssim(reproject::FloatSamples{a, width, height, 1, width}, reproject::FloatSamples{b, width, height, 1, width},
                         reproject::QualityOptions{}, &value);
}

}  // namespace
