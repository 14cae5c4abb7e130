// Flags shared by the subcommands that render a built-in scene (`scene`, `compare --scene`).
#pragma once

#include <string>
#include <vector>

#include "cli.hpp"
#include "scene.hpp"

namespace reproject::cli {

// The shortest decimal text that reads back as the same double.
std::string exact_number(double v);
// --scene, --width, --height, --fov.
std::vector<Flags::Spec> scene_flags();
scene::SceneId scene_from_flags(const Flags& flags);
// The centre eye's camera: the scene's recommended one with --width, --height, --fov,
// --separation and --convergence applied.
scene::Camera scene_camera(const Flags& flags, const scene::Scene& scene);
// --encoding for a rendered depth (any but disparity) [standard].
DepthEncoding scene_encoding(const Flags& flags);

}  // namespace reproject::cli
