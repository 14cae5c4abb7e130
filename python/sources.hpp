// warp's inputs (python/warp.cpp): the colour and depth arrays as the library's SourceView,
// in place. The dtype says the format (float32, or an engine's buffer: formats.hpp), the shape
// the colour's form (arrays.hpp); packed (H, W, 2|3) float colour is the one layout copied.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <utility>

#include "arrays.hpp"
#include "reproject/formats.hpp"
#include "reproject/reproject.hpp"

namespace reproject::python {

namespace py = pybind11;

// The NumPy dtype of a format's elements.
py::dtype dtype_of(ColorFormat format);
py::dtype dtype_of(DepthFormat format);

// Packed RGBA8 depth is (H, W, 4) bytes; every other depth format one element a pixel.
inline bool depth_has_channels(DepthFormat format) { return format == DepthFormat::rgba8_packed_linear; }

struct Source {
  SourceView view;
  int width = 0;
  int height = 0;
  ColorForm form = ColorForm::plane;
  int channels = 0;
  bool rgba = false;  // colour is interleaved RGBA
  ColorFormat color_format = ColorFormat::float32;
  DepthFormat depth_format = DepthFormat::float32;
  py::object keep;    // the planar copy of packed H x W x 2/3 colour, kept alive for the call
};

// warp's color, depth, color_space=, depth_format= and linear_range= as a Source: TypeError for a
// dtype that fits no format, ValueError for a shape or an argument that does not fit the format.
Source source_from(const py::array& color, const py::array& depth, const std::string& color_space,
                   const std::optional<std::string>& depth_format,
                   const std::optional<std::pair<double, double>>& linear_range);

}  // namespace reproject::python
