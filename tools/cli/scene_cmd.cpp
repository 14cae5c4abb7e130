// `reproject scene`: writes a built-in scene's three views (colour, depth) and, for each eye, which
// of its pixels the centre view also sees, so that any reprojection tool can be scored on them.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "scene_setup.hpp"

namespace reproject::cli {

namespace rs = reproject::scene;

// The shortest decimal text that reads back as the same double, so that printed flags reproduce
// the scene's camera exactly.
std::string exact_number(double v) {
  char text[40];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

std::vector<Flags::Spec> scene_flags() {
  return {
      {"scene", "NAME", "built-in scene: room, boxes, pole, spheres, near, edge [room]"},
      {"width", "N", "image width in pixels [1920]"},
      {"height", "N", "image height in pixels [1080]"},
      {"fov", "DEG", "horizontal field of view in degrees, 1..170 [60]"},
  };
}

rs::SceneId scene_from_flags(const Flags& flags) {
  rs::SceneId id = rs::SceneId::room;
  const std::string name = flags.text("scene", "room");
  if (!rs::parse_scene(name.c_str(), &id)) {
    std::string names;
    for (rs::SceneId s : rs::kAllScenes) names += std::string(names.empty() ? "" : ", ") + rs::to_string(s);
    flags.bad_value("scene", "unknown scene '" + name + "' (" + names + ")");
  }
  return id;
}

// The scene's camera for the centre eye, with --width, --height, --fov, --separation and
// --convergence applied.
rs::Camera scene_camera(const Flags& flags, const rs::Scene& scene) {
  const int width = flags.integer("width", 1920, 1, 16384);
  const int height = flags.integer("height", 1080, 1, 16384);
  const double fov = flags.number("fov", 60.0, 1.0, 170.0);
  rs::Camera camera = scene.camera(width, height, rs::kCentreEye, fov * 3.14159265358979323846 / 180.0);
  camera.stereo.separation = flags.number("separation", camera.stereo.separation, 0.0, 1.0);
  camera.stereo.convergence = flags.number("convergence", camera.stereo.convergence, 0.0, HUGE_VAL, true);
  return camera;
}

DepthEncoding scene_encoding(const Flags& flags) {
  DepthEncoding encoding = DepthEncoding::standard;
  if (!flags.has("encoding")) return encoding;
  const std::string name = flags.text("encoding");
  if (!parse_encoding(name.c_str(), &encoding)) {
    flags.bad_value("encoding", "unknown encoding '" + name +
                                    "' (linear, standard, gl_ndc, reversed, reversed_infinite, infinite)");
  }
  if (encoding == DepthEncoding::disparity) {
    flags.bad_value("encoding", "built-in scenes are rendered with depth, not disparity");
  }
  return encoding;
}

int run_scene(int argc, char** argv) {
  std::vector<Flags::Spec> specs = scene_flags();
  specs.insert(specs.end(), {
      {"encoding", "NAME", "depth encoding written: linear, standard, gl_ndc, reversed, reversed_infinite, infinite [standard]"},
      {"separation", "S", "stereo separation, a fraction of the width [0.03]"},
      {"convergence", "C", "zero-parallax distance [the scene's: 3.5]"},
      {"out-dir", "DIR", "where to write the views (created if missing)"},
      {"color-format", "EXT", "colour files: png (8-bit), pfm or exr (float) [png]"},
      {"depth-format", "EXT", "depth files: pfm or exr [pfm]"},
      {"threads", "N", "render threads, 0 = one per hardware thread [0]"},
  });
  Flags flags("scene", specs);
  flags.parse(argc, argv, 2);
  if (flags.help()) {
    std::string text = flags.usage("[--scene NAME] [--width N --height N] --out-dir DIR [flags]");
    text += "\nscenes:\n";
    for (rs::SceneId s : rs::kAllScenes) text += std::string("  ") + rs::to_string(s) + std::string(10 - std::string(rs::to_string(s)).size(), ' ') + rs::describe(s) + "\n";
    text += "\nwrites centre, left and right colour (<eye>.<ext>) and depth (<eye>_depth.<ext>), and\n"
            "left_visible.png / right_visible.png: 255 where that eye's pixel is also seen by the centre view\n";
    std::fputs(text.c_str(), stdout);
    return kExitOk;
  }
  flags.require("out-dir");
  const rs::SceneId id = scene_from_flags(flags);
  const DepthEncoding encoding = scene_encoding(flags);
  const std::string color_ext = flags.text("color-format", "png");
  if (color_ext != "png" && color_ext != "pfm" && color_ext != "exr") {
    flags.bad_value("color-format", "'" + color_ext + "' is not png, pfm or exr");
  }
  const std::string depth_ext = flags.text("depth-format", "pfm");
  if (depth_ext != "pfm" && depth_ext != "exr") {
    flags.bad_value("depth-format", "'" + depth_ext + "' is not pfm or exr (depth needs floats)");
  }
  const int threads = flags.integer("threads", 0, 0, 1024);
  const rs::Scene scene = rs::Scene::make(id);
  const rs::Camera centre = scene_camera(flags, scene);
  const DepthDecoder decoder = scene.decoder(encoding);
  check_status(decoder.validate(), "depth decoder");

  const std::filesystem::path dir(flags.text("out-dir"));
  OutputSet out;
  out.make_directory(dir.string());
  struct EyeSpec {
    const char* name;
    double sigma;
  };
  const EyeSpec eyes[] = {{"centre", rs::kCentreEye}, {"left", rs::kLeftEye}, {"right", rs::kRightEye}};
  for (const EyeSpec& eye : eyes) {
    out.expect("out-dir", (dir / (std::string(eye.name) + "." + color_ext)).string());
    out.expect("out-dir", (dir / (std::string(eye.name) + "_depth." + depth_ext)).string());
    if (eye.sigma != rs::kCentreEye) out.expect("out-dir", (dir / (std::string(eye.name) + "_visible.png")).string());
  }
  for (const EyeSpec& eye : eyes) {
    const rs::Camera camera = centre.with_eye(eye.sigma);
    rs::View view;
    check_status(scene.render(camera, &view, threads), std::string("render ") + eye.name);
    const Image depth = rs::encode_depth(view.depth, decoder);
    if (depth.empty()) fail(kExitRuntime, "out of memory encoding the depth");
    out.color((dir / (std::string(eye.name) + "." + color_ext)).string(), view.color.color(), 8);
    out.plane((dir / (std::string(eye.name) + "_depth." + depth_ext)).string(), depth.plane(0));
    if (eye.sigma != rs::kCentreEye) {
      std::vector<std::uint8_t> visible;
      check_status(scene.visible_in_both(camera, centre, &visible, threads), "visibility");
      for (std::uint8_t& v : visible) v = v ? 255 : 0;
      out.bytes((dir / (std::string(eye.name) + "_visible.png")).string(), visible.data(), camera.width, camera.height);
    }
  }
  out.commit();

  std::printf("scene %s: %dx%d, fov %.4g deg, %s depth; wrote %s/{centre,left,right}.%s, *_depth.%s, "
              "left_visible.png, right_visible.png\n",
              scene.name(), centre.width, centre.height, centre.horizontal_fov * 180.0 / 3.14159265358979323846,
              to_string(encoding), dir.string().c_str(), color_ext.c_str(), depth_ext.c_str());
  std::string depth_flags = std::string("--encoding ") + to_string(encoding);
  if (encoding != DepthEncoding::linear) depth_flags += " --near " + exact_number(scene.near_plane());
  if (encoding == DepthEncoding::standard || encoding == DepthEncoding::gl_ndc || encoding == DepthEncoding::reversed) {
    depth_flags += " --far " + exact_number(scene.far_plane());
  }
  std::printf("to synthesise the right eye from the centre view:\n"
              "  reproject warp --color %s --depth %s %s --separation %s --convergence %s --direction centre-to-right --out right_warped.png\n",
              (dir / ("centre." + color_ext)).string().c_str(), (dir / ("centre_depth." + depth_ext)).string().c_str(),
              depth_flags.c_str(), exact_number(centre.stereo.separation).c_str(),
              exact_number(centre.stereo.convergence).c_str());
  return kExitOk;
}

}  // namespace reproject::cli
