// The caller's output arrays (`out=`, a Result of an earlier call), checked before the call with
// messages that name the field, say what it holds, what fits, and the fix (python/targets.cpp).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace reproject::python {

namespace py = pybind11;

// `o`, the array given for the output `label` ("out.color"), when it is a writable NumPy array
// of `dtype` and `shape`; otherwise a TypeError (not an array of that dtype, None included) or a
// ValueError (another shape, read-only) that says what fits. `layout`: the shape's meaning for
// the message, e.g. "laid out like the source colour".
py::array output_array(const py::object& o, const py::dtype& dtype, const std::vector<py::ssize_t>& shape,
                       const std::string& label, const char* layout = nullptr);

// The fix every output message ends with.
extern const char* const kOutputFix;

}  // namespace reproject::python
