// Arguments that pybind11 cannot convert, named (python/). def_function, def_static,
// def_method and def_init bind like m.def, cls.def_static, cls.def and cls.def(py::init(...)),
// with the same signature and docstring; but when pybind11 refuses the arguments of a call (a list
// where an array goes, a string for a number, an int beyond 32 bits, an unknown keyword), the
// TypeError names the argument, shows its value briefly and says what it takes and what to pass,
// on one line:
//   warp(): convergence: got '3.5' (str); it takes a number: pass a float
// instead of pybind11's list of signatures and the repr of every argument (which, for a list of
// pixels, runs to megabytes). A call whose arguments convert costs one more dispatch.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

namespace reproject::python {

namespace py = pybind11;

// A parameter of a bound function, for messages.
struct Parameter {
  std::string name;
  bool keyword_only = false;
  bool has_default = false;
  bool (*accepts)(py::handle value) = nullptr;  // pybind11's conversion would take it
  // What it takes ("a number") and what to pass ("pass a float"); NAME in `fix` stands for the
  // parameter's name. Filled when a message needs them (class names are known by then).
  void (*describe)(std::string* takes, std::string* fix) = nullptr;
};
using Parameters = std::shared_ptr<const std::vector<Parameter>>;

// A value in a few words: "'3.5' (str)", "a list of 8 items", "float64 array of shape (2, 3)".
std::string short_value(py::handle value);

// `value` as a float. A finite value beyond the float range is a ValueError naming `name`
// (converted, it would become inf, and the library would report an inf the caller never passed);
// infinities and NaN pass as they are, for the library to judge.
float float_argument(double value, const char* name);

// Calls `typed` (pybind11's own function, with every conversion) with `args` and `kwargs`; when
// pybind11 refuses them, raises a TypeError that names the argument at fault (an unknown keyword,
// one given twice, one missing, too many positional ones, or one whose type does not convert), or
// pybind11's first line when none is found. Anything else the call raises passes unchanged.
py::object call_explained(const py::object& typed, const std::string& function,
                          const std::vector<Parameter>& parameters, const py::object* self, const py::args& args,
                          const py::kwargs& kwargs);

// The docstring pybind11 gave `typed` (its signature, then the docs).
std::string docstring_of(const py::object& typed);

namespace detail {

// The parameter types of a callable: a function pointer, a member function pointer (without the
// object, which pybind11 passes as self) or a lambda.
template <class... A>
struct Types {
  using Tuple = std::tuple<A...>;
};
template <class F>
struct Params : Params<decltype(&F::operator())> {};
template <class R, class... A>
struct Params<R (*)(A...)> : Types<A...> {};
template <class R, class... A>
struct Params<R (*)(A...) noexcept> : Types<A...> {};
template <class R, class C, class... A>
struct Params<R (C::*)(A...)> : Types<A...> {};
template <class R, class C, class... A>
struct Params<R (C::*)(A...) const> : Types<A...> {};
template <class R, class C, class... A>
struct Params<R (C::*)(A...) noexcept> : Types<A...> {};
template <class R, class C, class... A>
struct Params<R (C::*)(A...) const noexcept> : Types<A...> {};

template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};
template <class T>
struct is_pair : std::false_type {};
template <class A, class B>
struct is_pair<std::pair<A, B>> : std::true_type {};

// The name Python knows a bound class by ("reproject.Decoder").
std::string class_name(const std::type_info& type);

template <class T>
void describe(std::string* takes, std::string* fix) {
  using U = std::decay_t<T>;
  if constexpr (std::is_same_v<U, bool>) {
    *takes = "True or False";
    *fix = "pass a bool";
  } else if constexpr (std::is_integral_v<U>) {
    *takes = "an integer in " + std::to_string(std::numeric_limits<U>::min()) + ".." +
             std::to_string(std::numeric_limits<U>::max());
    *fix = "pass an int in that range";
  } else if constexpr (std::is_floating_point_v<U>) {
    *takes = "a number";
    *fix = "pass a float";
  } else if constexpr (std::is_same_v<U, std::string>) {
    *takes = "a string";
    *fix = "pass a str";
  } else if constexpr (std::is_base_of_v<py::array, U>) {
    *takes = "a NumPy array";
    *fix = "pass numpy.asarray(NAME) with the dtype it needs";
  } else if constexpr (is_optional<U>::value) {
    describe<typename U::value_type>(takes, fix);
    *takes = "None or " + *takes;
  } else if constexpr (is_pair<U>::value) {
    *takes = "a pair of numbers";
    *fix = "pass a tuple of two floats";
  } else if constexpr (std::is_base_of_v<py::handle, U>) {
    *takes = "any object";
    *fix = "";
  } else {
    *takes = "a " + class_name(typeid(U));
    *fix = "pass a " + class_name(typeid(U));
  }
}

template <class T>
bool accepts(py::handle value) {
  py::detail::make_caster<T> caster;
  return caster.load(value, true);
}

template <class Tuple, std::size_t... I>
std::vector<Parameter> parameters_of(std::index_sequence<I...>) {
  return {Parameter{"", false, false, &accepts<std::tuple_element_t<I, Tuple>>,
                    &describe<std::tuple_element_t<I, Tuple>>}...};
}

// Names, defaults and the keyword-only marker from pybind11's extras, in order.
struct Named {
  const char* name;
  bool has_default;
};
inline void collect(std::vector<Named>* names, int*, const py::arg& a) { names->push_back(Named{a.name, false}); }
inline void collect(std::vector<Named>* names, int*, const py::arg_v& a) { names->push_back(Named{a.name, true}); }
inline void collect(std::vector<Named>* names, int* keyword_only_from, const py::kw_only&) {
  *keyword_only_from = static_cast<int>(names->size());
}
template <class T, std::enable_if_t<!std::is_base_of_v<py::arg, T> && !std::is_same_v<T, py::kw_only>, int> = 0>
void collect(std::vector<Named>*, int*, const T&) {}

// The parameters of `Func` that the extras name: its last ones (a method's object comes first
// and is self, which has no name).
template <class Func, class... Extra>
Parameters describe_parameters(const Extra&... extra) {
  using Tuple = typename Params<std::decay_t<Func>>::Tuple;
  const std::vector<Parameter> all = parameters_of<Tuple>(std::make_index_sequence<std::tuple_size_v<Tuple>>{});
  std::vector<Named> names;
  int keyword_only_from = -1;
  (collect(&names, &keyword_only_from, extra), ...);
  const std::size_t first = all.size() >= names.size() ? all.size() - names.size() : 0;
  std::vector<Parameter> named(all.begin() + static_cast<std::ptrdiff_t>(first), all.end());
  for (std::size_t i = 0; i < named.size() && i < names.size(); ++i) {
    named[i].name = names[i].name;
    named[i].has_default = names[i].has_default;
    named[i].keyword_only = keyword_only_from >= 0 && static_cast<int>(i) >= keyword_only_from;
  }
  return std::make_shared<const std::vector<Parameter>>(std::move(named));
}

std::string qualified(py::handle cls, const char* name);

}  // namespace detail

template <class Func, class... Extra>
void def_function(py::module_& m, const char* name, Func&& f, const Extra&... extra) {
  const Parameters parameters = detail::describe_parameters<Func>(extra...);
  const py::object typed = py::cpp_function(std::forward<Func>(f), py::name(name), extra...);
  const std::string doc = docstring_of(typed), function = name;
  py::options options;
  options.disable_function_signatures();
  m.def(
      name,
      [typed, parameters, function](const py::args& args, const py::kwargs& kwargs) {
        return call_explained(typed, function, *parameters, nullptr, args, kwargs);
      },
      doc.c_str());
}

template <class Class, class Func, class... Extra>
void def_static(Class& cls, const char* name, Func&& f, const Extra&... extra) {
  const Parameters parameters = detail::describe_parameters<Func>(extra...);
  const py::object typed = py::cpp_function(std::forward<Func>(f), py::name(name), extra...);
  const std::string doc = docstring_of(typed), function = detail::qualified(cls, name);
  py::options options;
  options.disable_function_signatures();
  cls.def_static(
      name,
      [typed, parameters, function](const py::args& args, const py::kwargs& kwargs) {
        return call_explained(typed, function, *parameters, nullptr, args, kwargs);
      },
      doc.c_str());
}

template <class Class, class Func, class... Extra>
void def_method(Class& cls, const char* name, Func&& f, const Extra&... extra) {
  const Parameters parameters = detail::describe_parameters<Func>(extra...);
  const py::object typed = py::cpp_function(std::forward<Func>(f), py::name(name), py::is_method(cls), extra...);
  const std::string doc = docstring_of(typed), function = detail::qualified(cls, name);
  py::options options;
  options.disable_function_signatures();
  cls.def(
      name,
      [typed, parameters, function](const py::object& self, const py::args& args, const py::kwargs& kwargs) {
        return call_explained(typed, function, *parameters, &self, args, kwargs);
      },
      doc.c_str());
}

// The constructor, from a factory that returns the class by value.
template <class Class, class Factory, class... Extra>
void def_init(Class& cls, Factory&& factory, const Extra&... extra) {
  using T = typename Class::type;
  const Parameters parameters = detail::describe_parameters<Factory>(extra...);
  const std::string function = detail::qualified(cls, nullptr);
  const py::object typed = py::cpp_function(std::forward<Factory>(factory), py::name(function.c_str()), extra...);
  const std::string doc = docstring_of(typed);
  py::options options;
  options.disable_function_signatures();
  cls.def(py::init([typed, parameters, function](const py::args& args, const py::kwargs& kwargs) {
            return call_explained(typed, function, *parameters, nullptr, args, kwargs).template cast<T>();
          }),
          doc.c_str());
}

}  // namespace reproject::python
