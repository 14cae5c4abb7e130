#include "bindings.hpp"

namespace reproject::python {

void raise_if_failed(const Status& status) {
  if (!status.ok()) throw py::value_error(status.message());
}

}  // namespace reproject::python
