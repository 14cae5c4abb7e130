#include "options.hpp"

#include <algorithm>
#include <limits>

#include "arguments.hpp"
#include "names.hpp"

namespace reproject::python {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

DepthDecoder decoder_from(const std::optional<DepthDecoder>& decoder, const std::optional<std::string>& encoding,
                          std::optional<double> near_plane, std::optional<double> far_plane) {
  if (decoder) {
    if (encoding || near_plane || far_plane) {
      throw py::value_error("decoder= cannot be used with encoding=, near= or far=");
    }
    return *decoder;
  }
  const DepthEncoding e = parse_name(encoding.value_or("linear"), parse_encoding, kDepthEncodingCount, "encoding");
  if (e == DepthEncoding::linear || e == DepthEncoding::disparity) {
    if (near_plane || far_plane) {
      throw py::value_error(std::string("near= and far= cannot be used with the ") + to_string(e) + " encoding");
    }
  }
  return DepthDecoder::from_near_far(e, near_plane.value_or(kNaN), far_plane.value_or(kNaN));
}

ParallaxModel model_from(const std::optional<ParallaxModel>& model, const DepthDecoder& decoder,
                         std::optional<double> separation, std::optional<double> convergence,
                         const std::optional<std::string>& direction, int width, bool pair) {
  if (model) {
    if (separation || convergence || direction) {
      throw py::value_error("model= cannot be used with separation=, convergence= or direction=");
    }
    return *model;
  }
  auto direction_named = [](const std::string& name) {
    return parse_name(name, parse_direction, kEyeDirectionCount, "direction");
  };
  if (decoder.encoding() == DepthEncoding::disparity) {
    if (pair) throw py::value_error("a disparity map belongs to one eye: warp_pair needs depth, not disparity");
    if (separation || convergence) {
      throw py::value_error("separation= and convergence= cannot be used with a disparity map (p = -/+ disparity)");
    }
    return ParallaxModel::from_disparity(direction_named(direction.value_or("left-to-right")));
  }
  if (!convergence) throw py::value_error("convergence= is required (or model=, or a disparity map)");
  if (pair && direction) throw py::value_error("warp_pair makes both eyes from the centre: no direction=");
  const EyeDirection d = pair ? EyeDirection::centre_to_right : direction_named(direction.value_or("centre-to-right"));
  // An empty frame (width 0) is valid and writes nothing; its model is made for one column so that
  // separation and convergence are still checked (a stereo model needs a width >= 1).
  return ParallaxModel::from_stereo(separation.value_or(0.03), *convergence, std::max(width, 1), d);
}

Options options_from(const std::string& method, std::optional<double> max_negative_parallax, double hole_threshold,
                     const std::string& hole_fill, const std::string& edge, int guard,
                     std::optional<double> probe_parallax, int march_steps, int secant_max_steps,
                     const std::optional<std::string>& arch, int threads) {
  Options o;
  o.method = parse_name(method, parse_method, kMethodCount, "method");
  if (max_negative_parallax) o.max_negative_parallax = float_argument(*max_negative_parallax, "max_negative_parallax");
  o.hole_threshold = float_argument(hole_threshold, "hole_threshold");
  o.hole_fill = parse_name(hole_fill, parse_hole_fill, kHoleFillCount, "hole_fill");
  o.edge = parse_name(edge, parse_edge_mode, kEdgeModeCount, "edge");
  o.guard = guard;
  if (probe_parallax) o.probe_parallax = float_argument(*probe_parallax, "probe_parallax");
  o.march_steps = march_steps;
  o.secant_max_steps = secant_max_steps;
  if (arch) o.arch = parse_name(*arch, parse_arch, kArchCount, "arch");
  o.threads = threads;
  return o;
}

}  // namespace reproject::python
