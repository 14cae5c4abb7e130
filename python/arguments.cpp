#include "arguments.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "arrays.hpp"

namespace reproject::python {

namespace {

std::string type_name(py::handle value) { return py::str(py::type::handle_of(value).attr("__name__")); }

// At most `limit` characters of `text`, with "..." where it was cut.
std::string cut(const std::string& text, std::size_t limit) {
  return text.size() <= limit ? text : text.substr(0, limit - 3) + "...";
}

std::string replace_name(std::string text, const std::string& name) {
  for (std::size_t at = text.find("NAME"); at != std::string::npos; at = text.find("NAME", at + name.size()))
    text.replace(at, 4, name);
  return text;
}

[[noreturn]] void refuse(const std::string& function, const std::string& what) {
  throw py::type_error(function + "(): " + what);
}

[[noreturn]] void refuse_value(const std::string& function, const Parameter& p, py::handle value) {
  std::string takes, fix;
  p.describe(&takes, &fix);
  refuse(function, p.name + ": got " + short_value(value) + "; it takes " + takes +
                       (fix.empty() ? "" : ": " + replace_name(fix, p.name)));
}

std::string names_of(const std::vector<Parameter>& parameters, bool positional_only) {
  std::string names;
  for (const Parameter& p : parameters) {
    if (positional_only && p.keyword_only) continue;
    names += (names.empty() ? "" : ", ") + p.name;
  }
  return names;
}

// pybind11's refusal of a call's arguments (not a TypeError the function itself raised).
bool refused_by_pybind11(const std::string& message, const py::object& typed) {
  const std::string name = py::str(typed.attr("__name__"));
  return message.rfind(name + "(): incompatible function arguments", 0) == 0 ||
         message.rfind("__init__(): incompatible constructor arguments", 0) == 0;
}

[[noreturn]] void explain(const std::string& function, const std::vector<Parameter>& parameters,
                          const py::args& args, const py::kwargs& kwargs, const std::string& message) {
  std::size_t positional = 0;
  for (const Parameter& p : parameters) positional += p.keyword_only ? 0 : 1;
  if (args.size() > positional) {
    refuse(function, "takes " + std::to_string(positional) + " positional argument" + (positional == 1 ? "" : "s") +
                         (positional > 0 ? " (" + names_of(parameters, true) + ")" : "") + ", got " +
                         std::to_string(args.size()) + (positional < parameters.size() ? "; pass the others by keyword" : ""));
  }
  std::vector<bool> given(parameters.size(), false);
  for (std::size_t i = 0; i < args.size(); ++i) {
    given[i] = true;
    if (!parameters[i].accepts(args[i])) refuse_value(function, parameters[i], args[i]);
  }
  for (const auto& item : kwargs) {
    const std::string key = py::str(item.first);
    const auto at = std::find_if(parameters.begin(), parameters.end(), [&](const Parameter& p) { return p.name == key; });
    if (at == parameters.end()) {
      py::list names;
      for (const Parameter& p : parameters) names.append(p.name);
      const py::list close = py::module_::import("difflib").attr("get_close_matches")(key, names, 1);
      refuse(function, "unexpected keyword argument '" + cut(key, 40) + "'" +
                           (close.empty() ? "; it takes " + names_of(parameters, false)
                                          : "; did you mean '" + py::str(close[0]).cast<std::string>() + "'?"));
    }
    const std::size_t index = static_cast<std::size_t>(at - parameters.begin());
    if (given[index]) refuse(function, key + ": given both by position and by keyword; give it once");
    given[index] = true;
    if (!at->accepts(item.second)) refuse_value(function, *at, item.second);
  }
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    if (given[i] || parameters[i].has_default) continue;
    std::string takes, fix;
    parameters[i].describe(&takes, &fix);
    refuse(function, parameters[i].name + ": missing; it takes " + takes);
  }
  // Not found (pybind11 refused for a reason of its own): its first line, without the call's dump.
  throw py::type_error(cut(message.substr(0, message.find('\n')), 200));
}

}  // namespace

std::string short_value(py::handle value) {
  if (value.is_none()) return "None";
  if (PyBool_Check(value.ptr())) return py::str(value);
  if (PyLong_Check(value.ptr()) || PyFloat_Check(value.ptr()))
    return cut(py::repr(value).cast<std::string>(), 40) + " (" + type_name(value) + ")";
  if (PyUnicode_Check(value.ptr()) || PyBytes_Check(value.ptr()))
    return cut(py::repr(value).cast<std::string>(), 40) + " (" + type_name(value) + ")";
  if (py::isinstance<py::array>(value)) return "a " + describe(py::reinterpret_borrow<py::array>(value));
  if (PyList_Check(value.ptr()) || PyTuple_Check(value.ptr()) || PyDict_Check(value.ptr()) ||
      PyAnySet_Check(value.ptr())) {
    const Py_ssize_t length = PyObject_Length(value.ptr());
    return "a " + type_name(value) + " of " + std::to_string(length) + " item" + (length == 1 ? "" : "s");
  }
  // Anything else by its repr when that is short (a Decoder, a ParallaxModel), else by its type.
  const std::string repr = py::repr(value);
  return repr.size() <= 60 ? repr + " (" + type_name(value) + ")" : "a " + type_name(value) + " object";
}

float float_argument(double value, const char* name) {
  if (std::isfinite(value) && std::fabs(value) > static_cast<double>(std::numeric_limits<float>::max())) {
    char text[160];
    std::snprintf(text, sizeof text, "%s: %g is beyond the float range (magnitude at most %.8g): pass a smaller value",
                  name, value, static_cast<double>(std::numeric_limits<float>::max()));
    throw py::value_error(text);
  }
  return static_cast<float>(value);
}

py::object call_explained(const py::object& typed, const std::string& function,
                          const std::vector<Parameter>& parameters, const py::object* self, const py::args& args,
                          const py::kwargs& kwargs) {
  try {
    return self != nullptr ? typed(*self, *args, **kwargs) : typed(*args, **kwargs);
  } catch (py::error_already_set& error) {
    if (!error.matches(PyExc_TypeError)) throw;
    const std::string message = py::str(error.value());
    if (!refused_by_pybind11(message, typed)) throw;
    explain(function, parameters, args, kwargs, message);
  }
}

std::string docstring_of(const py::object& typed) { return py::str(typed.attr("__doc__")); }

namespace detail {

std::string class_name(const std::type_info& type) {
  const py::detail::type_info* info = py::detail::get_type_info(type);
  if (info == nullptr) return py::detail::clean_type_id(type.name());
  const py::handle cls(reinterpret_cast<PyObject*>(info->type));
  return py::str(cls.attr("__module__")).cast<std::string>() + "." + py::str(cls.attr("__qualname__")).cast<std::string>();
}

std::string qualified(py::handle cls, const char* name) {
  const std::string class_name = py::str(cls.attr("__name__"));
  return name == nullptr ? class_name : class_name + "." + name;
}

}  // namespace detail

}  // namespace reproject::python
