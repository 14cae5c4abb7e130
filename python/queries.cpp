// What the library is and has: its version, the names of its methods, and the instruction sets
// (reproject.hpp's arch queries).
#include <pybind11/pybind11.h>

#include <string>

#include "arguments.hpp"
#include "bindings.hpp"
#include "names.hpp"
#include "reproject/reproject.hpp"

namespace reproject::python {

void bind_queries(py::module_& m) {
  m.attr("__version__") = py::str(version());
  m.attr("methods") = name_tuple<Method>(kMethodCount);
  m.attr("arches") = name_tuple<Arch>(kArchCount);
  def_function(m, "arch_supported",
               [](const std::string& arch) { return arch_supported(parse_name(arch, parse_arch, kArchCount, "arch")); },
               py::arg("arch"), "The compiled reproject.arch_supported (documented there).");
  m.def("selected_arch", [] { return std::string(to_string(selected_arch())); },
        "The compiled reproject.selected_arch (documented there).");
}

}  // namespace reproject::python
