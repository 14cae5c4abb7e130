// The C test's reference: the same frame through the C++ API directly (reproject.hpp), so that
// test_c_api.c can compare the C interface's output with it bit for bit. Written apart from
// src/c_api_*.cpp on purpose: it builds the C++ views from the raw pointers itself.
#include <cstdint>
#include <type_traits>

#include "c_reference.h"
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

// The engine formats: the same frame through the C++ API's views, from the raw pointers of a RefView.

namespace {

using namespace reproject;

// The colour and depth of a SourceView or TargetView (View) from a RefView.
template <class View>
bool views_of(const RefView& r, int width, int height, View* v) {
  using Float = typename std::remove_pointer<decltype(v->depth.data)>::type;  // const float or float
  using Color = decltype(v->color);
  ColorFormat cf;
  DepthFormat df;
  if (!parse_color_format(r.color_format, &cf) || !parse_depth_format(r.depth_format, &df)) return false;
  if (cf == ColorFormat::float32) {
    const std::ptrdiff_t floats = r.color_stride / 4;
    v->color = Color::planar({PlaneView<Float>{static_cast<Float*>(r.color[0]), width, height, floats},
                              PlaneView<Float>{static_cast<Float*>(r.color[1]), width, height, floats},
                              PlaneView<Float>{static_cast<Float*>(r.color[2]), width, height, floats}});
  } else {
    v->color = Color::packed(cf, r.color[0], width, height, r.color_stride);
  }
  if (r.depth == nullptr) return true;
  if (r.depth_plane) {
    v->depth = PlaneView<Float>{static_cast<Float*>(r.depth), width, height, r.depth_stride / 4};
  } else {
    v->depth_buffer = decltype(v->depth_buffer)::of(df, r.depth, width, height, r.depth_stride);
    v->depth_buffer.linear_near = r.linear_near;
    v->depth_buffer.linear_far = r.linear_far;
  }
  return true;
}

bool target_of(const RefView& r, int width, int height, TargetView* t) {
  if (!views_of(r, width, height, t)) return false;
  t->status = BytePlane{r.status, width, height, width};
  t->source_x = MutableFloatPlane{r.source_x, width, height, width};
  return true;
}

void serial_for(void*, int count, void (*task)(void*, int), void* task_context) {
  for (int i = 0; i < count; ++i) task(task_context, i);
}

}  // namespace

extern "C" int reference_warp_buffers(const RefView* source, const RefView* left, const RefView* right, int width,
                                      int height, int linear_decoder, double near_plane, double far_plane,
                                      int method, int arch, int threads) {
  SourceView s;
  TargetView l, t;
  if (!views_of(*source, width, height, &s) || !target_of(*right, width, height, &t) ||
      (left != nullptr && !target_of(*left, width, height, &l)))
    return 2;
  Options options;
  options.method = static_cast<Method>(method);
  options.arch = static_cast<Arch>(arch);
  options.threads = threads;
  const DepthDecoder decoder = linear_decoder ? DepthDecoder::linear()
                                              : DepthDecoder::from_near_far(DepthEncoding::standard, near_plane, far_plane);
  const ParallelFor jobs{nullptr, serial_for};
  Status status;
  if (left != nullptr) {
    const ParallaxModel model = StereoCamera{0.03, 4.0}.parallax(width, EyeDirection::centre_to_right);
    status = threads > 0 ? reproject_pair(s, decoder, model, options, l, t)
                         : reproject_pair(s, decoder, model, options, l, t, jobs);
  } else {
    const ParallaxModel model = StereoCamera{0.03, 4.0}.parallax(width, EyeDirection::left_to_right);
    status = threads > 0 ? reproject::reproject(s, decoder, model, options, t)
                         : reproject::reproject(s, decoder, model, options, t, jobs);
  }
  return status.ok() ? 0 : 1;
}
