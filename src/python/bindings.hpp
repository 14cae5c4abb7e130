// The parts of the Python module, one function per file (src/python/).
#pragma once

#include <pybind11/pybind11.h>

#include "reproject/status.hpp"

namespace reproject::python {

namespace py = pybind11;

// ValueError with the library's message when `status` is not ok.
void raise_if_failed(const Status& status);

void bind_models(py::module_& m);  // models.cpp: Decoder, ParallaxModel, StereoCamera
void bind_core(py::module_& m);    // module.cpp: warp, warp_pair, Result, arch queries
void bind_stereo(py::module_& m);  // stereo.cpp: the helpers of stereo.hpp
void bind_scenes(py::module_& m);  // scenes.cpp: the built-in ray-cast scenes
void bind_metrics(py::module_ m);   // metrics.cpp: the submodule reproject.metrics (PSNR, SSIM)

}  // namespace reproject::python
