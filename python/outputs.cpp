#include "outputs.hpp"

#include "arguments.hpp"
#include "arrays.hpp"

namespace reproject::python {

const char* const kOutputFix =
    "pass the Result of an earlier call on a source of this form and size, or out=None for new arrays";

py::array output_array(const py::object& o, const py::dtype& dtype, const std::vector<py::ssize_t>& shape,
                       const std::string& label, const char* layout) {
  std::string want;
  for (std::size_t i = 0; i < shape.size(); ++i) want += (i ? ", " : "") + std::to_string(shape[i]);
  if (shape.size() == 1) want += ",";
  const std::string dtype_name = py::str(dtype.attr("name"));
  // Anything but an ndarray (None, a list) is refused as it is: a converted copy would be written
  // and thrown away.
  if (!py::isinstance<py::array>(o)) {
    throw py::type_error(label + ": expected a " + dtype_name + " array of shape (" + want + "), got " + short_value(o) +
                         "; " + kOutputFix);
  }
  const py::array a = py::reinterpret_borrow<py::array>(o);
  if (!has_dtype(a, dtype)) {
    throw py::type_error(label + ": expected a " + dtype_name + " array (the source's dtype), got " + describe(a) +
                         "; it takes shape (" + want + "): " + kOutputFix);
  }
  if (!a.writeable()) {
    throw py::value_error(label + ": the array is read-only (" + describe(a) +
                          "); pass a writable one, or out=None for new arrays");
  }
  bool same = a.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t i = 0; same && i < shape.size(); ++i) same = a.shape(static_cast<py::ssize_t>(i)) == shape[i];
  if (!same) {
    if (layout != nullptr) {
      throw py::value_error(label + ": " + describe(a) + " is not " + layout + ", which needs shape (" + want + "); " +
                            kOutputFix);
    }
    throw py::value_error(label + ": expected shape (" + want + "), got " + describe(a) + "; " + kOutputFix);
  }
  return a;
}

}  // namespace reproject::python
