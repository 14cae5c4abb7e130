// The built-in scenes: what each one holds (one builder per feature, the shell first), their names
// and one-line descriptions, and the object list the builders fill.
#include <cmath>
#include <cstring>

#include "scene.hpp"
#include "scene_internal.hpp"

namespace reproject::scene {
namespace {

Scene::Object make_object(const char* name, Scene::Shape shape, Scene::Material material,
                          Vec3 centre, const float a[3], const float b[3], double scale) {
  Scene::Object o;
  o.name = name;
  o.shape = shape;
  o.material = material;
  o.centre = centre;
  std::memcpy(o.color_a, a, sizeof o.color_a);
  std::memcpy(o.color_b, b, sizeof o.color_b);
  o.scale = scale;
  return o;
}

// The room and its features. Camera at the origin looking along +z, eye height 1.5 above the
// floor. Depths: 2 (nearest possible surface: the floor's front edge; the near sphere starts at
// 2.25) to 14 (the back wall, which every ray meets), so the recommended convergence is 3.5.
// Each feature is one builder, and every scene is the shell plus some of them: `room` holds all,
// in a fixed order (the order decides object indices and texture seeds, so it never changes).
using Shape = Scene::Shape;
using Material = Scene::Material;

// Texture seeds: each object's index in the default scene (see Object::texture_seed).
enum Seed : std::uint32_t {
  kFloor, kBackWall, kBoxFarLeft, kBoxYawed, kBoxMiddle, kPole, kSphere, kNearSphere, kEdgeBox,
};

void add_seeded(Scene* s, Scene::Object o, Seed seed) {
  o.texture_seed = seed;
  s->add(o);
}

// Floor and back wall: every scene has them, so every ray meets something.
void add_shell(Scene* s) {
  const double floor_y = -1.5;
  // Floor: 0.5 m tiles from z = 2 to the back wall. It ends at z = 2 so that no eye ever sees a
  // surface nearer than min_depth, whatever the field of view (rays past its front edge go on to
  // the back wall).
  {
    const float a[3] = {0.80f, 0.76f, 0.66f}, b[3] = {0.30f, 0.26f, 0.22f};
    Scene::Object o = make_object("floor", Shape::plane_y, Material::floor_tiles, {0, floor_y, 0}, a, b, 0.5);
    o.z_min = 2.0;
    o.z_max = 14.0;
    add_seeded(s, o, kFloor);
  }
  // Back wall: bricks 0.4 m x 0.2 m; infinite, so every ray meets something.
  {
    const float a[3] = {0.72f, 0.32f, 0.20f}, b[3] = {0.55f, 0.45f, 0.35f};
    add_seeded(s, make_object("back_wall", Shape::plane_z, Material::bricks, {0, 0, 14.0}, a, b, 0.4), kBackWall);
  }
}

// Boxes at several depths: an axis-aligned one far left, a yawed one far right (slanted faces:
// depth varies across them), a small one in the middle distance.
void add_boxes(Scene* s) {
  {
    const float a[3] = {0.20f, 0.45f, 0.80f}, b[3] = {0.85f, 0.90f, 0.95f};
    Scene::Object o = make_object("box_far_left", Shape::box, Material::checker, {-2.3, -0.85, 9.75}, a, b, 0.2);
    o.half = {0.7, 0.65, 0.75};
    add_seeded(s, o, kBoxFarLeft);
  }
  {
    const float a[3] = {0.25f, 0.65f, 0.30f}, b[3] = {0.95f, 0.85f, 0.30f};
    Scene::Object o = make_object("box_yawed", Shape::box, Material::checker, {3.0, -0.9, 9.5}, a, b, 0.25);
    o.half = {0.7, 0.6, 0.7};
    o.yaw = 0.61;  // about 35 degrees
    add_seeded(s, o, kBoxYawed);
  }
  {
    const float a[3] = {0.60f, 0.20f, 0.60f}, b[3] = {0.95f, 0.95f, 0.90f};
    Scene::Object o = make_object("box_middle", Shape::box, Material::checker, {2.2, -1.25, 5.4}, a, b, 0.1);
    o.half = {0.4, 0.25, 0.4};
    add_seeded(s, o, kBoxMiddle);
  }
}

// The thin pole in front of the brick wall: radius chosen so that its diameter projects to
// 2 px at 1920 px and 60 degrees: d = 2 px * 2 z tan(30 deg) / 1920 at z = 8. (At other
// resolutions it stays the same object, so it is 2 px * width / 1920 wide.)
void add_pole(Scene* s) {
  const float a[3] = {0.95f, 0.95f, 0.95f}, b[3] = {0.85f, 0.10f, 0.10f};
  Scene::Object o = make_object("pole", Shape::cylinder_y, Material::bands, {-0.8, 0.75, 8.0}, a, b, 0.15);
  o.radius = 2.0 * 8.0 * std::tan(0.5 * kDefaultHorizontalFov) / 1920.0;
  o.half = {0, 2.25, 0};  // y from the floor to 3, above the top of the image
  add_seeded(s, o, kPole);
}

// Curved depth: a large striped sphere in the middle distance.
void add_sphere(Scene* s) {
  const float a[3] = {0.95f, 0.75f, 0.15f}, b[3] = {0.15f, 0.30f, 0.75f};
  Scene::Object o = make_object("sphere", Shape::sphere, Material::stripes, {0.7, -0.5, 7.0}, a, b, 0.2);
  o.radius = 1.0;
  add_seeded(s, o, kSphere);
}

// In front of the convergence plane (negative parallax): a checkered sphere, z 2.25 .. 2.95.
void add_near_sphere(Scene* s) {
  const float a[3] = {0.10f, 0.75f, 0.75f}, b[3] = {0.95f, 0.35f, 0.55f};
  Scene::Object o = make_object("near_sphere", Shape::sphere, Material::checker, {0.55, -0.45, 2.6}, a, b, 0.06);
  o.radius = 0.35;
  add_seeded(s, o, kNearSphere);
}

// Touching the left viewport edge in every eye (it reaches x = -3, well outside the frustum's
// x = -2 at its front face), slightly in front of the convergence plane.
void add_edge_box(Scene* s) {
  const float a[3] = {0.90f, 0.55f, 0.10f}, b[3] = {0.20f, 0.15f, 0.10f};
  Scene::Object o = make_object("edge_box", Shape::box, Material::checker, {-2.15, -0.95, 3.8}, a, b, 0.12);
  o.half = {0.85, 0.55, 0.4};
  add_seeded(s, o, kEdgeBox);
}

void build(SceneId id, Scene* s) {
  add_shell(s);
  const bool all = id == SceneId::room;
  if (all || id == SceneId::boxes) add_boxes(s);
  if (all || id == SceneId::pole) add_pole(s);
  if (all || id == SceneId::spheres) add_sphere(s);
  if (all || id == SceneId::spheres || id == SceneId::near) add_near_sphere(s);
  if (all || id == SceneId::edge) add_edge_box(s);
  // The same range for every scene (the shell alone spans it), hence the same recommended
  // stereo camera: a scene's features change, its camera does not.
  s->set_depth_range(2.0, 14.0, 1.0, 20.0);
}

}  // namespace

const char* to_string(SceneId id) noexcept {
  switch (id) {
    case SceneId::room: return "room";
    case SceneId::boxes: return "boxes";
    case SceneId::pole: return "pole";
    case SceneId::spheres: return "spheres";
    case SceneId::near: return "near";
    case SceneId::edge: return "edge";
  }
  return "unknown";
}

const char* describe(SceneId id) noexcept {
  switch (id) {
    case SceneId::room: return "all of the below in one room (the default)";
    case SceneId::boxes: return "floor and back wall with boxes at several depths, one yawed";
    case SceneId::pole: return "a 2-px-wide pole (at 1920 px) in front of the brick wall";
    case SceneId::spheres: return "curved depth: a large sphere and a small near one";
    case SceneId::near: return "a sphere in front of the convergence plane (negative parallax)";
    case SceneId::edge: return "a box cut by the left viewport edge";
  }
  return "unknown";
}

bool parse_scene(const char* name, SceneId* out) noexcept {
  if (name == nullptr || out == nullptr) return false;
  for (SceneId id : kAllScenes) {
    if (std::strcmp(name, to_string(id)) == 0) {
      *out = id;
      return true;
    }
  }
  return false;
}

Scene Scene::make(SceneId id) {
  Scene s;
  s.id_ = id;
  build(id, &s);
  return s;
}

void Scene::add(const Object& object) {
  objects_.push_back(object);
  objects_.back().cos_yaw = std::cos(object.yaw);
  objects_.back().sin_yaw = std::sin(object.yaw);
  objects_.back().bound2 = dot(object.half, object.half);
}

const char* Scene::object_name(int index) const noexcept {
  if (index < 0 || index >= object_count()) return "none";
  return objects_[static_cast<std::size_t>(index)].name.c_str();
}

int Scene::find_object(const char* name) const noexcept {
  for (int i = 0; i < object_count(); ++i) {
    if (objects_[static_cast<std::size_t>(i)].name == name) return i;
  }
  return -1;
}

}  // namespace reproject::scene
