// warp's keyword arguments as the library's objects (python/warp.cpp): the depth decoder
// (decoder=, or encoding=, near=, far=), the parallax model (model=, or separation=,
// convergence=, direction=) and Options (method=, hole_fill=, ...). Names are parsed by the
// library (names.hpp); a combination that cannot mean anything is a ValueError that says why.
#pragma once

#include <optional>
#include <string>

#include "reproject/reproject.hpp"

namespace reproject::python {

DepthDecoder decoder_from(const std::optional<DepthDecoder>& decoder, const std::optional<std::string>& encoding,
                          std::optional<double> near_plane, std::optional<double> far_plane);

// `width`: the target's width (a stereo model scales with it); `pair`: for warp_pair, which makes
// both eyes from the centre (no direction=, no disparity map).
ParallaxModel model_from(const std::optional<ParallaxModel>& model, const DepthDecoder& decoder,
                         std::optional<double> separation, std::optional<double> convergence,
                         const std::optional<std::string>& direction, int width, bool pair);

Options options_from(const std::string& method, std::optional<double> max_negative_parallax, double hole_threshold,
                     const std::string& hole_fill, const std::string& edge, int guard,
                     std::optional<double> probe_parallax, int march_steps, int secant_max_steps,
                     const std::optional<std::string>& arch, int threads);

}  // namespace reproject::python
