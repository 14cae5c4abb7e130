// The parts of the extension module reproject._reproject, one function a file (python/);
// module.cpp calls them in this order.
#pragma once

#include <pybind11/pybind11.h>

#include "reproject/status.hpp"

namespace reproject::python {

namespace py = pybind11;

// A class of the package: py::class_<T>(m, name, extra...) whose __module__ is the package's,
// set before any function names the class in its signature, so that reprs, help() and error
// messages say reproject.Decoder, not the compiled module's reproject._reproject.Decoder.
template <class T, class... Extra>
py::class_<T> public_class(py::module_& m, const char* name, const Extra&... extra) {
  py::class_<T> cls(m, name, extra...);
  cls.attr("__module__") = "reproject";
  return cls;
}

// ValueError with the library's message when `status` is not ok (errors.cpp).
void raise_if_failed(const Status& status);

void bind_queries(py::module_& m);  // queries.cpp: __version__, methods, the arch queries
void bind_models(py::module_& m);   // models.cpp: Decoder, ParallaxModel, StereoCamera
void bind_warp(py::module_& m);     // warp.cpp: warp, warp_pair, Result, PairResult
void bind_stereo(py::module_& m);   // stereo.cpp: the helpers of stereo.hpp
void bind_scenes(py::module_& m);   // scenes.cpp: the built-in ray-cast scenes
void bind_metrics(py::module_ m);   // metrics.cpp: the submodule behind reproject.metrics (PSNR, SSIM)

}  // namespace reproject::python
