#include "bindings.hpp"

namespace reproject::python {

// Out of memory is Python's MemoryError; every other failure a ValueError with the message.
void raise_if_failed(const Status& status) {
  if (status.ok()) return;
  if (status.code() == StatusCode::out_of_memory) {
    PyErr_SetString(PyExc_MemoryError, status.message());
    throw py::error_already_set();
  }
  throw py::value_error(status.message());
}

}  // namespace reproject::python
