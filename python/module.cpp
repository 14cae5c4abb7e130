// The compiled part of the Python package `reproject` (python/reproject/): the extension
// module reproject._reproject, pybind11 over the library, one part a file. The package's
// __init__.py gives its functions their signatures and documentation, and __init__.pyi its types.
#include <pybind11/pybind11.h>

#include "bindings.hpp"

PYBIND11_MODULE(_reproject, m) {
  namespace python = reproject::python;
  m.doc() = "The compiled part of the package reproject: use the package (import reproject).";
  python::bind_queries(m);
  python::bind_models(m);
  python::bind_warp(m);
  python::bind_stereo(m);
  python::bind_scenes(m);
  python::bind_metrics(m.def_submodule("metrics", "The compiled part of reproject.metrics."));
}
