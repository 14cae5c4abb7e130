// The stereo helpers of stereo.hpp: parallax budget, stereo culling frustum, picking under a
// cursor, screen -> view reconstruction, 2D elements at a depth, the halo pre-filter. Depth planes
// are passed as views under the same rule as warp's (arrays.hpp); the per-pixel ones run without
// the GIL.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "arrays.hpp"
#include "arguments.hpp"
#include "bindings.hpp"
#include "reproject/stereo.hpp"

namespace reproject::python {

namespace {

FloatPlane depth_view(const py::array& depth, const char* name) {
  require_dtype(depth, name);
  if (depth.ndim() != 2) throw py::value_error(std::string(name) + ": expected an (H, W) array, got " + describe(depth));
  return plane_view<const float>(depth, 0, 1, 0, name);
}

// `out` (None: a new array) as a writable plane of depth's size.
py::array output_plane(const py::object& out, const FloatPlane& like, const char* name, MutableFloatPlane* view) {
  py::array a = out.is_none() ? py::array(py::array_t<float>({like.height, like.width})) : py::array::ensure(out);
  if (!a) throw py::type_error(std::string(name) + ": expected a float32 array");
  require_dtype(a, name);
  require_writeable(a, name);
  if (a.ndim() != 2 || a.shape(0) != like.height || a.shape(1) != like.width) {
    throw py::value_error(std::string(name) + ": expected shape (" + std::to_string(like.height) + ", " +
                          std::to_string(like.width) + "), got " + describe(a));
  }
  *view = plane_view<float>(a, 0, 1, 0, name);
  return a;
}

template <std::size_t N>
py::tuple tuple_of(const double (&values)[N]) {
  py::tuple t(N);
  for (std::size_t i = 0; i < N; ++i) t[i] = values[i];
  return t;
}

py::tuple clip_tuple(const ClipPosition& p) { return py::make_tuple(p.x, p.y, p.z, p.w); }

}  // namespace

void bind_stereo(py::module_& m) {
  // 1. Parallax budget
  py::class_<ParallaxBudget>(m, "ParallaxBudget", py::dynamic_attr(),
                             "parallax_budget's result (stereo.hpp): pixels, in units of E*W (`_of_eyes`), "
                             "comfort shares, and `histogram` (int64 counts, or None).")
      .def_readonly("pixels", &ParallaxBudget::pixels)
      .def_readonly("unreadable", &ParallaxBudget::unreadable)
      .def_readonly("display_width", &ParallaxBudget::display_width)
      .def_readonly("eye_separation", &ParallaxBudget::eye_separation)
      .def_readonly("eye_parallax", &ParallaxBudget::eye_parallax)
      .def_readonly("parallax_limit", &ParallaxBudget::parallax_limit)
      .def_readonly("min", &ParallaxBudget::min)
      .def_readonly("max", &ParallaxBudget::max)
      .def_property_readonly("percentile", [](const ParallaxBudget& b) { return tuple_of(b.percentile); })
      .def_readonly("min_of_eyes", &ParallaxBudget::min_of_eyes)
      .def_readonly("max_of_eyes", &ParallaxBudget::max_of_eyes)
      .def_property_readonly("percentile_of_eyes", [](const ParallaxBudget& b) { return tuple_of(b.percentile_of_eyes); })
      .def_readonly("beyond_limit", &ParallaxBudget::beyond_limit)
      .def_readonly("nearer_than_half_convergence", &ParallaxBudget::nearer_than_half_convergence)
      .def_readonly("farther_than_100_convergence", &ParallaxBudget::farther_than_100_convergence)
      .def_readonly("uncomfortable", &ParallaxBudget::uncomfortable)
      .def_readonly("histogram_min", &ParallaxBudget::histogram_min)
      .def_readonly("histogram_max", &ParallaxBudget::histogram_max)
      .def_readonly("below_histogram", &ParallaxBudget::below_histogram)
      .def_readonly("above_histogram", &ParallaxBudget::above_histogram);
  m.attr("budget_percentiles") = tuple_of(kBudgetPercentiles);
  def_function(m, "parallax_budget",
        [](const py::array& depth, const DepthDecoder& decoder, const StereoCamera& camera,
           std::optional<double> eye_separation, int display_width, std::optional<double> parallax_limit,
           int histogram_bins, std::optional<double> histogram_min, std::optional<double> histogram_max) {
          const FloatPlane plane = depth_view(depth, "depth");
          BudgetOptions options;
          options.eye_separation = eye_separation;
          options.display_width = display_width;
          options.parallax_limit = parallax_limit;
          options.histogram_bins = histogram_bins;
          options.histogram_min = histogram_min;
          options.histogram_max = histogram_max;
          py::array_t<std::int64_t> histogram(std::max(histogram_bins, 0));
          ParallaxBudget budget;
          Status status;
          {
            py::gil_scoped_release release;
            status = parallax_budget(plane, decoder, camera, options, &budget,
                                     histogram_bins > 0 ? histogram.mutable_data() : nullptr);
          }
          raise_if_failed(status);
          py::object result = py::cast(budget);
          result.attr("histogram") = histogram_bins > 0 ? py::object(histogram) : py::object(py::none());
          return result;
        },
        py::arg("depth"), py::arg("decoder"), py::arg("camera"), py::kw_only(), py::arg("eye_separation") = py::none(),
        py::arg("display_width") = 0, py::arg("parallax_limit") = py::none(), py::arg("histogram_bins") = 0,
        py::arg("histogram_min") = py::none(), py::arg("histogram_max") = py::none(),
        "The parallax budget of a depth buffer under a stereo camera (BudgetOptions as keyword arguments).");

  // Frusta and 2. the stereo culling frustum
  py::class_<ViewFrustum> frustum(m, "ViewFrustum", "A view frustum (glFrustum's numbers at the near plane).");
  def_init(frustum,
           [](double left, double right, double bottom, double top, double near_plane, double far_plane,
              bool orthographic) { return ViewFrustum{left, right, bottom, top, near_plane, far_plane, orthographic}; },
           py::arg("left") = -1.0, py::arg("right") = 1.0, py::arg("bottom") = -1.0, py::arg("top") = 1.0,
           py::arg("near") = 1.0, py::arg("far") = 1000.0, py::arg("orthographic") = false);
  def_static(frustum, "perspective", &ViewFrustum::perspective, py::arg("horizontal_fov"), py::arg("width"),
             py::arg("height"), py::arg("near"), py::arg("far"),
             "A symmetric perspective frustum with square pixels: horizontal_fov in radians (math.radians(60) for "
             "60 degrees), width and height in pixels (their ratio gives the vertical extent), near > 0, far > near "
             "(may be inf). right = near tan(horizontal_fov / 2), top = right height / width.");
  frustum.def_readwrite("left", &ViewFrustum::left)
      .def_readwrite("right", &ViewFrustum::right)
      .def_readwrite("bottom", &ViewFrustum::bottom)
      .def_readwrite("top", &ViewFrustum::top)
      .def_readwrite("near", &ViewFrustum::near_plane)
      .def_readwrite("far", &ViewFrustum::far_plane)
      .def_readwrite("orthographic", &ViewFrustum::orthographic)
      .def("validate", [](const ViewFrustum& f) { raise_if_failed(f.validate()); });
  py::class_<CullingFrustum> culling(m, "CullingFrustum", "One frustum that holds both eyes' frusta.");
  culling
      .def_readonly("pull_back", &CullingFrustum::pull_back)
      .def_property_readonly("origin", [](const CullingFrustum& c) { return tuple_of(c.origin); })
      .def_readonly("frustum", &CullingFrustum::frustum)
      .def_property_readonly("planes",
                             [](const CullingFrustum& c) {
                               py::array_t<double> planes({6, 4});
                               for (int i = 0; i < 24; ++i) planes.mutable_data()[i] = c.planes[i / 4][i % 4];
                               return planes;
                             });
  def_method(culling, "contains", &CullingFrustum::contains, py::arg("x"), py::arg("y"), py::arg("z"),
             py::arg("slack") = 0.0);
  def_function(m, "stereo_culling_frustum",
        [](const ViewFrustum& mono, const StereoCamera& camera) {
          CullingFrustum out;
          raise_if_failed(stereo_culling_frustum(mono, camera, &out));
          return out;
        },
        py::arg("mono"), py::arg("camera"));

  // 3. Picking
  py::class_<PickResult>(m, "PickResult", "What is under a cursor (stereo.hpp's pick).")
      .def_property_readonly("source", [](const PickResult& r) { return std::string(to_string(r.source)); })
      .def_readonly("parallax", &PickResult::parallax)
      .def_readonly("inverse_depth", &PickResult::inverse_depth)
      .def_readonly("depth", &PickResult::depth)
      .def_readonly("left_x", &PickResult::left_x)
      .def_readonly("right_x", &PickResult::right_x)
      .def_readonly("left_parallax", &PickResult::left_parallax)
      .def_readonly("right_parallax", &PickResult::right_parallax);
  def_function(m, "pick",
        [](const py::array& left_depth, const py::array& right_depth, const DepthDecoder& decoder,
           const ParallaxModel& left_to_right, double cursor_x, int cursor_y,
           std::optional<double> max_negative_parallax, double hole_threshold, double agreement) {
          PickOptions options;
          if (max_negative_parallax)
            options.max_negative_parallax = float_argument(*max_negative_parallax, "max_negative_parallax");
          options.hole_threshold = float_argument(hole_threshold, "hole_threshold");
          options.agreement = float_argument(agreement, "agreement");
          PickResult out;
          raise_if_failed(pick(depth_view(left_depth, "left_depth"), depth_view(right_depth, "right_depth"), decoder,
                               left_to_right, cursor_x, cursor_y, options, &out));
          return out;
        },
        py::arg("left_depth"), py::arg("right_depth"), py::arg("decoder"), py::arg("left_to_right"),
        py::arg("cursor_x"), py::arg("cursor_y"), py::kw_only(), py::arg("max_negative_parallax") = py::none(),
        py::arg("hole_threshold") = 1.0, py::arg("agreement") = 0.25);

  // 4. Screen -> view reconstruction
  py::class_<ScreenToView> screen_to_view_class(m, "ScreenToView", "Scale and bias constants of one frustum and viewport.");
  screen_to_view_class
      .def_readonly("orthographic", &ScreenToView::orthographic)
      .def_readonly("width", &ScreenToView::width)
      .def_readonly("height", &ScreenToView::height)
      .def_readonly("x_scale", &ScreenToView::x_scale)
      .def_readonly("x_bias", &ScreenToView::x_bias)
      .def_readonly("y_scale", &ScreenToView::y_scale)
      .def_readonly("y_bias", &ScreenToView::y_bias)
      .def_readonly("decoder", &ScreenToView::decoder)
      .def_readonly("z_scale", &ScreenToView::z_scale)
      .def_readonly("z_bias", &ScreenToView::z_bias);
  def_method(screen_to_view_class, "at_pixel",
             [](const ScreenToView& s, float x, float y, float stored) {
               const ViewPoint p = s.at_pixel(x, y, stored);
               return py::make_tuple(p.x, p.y, p.z);
             },
             py::arg("pixel_x"), py::arg("pixel_y"), py::arg("stored"));
  def_function(m, "make_screen_to_view",
        [](const ViewFrustum& frustum, const std::string& encoding, int width, int height) {
          DepthEncoding e{};
          if (!parse_encoding(encoding.c_str(), &e)) throw py::value_error("unknown encoding '" + encoding + "'");
          ScreenToView out;
          raise_if_failed(make_screen_to_view(frustum, e, width, height, &out));
          return out;
        },
        py::arg("frustum"), py::arg("encoding"), py::arg("width"), py::arg("height"));
  def_function(m, "screen_to_view",
        [](const ScreenToView& reconstruction, const py::array& depth, const py::object& out_x,
           const py::object& out_y, const py::object& out_z) {
          const FloatPlane d = depth_view(depth, "depth");
          MutableFloatPlane x, y, z;
          py::array ax = output_plane(out_x, d, "out_x", &x), ay = output_plane(out_y, d, "out_y", &y),
                    az = output_plane(out_z, d, "out_z", &z);
          Status status;
          {
            py::gil_scoped_release release;
            status = screen_to_view(reconstruction, d, x, y, z);
          }
          raise_if_failed(status);
          return py::make_tuple(ax, ay, az);
        },
        py::arg("reconstruction"), py::arg("depth"), py::kw_only(), py::arg("out_x") = py::none(),
        py::arg("out_y") = py::none(), py::arg("out_z") = py::none(),
        "View-space x, y, z at every pixel centre of depth: a tuple of three (H, W) arrays.");

  // 5. 2D elements at a depth
  def_function(m, "place_at_depth",
        [](double ndc_x, double ndc_y, double z, const StereoCamera& camera, const DepthDecoder& decoder) {
          ClipPosition left, right;
          raise_if_failed(place_at_depth(ndc_x, ndc_y, z, camera, decoder, &left, &right));
          return py::make_tuple(clip_tuple(left), clip_tuple(right));
        },
        py::arg("ndc_x"), py::arg("ndc_y"), py::arg("z"), py::arg("camera"), py::arg("decoder"),
        "The left and right eyes' clip positions (x, y, z, w) of an element at mono NDC (x, y) seen at depth z.");

  // 6. Halo pre-filter
  def_function(m, "dilate_nearer_depth",
        [](const py::array& depth, const DepthDecoder& decoder, int radius, const py::object& out) {
          const FloatPlane d = depth_view(depth, "depth");
          MutableFloatPlane o;
          py::array result = output_plane(out, d, "out", &o);
          Status status;
          {
            py::gil_scoped_release release;
            status = dilate_nearer_depth(d, decoder, radius, o);
          }
          raise_if_failed(status);
          return result;
        },
        py::arg("depth"), py::arg("decoder"), py::arg("radius"), py::kw_only(), py::arg("out") = py::none(),
        "Halo pre-filter: each depth becomes the nearest (largest 1/z) within radius columns of its row.");
}

}  // namespace reproject::python
