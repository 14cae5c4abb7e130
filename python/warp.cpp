// warp and warp_pair (reproject.hpp's reproject and reproject_pair) over NumPy arrays, and their
// Result classes. The arrays are passed to the library as views (sources.hpp, targets.hpp); the
// library's own validation decides what is valid, and its message becomes a ValueError. The GIL
// is released while the kernels run, and Ctrl-C stops a call (interrupt.hpp). The arguments are
// documented once, on the package's wrappers (python/reproject/__init__.py).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <optional>
#include <string>
#include <utility>

#include "arguments.hpp"
#include "bindings.hpp"
#include "counters.hpp"
#include "interrupt.hpp"
#include "options.hpp"
#include "sources.hpp"
#include "targets.hpp"

namespace reproject::python {

namespace {

CallCounter& warp_calls() {
  static CallCounter counter;
  return counter;
}

// Runs `work` with the GIL released, counted: on the main thread, Ctrl-C (any signal handler that
// raises) sets `cancel` and raises KeyboardInterrupt within a poll and a block of rows.
template <class Work>
Status run_without_gil(Work&& work, std::atomic<bool>& cancel) {
  return run_interruptible([&work] { return warp_calls().count(work); }, cancel);
}

#define REPROJECT_WARP_PARAMETERS                                                                                 \
  const std::string &color_space, const std::optional<std::string>&depth_format,                                  \
      const std::optional<std::pair<double, double>>&linear_range, const std::optional<std::string>&encoding,     \
      std::optional<double> near_plane, std::optional<double> far_plane,                                          \
      const std::optional<DepthDecoder>&decoder, std::optional<double> separation,                                \
      std::optional<double> convergence, const std::optional<std::string>&direction,                              \
      const std::optional<ParallaxModel>&model, const std::string &method,                                        \
      std::optional<double> max_negative_parallax, double hole_threshold, const std::string &hole_fill,           \
      const std::string &edge, int guard, std::optional<double> probe_parallax, int march_steps,                  \
      int secant_max_steps, const std::optional<std::string>&arch, int threads
// The same parameters passed on, in their order.
#define REPROJECT_WARP_ARGUMENTS                                                                                  \
  color_space, depth_format, linear_range, encoding, near_plane, far_plane, decoder, separation, convergence,     \
      direction, model, method, max_negative_parallax, hole_threshold, hole_fill, edge, guard, probe_parallax,    \
      march_steps, secant_max_steps, arch, threads

// What warp and warp_pair read from their arguments alike: the source, the decoder, the options
// (with a cancel flag of the call's own) and the model (`pair`: the centre-to-right eye's).
struct WarpCall {
  Source source;
  DepthDecoder decoder;
  Options options;
  int width = 0;
  ParallaxModel model;
  std::atomic<bool> cancel{false};

  WarpCall(const py::array& color, const py::array& depth, REPROJECT_WARP_PARAMETERS, bool pair)
      : source(source_from(color, depth, color_space, depth_format, linear_range)),
        decoder(decoder_from(decoder, encoding, near_plane, far_plane)) {
    options = options_from(method, max_negative_parallax, hole_threshold, hole_fill, edge, guard, probe_parallax,
                           march_steps, secant_max_steps, arch, threads);
    options.cancel = &cancel;
    width = target_width(source, guard);
    this->model = model_from(model, this->decoder, separation, convergence, direction, width, pair);
  }
};

Result warp(const py::array& color, const py::array& depth, REPROJECT_WARP_PARAMETERS, const py::object& out) {
  WarpCall c(color, depth, REPROJECT_WARP_ARGUMENTS, false);
  Target t = target_from(c.source, c.source.height, c.width, out, "out");
  raise_if_failed(run_without_gil(
      [&] { return reproject::reproject(c.source.view, c.decoder, c.model, c.options, t.view); }, c.cancel));
  return t.result;
}

PairResult warp_pair(const py::array& color, const py::array& depth, REPROJECT_WARP_PARAMETERS,
                     const py::object& out_left, const py::object& out_right) {
  WarpCall c(color, depth, REPROJECT_WARP_ARGUMENTS, true);
  Target left = target_from(c.source, c.source.height, c.width, out_left, "out_left");
  Target right = target_from(c.source, c.source.height, c.width, out_right, "out_right");
  raise_if_failed(run_without_gil(
      [&] { return reproject::reproject_pair(c.source.view, c.decoder, c.model, c.options, left.view, right.view); },
      c.cancel));
  return PairResult{left.result, right.result};
}

#undef REPROJECT_WARP_PARAMETERS
#undef REPROJECT_WARP_ARGUMENTS

// Adds the keyword arguments shared by warp and warp_pair, in the same order as the parameters
// (and as the package's wrappers: tests/python/test_package.py compares them).
template <class Function, class... Extra>
void def_warp(py::module_& m, const char* name, Function function, const char* doc, Extra... extra) {
  def_function(m, name, function, py::arg("color"), py::arg("depth"), py::kw_only(), py::arg("color_space") = "linear",
        py::arg("depth_format") = py::none(), py::arg("linear_range") = py::none(), py::arg("encoding") = py::none(),
        py::arg("near") = py::none(), py::arg("far") = py::none(), py::arg("decoder") = py::none(),
        py::arg("separation") = py::none(), py::arg("convergence") = py::none(), py::arg("direction") = py::none(),
        py::arg("model") = py::none(), py::arg("method") = "exact", py::arg("max_negative_parallax") = py::none(),
        py::arg("hole_threshold") = 1.0, py::arg("hole_fill") = "background", py::arg("edge") = "clamp",
        py::arg("guard") = 0, py::arg("probe_parallax") = py::none(), py::arg("march_steps") = 16,
        py::arg("secant_max_steps") = 256, py::arg("arch") = py::none(), py::arg("threads") = 0, extra..., doc);
}

}  // namespace

void bind_warp(py::module_& m) {
  public_class<Result>(m, "Result",
                     "One eye's outputs, arrays of the target's height and width: color (the source's dtype and "
                     "form), depth (the source depth's dtype and format), status (uint8: 0 hit, 1 hole, 2 outside, "
                     "3 clipped), source_x (float32, the source column each pixel came from). Result() holds None "
                     "in each; pass a Result of an earlier call as out= to write into its arrays.")
      .def(py::init<>())
      .def_readwrite("color", &Result::color)
      .def_readwrite("depth", &Result::depth)
      .def_readwrite("status", &Result::status)
      .def_readwrite("source_x", &Result::source_x)
      .def("__repr__", [](const Result& r) {
        // Shapes and dtypes, not the pixels.
        auto field = [](const char* name, const py::object& o) {
          if (o.is_none()) return std::string(name) + "=None";
          return std::string(name) + "=<" + py::str(o.attr("dtype")).cast<std::string>() + " " +
                 py::str(o.attr("shape")).cast<std::string>() + ">";
        };
        return "Result(" + field("color", r.color) + ", " + field("depth", r.depth) + ", " +
               field("status", r.status) + ", " + field("source_x", r.source_x) + ")";
      });
  public_class<PairResult>(m, "PairResult", "Both eyes' Results (warp_pair); unpacks as (left, right).")
      .def_readwrite("left", &PairResult::left)
      .def_readwrite("right", &PairResult::right)
      .def("__iter__", [](const PairResult& p) { return py::iter(py::make_tuple(p.left, p.right)); });

  def_warp(m, "warp", &warp, "The compiled reproject.warp (documented there).", py::arg("out") = py::none());
  def_warp(m, "warp_pair", &warp_pair, "The compiled reproject.warp_pair (documented there).",
           py::arg("out_left") = py::none(), py::arg("out_right") = py::none());
  warp_calls().bind(m, "warp and warp_pair calls");
}

}  // namespace reproject::python
