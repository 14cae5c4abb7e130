// The built-in ray-cast scenes (scene/), so a notebook can compare the methods against the
// true other eye without files: the centre view, both true eyes and what each eye shares with the
// centre, as arrays.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <iterator>
#include <optional>
#include <string>

#include "arguments.hpp"
#include "bindings.hpp"
#include "scene.hpp"

namespace reproject::python {

namespace {

struct SceneViews {
  std::string name;
  int width = 0, height = 0;
  double horizontal_fov = 0.0;
  StereoCamera camera;
  DepthDecoder decoder;
  py::object color, depth, left, left_depth, right, right_depth, left_visible, right_visible;
};

// An (H, W, C) view of C new planes (numpy.moveaxis): the layout warp() reads and writes in place.
py::object color_array(const Image& image) {
  const int w = image.width(), h = image.height(), channels = image.channels();
  py::array_t<float> planes({channels, h, w});
  for (int c = 0; c < channels; ++c) {
    for (int y = 0; y < h; ++y) {
      std::memcpy(planes.mutable_data(c, y, 0), image.plane(c).row(y), sizeof(float) * static_cast<std::size_t>(w));
    }
  }
  return py::module_::import("numpy").attr("moveaxis")(planes, 0, -1);
}

py::array_t<float> plane_array(const Image& image) {
  py::array_t<float> out({image.height(), image.width()});
  for (int y = 0; y < image.height(); ++y) {
    std::memcpy(out.mutable_data(y, 0), image.plane(0).row(y), sizeof(float) * static_cast<std::size_t>(image.width()));
  }
  return out;
}

py::array_t<bool> mask_array(const std::vector<std::uint8_t>& mask, int width, int height) {
  py::array_t<bool> out({height, width});
  for (std::size_t i = 0; i < mask.size(); ++i) out.mutable_data()[i] = mask[i] != 0;
  return out;
}

// The built-in scenes' names, from the scene library's own list.
py::tuple scene_names() {
  py::tuple names(std::size(scene::kAllScenes));
  for (std::size_t i = 0; i < std::size(scene::kAllScenes); ++i) names[i] = py::str(scene::to_string(scene::kAllScenes[i]));
  return names;
}

SceneViews make_scene(const std::string& name, int width, int height, double fov_degrees, const std::string& encoding,
                      std::optional<double> separation, std::optional<double> convergence, double offset, int threads) {
  scene::SceneId id{};
  if (!scene::parse_scene(name.c_str(), &id)) {
    std::string names;
    for (const scene::SceneId known : scene::kAllScenes) names += (names.empty() ? "" : ", ") + std::string(to_string(known));
    throw py::value_error("unknown scene '" + name + "' (" + names + ")");
  }
  DepthEncoding e{};
  if (!parse_encoding(encoding.c_str(), &e) || e == DepthEncoding::disparity) {
    throw py::value_error("encoding '" + encoding + "' is not a depth encoding a scene can store");
  }
  if (width < 1 || height < 1 || width > 16384 || height > 16384) {
    throw py::value_error("scene size " + std::to_string(width) + "x" + std::to_string(height) + " is not in 1..16384");
  }
  const scene::Scene s = scene::Scene::make(id);
  scene::Camera camera = s.camera(width, height, scene::kCentreEye, fov_degrees * M_PI / 180.0);
  if (separation) camera.stereo.separation = *separation;
  if (convergence) camera.stereo.convergence = *convergence;
  if (!(std::isfinite(camera.stereo.separation) && camera.stereo.separation >= 0.0 &&
        std::isfinite(camera.stereo.convergence) && camera.stereo.convergence > 0.0)) {
    throw py::value_error("separation must be finite and >= 0, convergence finite and > 0");
  }
  if (!std::isfinite(offset) || std::abs(offset) > 1000.0) {
    throw py::value_error("offset must be finite and within 1000 interaxials");
  }
  SceneViews out;
  out.name = s.name();
  out.width = width;
  out.height = height;
  out.horizontal_fov = camera.horizontal_fov;
  out.camera = camera.stereo;
  out.decoder = s.decoder(e);
  scene::View views[3];
  std::vector<std::uint8_t> visible[2];
  {
    py::gil_scoped_release release;  // ray casting takes a while at full HD
    // The rig moved sideways by `offset` interaxials (each eye's sigma shifted): a camera path.
    const double sigmas[3] = {scene::kCentreEye + offset, scene::kLeftEye + offset, scene::kRightEye + offset};
    for (int i = 0; i < 3; ++i) {
      const Status status = s.render(camera.with_eye(sigmas[i]), &views[i], threads);
      if (!status.ok()) {
        py::gil_scoped_acquire acquire;
        raise_if_failed(status);
      }
    }
    for (int i = 0; i < 2; ++i) {
      const Status status =
          s.visible_in_both(camera.with_eye(sigmas[i + 1]), camera.with_eye(sigmas[0]), &visible[i], threads);
      if (!status.ok()) {
        py::gil_scoped_acquire acquire;
        raise_if_failed(status);
      }
    }
  }
  out.color = color_array(views[0].color);
  out.depth = plane_array(scene::encode_depth(views[0].depth, out.decoder));
  out.left = color_array(views[1].color);
  out.left_depth = plane_array(scene::encode_depth(views[1].depth, out.decoder));
  out.right = color_array(views[2].color);
  out.right_depth = plane_array(scene::encode_depth(views[2].depth, out.decoder));
  out.left_visible = mask_array(visible[0], width, height);
  out.right_visible = mask_array(visible[1], width, height);
  return out;
}

}  // namespace

void bind_scenes(py::module_& m) {
  public_class<SceneViews>(m, "SceneViews",
                         "A built-in scene's centre view and true eyes (reproject.scene): color, left, right "
                         "(float32 (H, W, 3) in 0..1), depth, left_depth, right_depth (float32 (H, W) in the "
                         "scene's encoding, decoded by `decoder`), left_visible, right_visible (bool (H, W): "
                         "where that eye sees what the centre sees); name, width and height (pixels), "
                         "horizontal_fov (radians), camera (StereoCamera), near and far (view-space units).")
      .def_readonly("name", &SceneViews::name)
      .def_readonly("width", &SceneViews::width)
      .def_readonly("height", &SceneViews::height)
      .def_readonly("horizontal_fov", &SceneViews::horizontal_fov)
      .def_readonly("camera", &SceneViews::camera)
      .def_readonly("decoder", &SceneViews::decoder)
      .def_readonly("color", &SceneViews::color)
      .def_readonly("depth", &SceneViews::depth)
      .def_readonly("left", &SceneViews::left)
      .def_readonly("left_depth", &SceneViews::left_depth)
      .def_readonly("right", &SceneViews::right)
      .def_readonly("right_depth", &SceneViews::right_depth)
      .def_readonly("left_visible", &SceneViews::left_visible)
      .def_readonly("right_visible", &SceneViews::right_visible)
      .def_property_readonly("near", [](const SceneViews& v) { return v.decoder.near_plane(); })
      .def_property_readonly("far", [](const SceneViews& v) { return v.decoder.far_plane(); })
      .def("__repr__", [](const SceneViews& v) {
        return "SceneViews('" + v.name + "', " + std::to_string(v.width) + "x" + std::to_string(v.height) + ")";
      });
  def_function(m, "scene", &make_scene, py::arg("name") = "room", py::arg("width") = 960, py::arg("height") = 540,
        py::kw_only(), py::arg("fov") = 60.0, py::arg("encoding") = "standard", py::arg("separation") = py::none(),
        py::arg("convergence") = py::none(), py::arg("offset") = 0.0, py::arg("threads") = 0,
        "The compiled reproject.scene (documented there).");
  m.attr("scenes") = scene_names();
}

}  // namespace reproject::python
