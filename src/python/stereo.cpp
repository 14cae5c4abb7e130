#include "bindings.hpp"
namespace reproject::python {
void bind_stereo(py::module_&) {}
}  // namespace reproject::python
