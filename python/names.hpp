// Names <-> the library's enums for the Python module (python/): every option given by name
// (method=, hole_fill=, edge=, arch=, encoding=, direction=, depth_format=) is parsed by the
// library's own parser (reproject.hpp, depth.hpp, parallax.hpp, formats.hpp), and an unknown name
// is a ValueError that lists the valid ones, read from the library's name table (to_string), so
// the module never keeps a list of its own.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

namespace reproject::python {

namespace py = pybind11;

// "a, b, c": to_string of the first `count` values of Enum.
template <class Enum>
std::string names_of(int count) {
  std::string names;
  for (int i = 0; i < count; ++i) names += (i ? ", " : "") + std::string(to_string(static_cast<Enum>(i)));
  return names;
}

// The value named `name`, read by the library's `parse`; ValueError "unknown <what> 'x' (a, b, c)"
// otherwise, listing the `count` names of Enum.
template <class Enum>
Enum parse_name(const std::string& name, bool (*parse)(const char*, Enum*), int count, const char* what) {
  Enum value{};
  if (!parse(name.c_str(), &value)) {
    throw py::value_error("unknown " + std::string(what) + " '" + name + "' (" + names_of<Enum>(count) + ")");
  }
  return value;
}

// The names as a tuple, for the module's lists (reproject.methods).
template <class Enum>
py::tuple name_tuple(int count) {
  py::tuple names(count);
  for (int i = 0; i < count; ++i) names[i] = py::str(to_string(static_cast<Enum>(i)));
  return names;
}

}  // namespace reproject::python
