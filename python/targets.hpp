// warp's outputs (python/warp.cpp): one eye's arrays, new or the caller's (`out=`), as the
// library's TargetView, written in place. New arrays come in the source's dtypes and form; the
// caller's are checked first (outputs.hpp), with messages that name the field and the fix.
#pragma once

#include <pybind11/pybind11.h>

#include "reproject/reproject.hpp"
#include "sources.hpp"

namespace reproject::python {

namespace py = pybind11;

// One eye's outputs (reproject.Result): arrays, or None for an output not written.
struct Result {
  py::object color = py::none();
  py::object depth = py::none();
  py::object status = py::none();
  py::object source_x = py::none();
};

struct PairResult {
  Result left;
  Result right;
};

struct Target {
  TargetView view;
  Result result;
};

// The arrays of `out` (a Result, an array for colour alone, or None: all four new) as a
// TargetView of height x width; `name` ("out", "out_left") labels the messages.
Target target_from(const Source& s, int height, int width, const py::object& out, const char* name);

// The target's width: the source's less the guard band on each side, in 64 bits (2 guard
// overflows int near its limit, and a wrapped width would be allocated). An empty source makes
// an empty target, as the library does. ValueError for a guard that is negative or leaves nothing.
int target_width(const Source& s, int guard);

}  // namespace reproject::python
