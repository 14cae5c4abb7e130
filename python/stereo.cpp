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
#include "names.hpp"
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
  public_class<ParallaxBudget>(m, "ParallaxBudget", py::dynamic_attr(),
                             "parallax_budget's result (stereo.hpp). Parallax is left eye -> right eye, in pixels "
                             "of the display width W. pixels, unreadable (NaN or w < 0, read as infinitely far): "
                             "counts; display_width W; eye_separation E; eye_parallax E W and parallax_limit, "
                             "pixels; min, max, percentile (at budget_percentiles, in %): pixels; the same "
                             "`_of_eyes`: in units of E W (1: the eyes are parallel); beyond_limit, "
                             "nearer_than_half_convergence, farther_than_100_convergence, uncomfortable: shares of "
                             "the pixels, 0..1; histogram_min, histogram_max: pixels; below_histogram, "
                             "above_histogram: counts; histogram: int64 counts per bin, or None.")
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
        "The compiled reproject.parallax_budget (documented there).");

  // Frusta and 2. the stereo culling frustum
  auto frustum = public_class<ViewFrustum>(
      m, "ViewFrustum",
      "A view frustum in view space (x right, y up, z forward), view-space units. Perspective: its side edges meet "
      "the plane z = near at x = left, right and y = bottom, top (glFrustum's numbers); far may be inf. "
      "Orthographic: the box x in [left, right], y in [bottom, top], z in [near, far].");
  def_init(frustum,
           [](double left, double right, double bottom, double top, double near_plane, double far_plane,
              bool orthographic) { return ViewFrustum{left, right, bottom, top, near_plane, far_plane, orthographic}; },
           py::arg("left") = -1.0, py::arg("right") = 1.0, py::arg("bottom") = -1.0, py::arg("top") = 1.0,
           py::arg("near") = 1.0, py::arg("far") = 1000.0, py::arg("orthographic") = false,
           "A frustum from its numbers (view-space units; see the class). validate() checks them.");
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
      .def("validate", [](const ViewFrustum& f) { raise_if_failed(f.validate()); },
           "ValueError unless every number is finite (far may be inf for perspective), left < right, bottom < top "
           "and 0 < near < far (orthographic: 0 <= near < far, finite).");
  auto culling = public_class<CullingFrustum>(
      m, "CullingFrustum",
      "One frustum that holds both eyes' frusta (stereo_culling_frustum): pull_back (view-space units), origin (its "
      "centre of projection in the mono view space), frustum (a ViewFrustum in its own frame) and planes, (6, 4) "
      "float64 rows (a, b, c, d) with a x + b y + c z + d >= 0 inside: left, right, bottom, top, near, far.");
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
             py::arg("slack") = 0.0,
             "Whether the mono view-space point (x, y, z) is inside every plane, with `slack` view-space units to "
             "spare.");
  def_function(m, "stereo_culling_frustum",
        [](const ViewFrustum& mono, const StereoCamera& camera) {
          CullingFrustum out;
          raise_if_failed(stereo_culling_frustum(mono, camera, &out));
          return out;
        },
        py::arg("mono"), py::arg("camera"), "The compiled reproject.stereo_culling_frustum (documented there).");

  // 3. Picking
  public_class<PickResult>(m, "PickResult",
                           "What is under a cursor (pick): source ('both', 'left', 'right', 'none': whose answer "
                           "stands), parallax (left -> right, pixels), inverse_depth (the decoder's units), depth "
                           "(view-space units, inf at infinity), left_x and right_x (the point's column in each "
                           "eye, pixels), left_parallax and right_parallax (each eye's own answer, pixels).")
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
        py::arg("hole_threshold") = 1.0, py::arg("agreement") = 0.25, "The compiled reproject.pick (documented there).");

  // 4. Screen -> view reconstruction
  auto screen_to_view_class = public_class<ScreenToView>(
      m, "ScreenToView",
      "Scale and bias constants of one frustum and viewport (make_screen_to_view), public so a shader can take "
      "them: perspective x_v = (x_bias + pixel_x x_scale) / w with w from the decoder, y likewise, z_v = 1 / w; "
      "orthographic x_v = x_bias + pixel_x x_scale, z_v = z_bias + d z_scale. width and height in pixels.");
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
             py::arg("pixel_x"), py::arg("pixel_y"), py::arg("stored"),
             "The view-space (x, y, z) at continuous pixel coordinates (pixel centres at integers) with stored "
             "depth `stored`.");
  def_function(m, "make_screen_to_view",
        [](const ViewFrustum& frustum, const std::string& encoding, int width, int height) {
          const DepthEncoding e = parse_name(encoding, parse_encoding, kDepthEncodingCount, "encoding");
          ScreenToView out;
          raise_if_failed(make_screen_to_view(frustum, e, width, height, &out));
          return out;
        },
        py::arg("frustum"), py::arg("encoding"), py::arg("width"), py::arg("height"),
        "The compiled reproject.make_screen_to_view (documented there).");
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
        "The compiled reproject.screen_to_view (documented there).");

  // 5. 2D elements at a depth
  def_function(m, "place_at_depth",
        [](double ndc_x, double ndc_y, double z, const StereoCamera& camera, const DepthDecoder& decoder) {
          ClipPosition left, right;
          raise_if_failed(place_at_depth(ndc_x, ndc_y, z, camera, decoder, &left, &right));
          return py::make_tuple(clip_tuple(left), clip_tuple(right));
        },
        py::arg("ndc_x"), py::arg("ndc_y"), py::arg("z"), py::arg("camera"), py::arg("decoder"),
        "The compiled reproject.place_at_depth (documented there).");

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
        "The compiled reproject.dilate_nearer_depth (documented there).");
}

}  // namespace reproject::python
