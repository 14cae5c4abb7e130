// The depth decoder, the parallax model and the stereo camera (depth.hpp, parallax.hpp). A factory
// given invalid parameters raises ValueError with the library's message instead of returning an
// object that every later call would refuse.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>

#include "arguments.hpp"
#include "bindings.hpp"
#include "names.hpp"
#include "reproject/depth.hpp"
#include "reproject/parallax.hpp"

namespace reproject::python {

namespace {

DepthEncoding encoding_of(const std::string& name) {
  return parse_name(name, parse_encoding, kDepthEncodingCount, "encoding");
}

EyeDirection direction_of(const std::string& name) {
  return parse_name(name, parse_direction, kEyeDirectionCount, "direction");
}

// The library names no Eye (parallax.hpp): the two are spelled here.
Eye eye_of(const std::string& name) {
  if (name == "left") return Eye::left;
  if (name == "right") return Eye::right;
  throw py::value_error("unknown eye '" + name + "' (left, right)");
}

DepthDecoder checked(const DepthDecoder& d) {
  raise_if_failed(d.validate());
  return d;
}
ParallaxModel checked(const ParallaxModel& m) {
  raise_if_failed(m.validate());
  return m;
}

// 16 floats in the API's memory order: a (4, 4) array flattened in C order, or 16 numbers.
struct Matrix {
  float m[16];
};
Matrix matrix_of(const py::array_t<float, py::array::c_style | py::array::forcecast>& a) {
  if (a.size() != 16) throw py::value_error("expected a 4x4 matrix (16 numbers), got " + std::to_string(a.size()));
  Matrix out;
  for (int i = 0; i < 16; ++i) out.m[i] = a.data()[i];
  return out;
}
// f applied to every element of a number or an array (float32 out; a number gives a number).
template <class In, class F>
py::object elementwise(const py::object& x, F f) {
  if (py::isinstance<py::float_>(x) || py::isinstance<py::int_>(x)) return py::float_(f(x.cast<In>()));
  const auto in = py::array_t<In, py::array::c_style | py::array::forcecast>::ensure(x);
  if (!in) throw py::type_error("expected a number or an array of numbers");
  py::array_t<float> out(std::vector<py::ssize_t>(in.shape(), in.shape() + in.ndim()));
  for (py::ssize_t i = 0; i < in.size(); ++i) out.mutable_data()[i] = f(in.data()[i]);
  return std::move(out);
}

py::array_t<float> matrix_array(const float m[16]) {
  py::array_t<float> out({4, 4});
  for (int i = 0; i < 16; ++i) out.mutable_data()[i] = m[i];
  return out;
}

}  // namespace

void bind_models(py::module_& m) {
  // Bound through arguments.hpp (def_init, def_static, def_method): an argument of the wrong type
  // is a TypeError that names it.
  auto decoder = public_class<DepthDecoder>(
      m, "Decoder",
      "The shared depth decoder: stored value d -> inverse depth w = 1/z, z in view-space units (depth.hpp).\n\n"
      "Decoder(encoding='linear', near=None, far=None): encoding is one of linear (d = z), standard (0 at near, 1 at "
      "far: D3D, GL window depth), gl_ndc (NDC z in -1..1), reversed (1 at near, 0 at far), reversed_infinite (1 at "
      "near, 0 at infinity), infinite (0 at near, 1 at infinity), disparity (d is a disparity in pixels); near and "
      "far are view-space distances, needed by every encoding but linear and disparity (far is ignored by the "
      "infinite ones). Invalid values raise ValueError.");
  def_init(decoder,
           [](const std::string& encoding, std::optional<double> near_plane, std::optional<double> far_plane) {
             const DepthEncoding e = encoding_of(encoding);
             if (e == DepthEncoding::linear) return DepthDecoder::linear();
             if (e == DepthEncoding::disparity) return DepthDecoder::disparity();
             const double nan = std::numeric_limits<double>::quiet_NaN();
             return checked(DepthDecoder::from_near_far(e, near_plane.value_or(nan), far_plane.value_or(nan)));
           },
           py::arg("encoding") = "linear", py::arg("near") = py::none(), py::arg("far") = py::none(),
           "A decoder for `encoding` with near and far planes in view-space units (see the class).");
  def_static(decoder, "from_near_far",
             [](const std::string& encoding, double near_plane, double far_plane) {
               return checked(DepthDecoder::from_near_far(encoding_of(encoding), near_plane, far_plane));
             },
             py::arg("encoding"), py::arg("near"), py::arg("far"),
             "A decoder for `encoding` with near and far planes in view-space units (all three required).");
  decoder.def_static("linear", &DepthDecoder::linear, "The decoder of linear depth: the stored value is z.")
      .def_static("disparity", &DepthDecoder::disparity,
                  "The decoder of a disparity map in pixels (w = d; use it with ParallaxModel.from_disparity).");
  def_static(decoder, "from_d3d_projection",
             [](const py::array_t<float, py::array::c_style | py::array::forcecast>& matrix, const std::string& encoding) {
               const Matrix mm = matrix_of(matrix);
               return checked(DepthDecoder::from_d3d_projection(mm.m, encoding_of(encoding)));
             },
             py::arg("matrix"), py::arg("encoding"),
             "Near/far read off a D3D projection matrix (row-vector form, row-major: the (4, 4) array as written); "
             "encoding (standard, gl_ndc, reversed, reversed_infinite, infinite) is the depth the matrix produces.");
  def_static(decoder, "from_gl_projection",
             [](const py::array_t<float, py::array::c_style | py::array::forcecast>& matrix, const std::string& encoding) {
               const Matrix mm = matrix_of(matrix);
               return checked(DepthDecoder::from_gl_projection(mm.m, encoding_of(encoding)));
             },
             py::arg("matrix"), py::arg("encoding"),
             "Near/far read off a GL projection matrix in glUniformMatrix4fv order (column-major: 16 numbers as "
             "OpenGL stores them); encoding as from_d3d_projection's.");
  decoder
      .def_property_readonly("encoding", [](const DepthDecoder& d) { return std::string(to_string(d.encoding())); },
                             "The encoding's name.")
      .def_property_readonly("near", &DepthDecoder::near_plane, "The near plane, view-space units (0 when unused).")
      .def_property_readonly("far", &DepthDecoder::far_plane, "The far plane, view-space units (0 when unused).")
      .def_property_readonly("A", &DepthDecoder::A, "The affine encodings' w = A d + B: A (0 for linear).")
      .def_property_readonly("B", &DepthDecoder::B, "The affine encodings' w = A d + B: B (0 for linear).")
      .def("inverse_depth", [](const DepthDecoder& d, const py::object& stored) {
             return elementwise<float>(stored, [&d](float v) { return d.inverse_depth(v); });
           },
           py::arg("stored"), "w = 1/z of a stored value, a number or an array (float32 out).")
      .def("linear_depth", [](const DepthDecoder& d, const py::object& stored) {
             return elementwise<float>(stored, [&d](float v) { return d.linear_depth(v); });
           },
           py::arg("stored"), "z = 1/w of a stored value, view-space units (inf at infinity).")
      .def("encode", [](const DepthDecoder& d, const py::object& z) {
             return elementwise<double>(z, [&d](double v) { return d.encode(v); });
           }, py::arg("z"), "The stored value for view-space depth z (z may be inf for the infinite encodings).")
      .def("__repr__", [](const DepthDecoder& d) {
        return "Decoder('" + std::string(to_string(d.encoding())) + "', near=" + py::repr(py::float_(d.near_plane())).cast<std::string>() +
               ", far=" + py::repr(py::float_(d.far_plane())).cast<std::string>() + ")";
      });

  auto model = public_class<ParallaxModel>(
      m, "ParallaxModel",
      "The parallax model (parallax.hpp): a point at inverse depth w seen at source column x appears in the target at "
      "x + p(w), p(w) = a + b w pixels. ParallaxModel(a, b), or one of the factories.");
  // a and b are floats: a number beyond the float range is named, not turned into inf.
  def_init(model, [](double a, double b) { return checked(ParallaxModel{float_argument(a, "a"), float_argument(b, "b")}); },
           py::arg("a"), py::arg("b"), "p(w) = a + b w: a in pixels, b in pixels per unit of inverse depth.");
  model.def_readwrite("a", &ParallaxModel::a, "The parallax at infinity (w = 0), pixels.")
      .def_readwrite("b", &ParallaxModel::b, "Pixels per unit of inverse depth.")
      .def("parallax", [](const ParallaxModel& p, const py::object& w) {
             return elementwise<float>(w, [&p](float v) { return p.parallax(v); });
           },
           py::arg("inverse_depth"), "p(w) in pixels, of a number or an array (float32 out).");
  def_static(model, "from_stereo",
             [](double separation, double convergence, int width, const std::string& direction) {
               return checked(ParallaxModel::from_stereo(separation, convergence, width, direction_of(direction)));
             },
             py::arg("separation"), py::arg("convergence"), py::arg("width"), py::arg("direction"),
             "The stereo camera's model: separation = interaxial / virtual screen width (0 .. ~0.1), convergence = "
             "the view-space distance of the zero-parallax plane, width = the source's width in pixels (without "
             "guard band), direction = left-to-right, right-to-left, centre-to-left or centre-to-right "
             "(underscores also accepted). a = sigma separation width, b = -a convergence.");
  def_static(model, "from_physical",
             [](double interocular, double screen_width, double convergence, int width, const std::string& direction) {
               return checked(ParallaxModel::from_physical(interocular, screen_width, convergence, width,
                                                           direction_of(direction)));
             },
             py::arg("interocular"), py::arg("screen_width"), py::arg("convergence"), py::arg("width"),
             py::arg("direction"),
             "from_stereo with separation = interocular / screen_width (both in one length unit, e.g. metres).");
  def_static(model, "from_disparity",
             [](const std::string& direction) { return checked(ParallaxModel::from_disparity(direction_of(direction))); },
             py::arg("direction") = "left-to-right",
             "For a disparity map in pixels (Decoder.disparity()): p = -d left-to-right (the default), p = +d "
             "right-to-left.");
  def_static(model, "from_relative",
             [](double max_parallax, double zero_plane, int width, const std::string& direction) {
               return checked(ParallaxModel::from_relative(max_parallax, zero_plane, width, direction_of(direction)));
             },
             py::arg("max_parallax"), py::arg("zero_plane"), py::arg("width"), py::arg("direction"),
             "For relative inverse depth v (a monocular depth model's output, 0 farthest .. 1 nearest; "
             "Decoder.disparity() decodes it as w = v): p = sigma max_parallax width (zero_plane - v). max_parallax, "
             "a fraction of the width (>= 0), is the parallax between the eyes from v = 0 to v = 1; zero_plane (0..1) "
             "is the v seen on the screen.");
  model.def("__repr__", [](const ParallaxModel& p) {
    return "ParallaxModel(a=" + py::repr(py::float_(p.a)).cast<std::string>() +
           ", b=" + py::repr(py::float_(p.b)).cast<std::string>() + ")";
  });

  auto camera = public_class<StereoCamera>(
      m, "StereoCamera",
      "The standard stereo projection (parallax.hpp): each eye's clip x is shifted by side S (clip.w - c), side -1 "
      "left, +1 right; S = separation (interaxial / virtual screen width), c = convergence (view-space distance of "
      "the zero-parallax plane).");
  def_init(camera, [](double separation, double convergence) { return StereoCamera{separation, convergence}; },
           py::arg("separation") = 0.0, py::arg("convergence") = 1.0,
           "separation S (interaxial / virtual screen width) and convergence c (view-space units).");
  camera.def_readwrite("separation", &StereoCamera::separation, "S: interaxial / virtual screen width.")
      .def_readwrite("convergence", &StereoCamera::convergence, "c: view-space distance of the zero-parallax plane.");
  def_static(camera, "from_physical", &StereoCamera::from_physical, py::arg("interocular"), py::arg("screen_width"),
             py::arg("convergence"),
             "S = interocular / screen_width (both in one length unit), c = convergence (view-space units).");
  def_static(camera, "from_rig",
             [](double interaxial, double convergence, double horizontal_fov) {
               const StereoCamera c = StereoCamera::from_rig(interaxial, convergence, horizontal_fov);
               if (!std::isfinite(c.separation)) {
                 throw py::value_error("StereoCamera.from_rig: interaxial must be finite and >= 0, convergence finite "
                                       "and > 0, horizontal_fov in (0, pi) radians");
               }
               return c;
             },
             py::arg("interaxial"), py::arg("convergence"), py::arg("horizontal_fov"),
             "A renderer's stereo rig (Blender: interocular distance, convergence distance, the camera's horizontal "
             "field of view in radians): S = interaxial / (2 convergence tan(horizontal_fov / 2)), c = convergence.");
  def_method(camera, "eye_translation", &StereoCamera::eye_translation, py::arg("horizontal_fov"),
             "The eyes' horizontal offset from the centre camera, in view units, for a horizontal field of view in "
             "radians.");
  def_method(camera, "parallax",
             [](const StereoCamera& c, int width, const std::string& direction) {
               return checked(c.parallax(width, direction_of(direction)));
             },
             py::arg("width"), py::arg("direction"),
             "The ParallaxModel for an image `width` pixels wide and a direction (as ParallaxModel.from_stereo's).");
  def_method(camera, "projection_d3d",
             [](const StereoCamera& c, const py::array_t<float, py::array::c_style | py::array::forcecast>& mono,
                const std::string& eye) {
               float out[16];
               c.projection_d3d(matrix_of(mono).m, eye_of(eye), out);
               return matrix_array(out);
             },
             py::arg("mono"), py::arg("eye"),
             "The eye's ('left' or 'right') D3D projection from the mono one, row-major row-vector (4, 4) arrays: "
             "P[2][0] += side S, P[3][0] -= side S c.");
  def_method(camera, "projection_gl",
             [](const StereoCamera& c, const py::array_t<float, py::array::c_style | py::array::forcecast>& mono,
                const std::string& eye) {
               float out[16];
               c.projection_gl(matrix_of(mono).m, eye_of(eye), out);
               return matrix_array(out);
             },
             py::arg("mono"), py::arg("eye"),
             "The eye's ('left' or 'right') GL projection from the mono one, 16 numbers in glUniformMatrix4fv "
             "(column-major) order, returned as a (4, 4) array in the same memory order.");
  camera.def("__repr__", [](const StereoCamera& c) {
    return "StereoCamera(separation=" + py::repr(py::float_(c.separation)).cast<std::string>() +
           ", convergence=" + py::repr(py::float_(c.convergence)).cast<std::string>() + ")";
  });
}

}  // namespace reproject::python
