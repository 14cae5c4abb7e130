// The C test's reference: the same frame through the C++ API directly (reproject.hpp), so that
// test_c_api.c can compare the C interface's output with it bit for bit. Written apart from
// src/c_api.cpp on purpose: it builds the C++ views from the raw pointers itself.
#include <cstdint>

#include "reproject/reproject.hpp"

extern "C" int reference_warp(const float* const* color_planes, int channels, const float* depth, int width,
                              int height, double near_plane, double far_plane, int method, int arch,
                              float* const* out_color, float* out_depth, std::uint8_t* out_status,
                              float* out_source_x, int pair, float* const* left_color) {
  using namespace reproject;
  SourceView source;
  source.color.channels = channels;
  TargetView target;
  target.color.channels = channels;
  TargetView left = target;
  for (int c = 0; c < channels; ++c) {
    source.color.plane[c] = FloatPlane{color_planes[c], width, height, width};
    target.color.plane[c] = MutableFloatPlane{out_color[c], width, height, width};
    if (pair) left.color.plane[c] = MutableFloatPlane{left_color[c], width, height, width};
  }
  source.depth = FloatPlane{depth, width, height, width};
  target.depth = MutableFloatPlane{out_depth, width, height, width};
  target.status = BytePlane{out_status, width, height, width};
  target.source_x = MutableFloatPlane{out_source_x, width, height, width};
  Options options;
  options.method = static_cast<Method>(method);
  options.arch = static_cast<Arch>(arch);
  const DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::standard, near_plane, far_plane);
  if (pair) {
    const ParallaxModel model = StereoCamera{0.03, 4.0}.parallax(width, EyeDirection::centre_to_right);
    return reproject_pair(source, decoder, model, options, left, target).ok() ? 0 : 1;
  }
  const ParallaxModel model = StereoCamera{0.03, 4.0}.parallax(width, EyeDirection::left_to_right);
  return reproject::reproject(source, decoder, model, options, target).ok() ? 0 : 1;
}
