#include "scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <thread>

namespace reproject::scene {
namespace {

constexpr std::uint8_t kNoObject = 255;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Vec3 at(const Ray& r, double t) {
  return {r.origin.x + t * r.direction.x, r.origin.y + t * r.direction.y, r.origin.z + t * r.direction.z};
}

// Hits closer than this (in ray parameter, i.e. view-space depth) are ignored: no surface of a
// scene is that close to an eye.
constexpr double kMinT = 1e-6;

// --- Procedural texture: lattice value noise over an integer hash ------------------------------
// Colour must be a function of the surface point only (never of the ray), so that a point has the
// same colour in every eye and a reprojected pixel can be compared with the true other eye.

std::uint32_t hash3(std::int64_t x, std::int64_t y, std::uint32_t seed) {
  // Fold the lattice coordinates and the seed together, then scramble with multiply/xor-shift
  // rounds so that neighbouring cells get unrelated values.
  std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full + seed;
  h ^= h >> 31;
  h *= 0xD6E8FEB86659FD93ull;
  h ^= h >> 29;
  h *= 0x9FB21C651E98DF25ull;
  h ^= h >> 32;
  return static_cast<std::uint32_t>(h);
}

double cell_value(std::int64_t x, std::int64_t y, std::uint32_t seed) {
  return (hash3(x, y, seed) >> 8) * (1.0 / 16777216.0);  // [0, 1)
}

// Smooth value noise in [0, 1), feature size 1 in (u, v).
double value_noise(double u, double v, std::uint32_t seed) {
  const double fu = std::floor(u), fv = std::floor(v);
  const auto iu = static_cast<std::int64_t>(fu);
  const auto iv = static_cast<std::int64_t>(fv);
  double su = u - fu, sv = v - fv;
  su = su * su * (3.0 - 2.0 * su);  // smoothstep: no visible lattice creases
  sv = sv * sv * (3.0 - 2.0 * sv);
  const double n00 = cell_value(iu, iv, seed), n10 = cell_value(iu + 1, iv, seed);
  const double n01 = cell_value(iu, iv + 1, seed), n11 = cell_value(iu + 1, iv + 1, seed);
  const double top = n00 + (n10 - n00) * su;
  const double bottom = n01 + (n11 - n01) * su;
  return top + (bottom - top) * sv;
}

// Two octaves centred on 0, amplitude about +-0.5: detail at the feature size and at a quarter.
double detail(double u, double v, std::uint32_t seed) {
  return 0.65 * (value_noise(u, v, seed) - 0.5) + 0.35 * (value_noise(4.0 * u, 4.0 * v, seed + 1) - 0.5);
}

// Texture edges are ramps, not steps: a step is aliased by the one-ray-per-pixel rendering, and
// then even a perfect reprojection (which must interpolate between pixels) differs from the true
// other eye at every texel edge, drowning the geometric errors the demo is meant to show. The
// ramps are narrow (kEdge of a cell on each side of the edge), so a misplaced pixel still shows.
constexpr double kEdge = 0.04;

// Square wave of period 2 in u (0 on even cells, 1 on odd ones) with linear ramps of half-width
// kEdge around each integer, passing 0.5 at the integer.
double soft_parity(double u) {
  const double cell = std::floor(u);
  const double own = (static_cast<std::int64_t>(cell) & 1) != 0 ? 1.0 : 0.0;
  const double f = u - cell;
  const double edge_distance = std::min(f, 1.0 - f);
  const double weight = edge_distance >= kEdge ? 1.0 : 0.5 + 0.5 * edge_distance / kEdge;
  return own * weight + (1.0 - own) * (1.0 - weight);
}

// Checkerboard, the soft exclusive-or of the two square waves.
double soft_checker(double u, double v) {
  const double a = soft_parity(u), b = soft_parity(v);
  return a + b - 2.0 * a * b;
}

// 1 within `half_width` of an integer of u, falling linearly to 0 over `ramp` beyond (all in
// units of u): a joint line.
double soft_line(double u, double half_width, double ramp) {
  const double f = u - std::floor(u);
  const double d = std::min(f, 1.0 - f);
  return std::min(1.0, std::max(0.0, (half_width + ramp - d) / ramp));
}

float clamp01(double x) { return static_cast<float>(std::min(1.0, std::max(0.0, x))); }

// --- Scene builders --------------------------------------------------------------------------

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

// ---------------------------------------------------------------------------------------------

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

double Camera::tan_half_fov_x() const noexcept { return std::tan(0.5 * horizontal_fov); }

double Camera::tan_half_fov_y() const noexcept {
  return tan_half_fov_x() * static_cast<double>(height) / static_cast<double>(width);
}

double Camera::eye_x() const noexcept {
  // docs/DESIGN.md §4: T = S c tan(fov/2) is half the interaxial; the eye at sigma is at 2 sigma T.
  return 2.0 * sigma * stereo.separation * stereo.convergence * tan_half_fov_x();
}

namespace {

// Per-camera constants of ray generation, so that rendering does not recompute tan() per pixel.
// Camera::ray goes through the same code, so a rendered pixel and Camera::ray agree bit for bit.
struct RayGenerator {
  double origin_x, shear, tx, ty, inv_w, inv_h;
  explicit RayGenerator(const Camera& c)
      : origin_x(c.eye_x()),
        shear(2.0 * c.sigma * c.stereo.separation),
        tx(c.tan_half_fov_x()),
        ty(c.tan_half_fov_y()),
        inv_w(1.0 / c.width),
        inv_h(1.0 / c.height) {}
  Ray operator()(double u, double v) const {
    // Pixel centre u = i covers NDC (2i + 1)/W - 1. Undo the eye's shear (2 sigma S) to get the
    // slope of the ray relative to the translated eye.
    const double ndc_x = (2.0 * u + 1.0) * inv_w - 1.0;
    const double ndc_y = 1.0 - (2.0 * v + 1.0) * inv_h;
    Ray r;
    r.origin = {origin_x, 0.0, 0.0};
    r.direction = {(ndc_x - shear) * tx, ndc_y * ty, 1.0};
    return r;
  }
};

}  // namespace

Ray Camera::ray(double u, double v) const noexcept { return RayGenerator(*this)(u, v); }

void Camera::project(const Vec3& p, double* u, double* v) const noexcept {
  const double ndc_x = (p.x - eye_x()) / (p.z * tan_half_fov_x()) + 2.0 * sigma * stereo.separation;
  const double ndc_y = p.y / (p.z * tan_half_fov_y());
  if (u != nullptr) *u = 0.5 * (ndc_x + 1.0) * width - 0.5;
  if (v != nullptr) *v = 0.5 * (1.0 - ndc_y) * height - 0.5;
}

Scene Scene::make(SceneId id) {
  Scene s;
  s.id_ = id;
  build(id, &s);
  return s;
}

DepthDecoder Scene::decoder(DepthEncoding encoding) const noexcept {
  if (encoding == DepthEncoding::linear) return DepthDecoder::linear();
  if (encoding == DepthEncoding::disparity) return DepthDecoder::disparity();
  return DepthDecoder::from_near_far(encoding, near_, far_);
}

StereoCamera Scene::recommended_stereo() const noexcept {
  StereoCamera stereo;
  stereo.separation = separation_;
  stereo.convergence = 2.0 / (1.0 / min_depth_ + 1.0 / max_depth_);
  return stereo;
}

Camera Scene::camera(int width, int height, double sigma, double horizontal_fov) const noexcept {
  Camera c;
  c.width = width;
  c.height = height;
  c.horizontal_fov = horizontal_fov;
  c.stereo = recommended_stereo();
  c.sigma = sigma;
  return c;
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

// Nearest intersection of `ray` with `o` in (kMinT, t_max). Cameras are never inside an object,
// so only entering hits are needed. Also fills the outward normal and texture coordinates
// (view-space units along the surface) when asked.
bool Scene::intersect(const Object& o, const Ray& ray, double t_max, double* t_out, Vec3* normal,
                      double uv[2]) const noexcept {
  const Vec3& d = ray.direction;
  double t = 0.0;
  switch (o.shape) {
    case Shape::plane_y: {
      if (d.y == 0.0) return false;
      t = (o.centre.y - ray.origin.y) / d.y;
      if (!(t > kMinT && t < t_max)) return false;
      const Vec3 p = at(ray, t);
      if (p.z < o.z_min || p.z > o.z_max) return false;
      if (normal != nullptr) {
        *normal = {0.0, ray.origin.y > o.centre.y ? 1.0 : -1.0, 0.0};
        uv[0] = p.x;
        uv[1] = p.z;
      }
      break;
    }
    case Shape::plane_z: {
      t = (o.centre.z - ray.origin.z) / d.z;
      if (!(t > kMinT && t < t_max)) return false;
      if (normal != nullptr) {
        const Vec3 p = at(ray, t);
        *normal = {0.0, 0.0, -1.0};
        uv[0] = p.x;
        uv[1] = p.y;
      }
      break;
    }
    case Shape::sphere: {
      // |o + t d - c|^2 = r^2. The discriminant is written as |d|^2 r^2 - |(o - c) x d|^2 rather
      // than B^2 - 4AC: the latter cancels catastrophically for small, distant spheres.
      const Vec3 oc = sub(ray.origin, o.centre);
      const double dd = dot(d, d);
      const Vec3 c = cross(oc, d);
      const double h = dd * o.radius * o.radius - dot(c, c);
      if (h < 0.0) return false;
      t = (-dot(oc, d) - std::sqrt(h)) / dd;  // nearer root: both terms add, no cancellation
      if (!(t > kMinT && t < t_max)) return false;
      if (normal != nullptr) {
        const Vec3 p = at(ray, t);
        const Vec3 n = {(p.x - o.centre.x) / o.radius, (p.y - o.centre.y) / o.radius,
                        (p.z - o.centre.z) / o.radius};
        *normal = n;
        // Longitude 0 faces the camera; arc lengths, so `scale` is a size on the surface.
        uv[0] = std::atan2(n.x, -n.z) * o.radius;
        uv[1] = std::asin(std::max(-1.0, std::min(1.0, n.y))) * o.radius;
      }
      break;
    }
    case Shape::cylinder_y: {
      // Infinite vertical cylinder in (x, z), then the y extent; same stable discriminant.
      const double ox = ray.origin.x - o.centre.x, oz = ray.origin.z - o.centre.z;
      const double dd = d.x * d.x + d.z * d.z;
      const double c = ox * d.z - oz * d.x;
      const double h = dd * o.radius * o.radius - c * c;
      if (h < 0.0 || dd == 0.0) return false;
      t = (-(ox * d.x + oz * d.z) - std::sqrt(h)) / dd;
      if (!(t > kMinT && t < t_max)) return false;
      const Vec3 p = at(ray, t);
      if (std::fabs(p.y - o.centre.y) > o.half.y) return false;
      if (normal != nullptr) {
        *normal = {(p.x - o.centre.x) / o.radius, 0.0, (p.z - o.centre.z) / o.radius};
        uv[0] = std::atan2(normal->x, -normal->z) * o.radius;
        uv[1] = p.y;
      }
      break;
    }
    case Shape::box: {
      // Slabs in the box's own frame (rotated by yaw about y): local = R^T (world - centre).
      const Vec3 w = sub(ray.origin, o.centre);
      {
        // Bounding sphere first (the sphere test's distance of the line from the centre).
        const Vec3 c = cross(w, d);
        if (dot(c, c) > o.bound2 * dot(d, d)) return false;
      }
      const double cy = o.cos_yaw, sy = o.sin_yaw;
      const double lo[3] = {cy * w.x - sy * w.z, w.y, sy * w.x + cy * w.z};
      const double ld[3] = {cy * d.x - sy * d.z, d.y, sy * d.x + cy * d.z};
      const double half[3] = {o.half.x, o.half.y, o.half.z};
      double t_near = -1e300, t_far = 1e300;
      int axis = -1;
      double sign = 0.0;
      for (int k = 0; k < 3; ++k) {
        if (ld[k] == 0.0) {
          if (std::fabs(lo[k]) > half[k]) return false;
          continue;
        }
        double t0 = (-half[k] - lo[k]) / ld[k], t1 = (half[k] - lo[k]) / ld[k];
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > t_near) {
          t_near = t0;
          axis = k;
          sign = ld[k] > 0.0 ? -1.0 : 1.0;  // the face the ray enters through faces the ray
        }
        t_far = std::min(t_far, t1);
      }
      if (axis < 0 || t_near > t_far) return false;
      t = t_near;
      if (!(t > kMinT && t < t_max)) return false;
      if (normal != nullptr) {
        double n[3] = {0, 0, 0};
        n[axis] = sign;
        *normal = {cy * n[0] + sy * n[2], n[1], -sy * n[0] + cy * n[2]};  // R n
        // Texture coordinates: the two local coordinates across the face, offset by the half
        // extents so that checkers start at a corner.
        const int k1 = axis == 0 ? 1 : 0, k2 = axis == 2 ? 1 : 2;
        uv[0] = lo[k1] + t * ld[k1] + half[k1];
        uv[1] = lo[k2] + t * ld[k2] + half[k2];
      }
      break;
    }
  }
  *t_out = t;
  return true;
}

void Scene::shade(const Object& o, const Vec3& n, const double uv[2], float rgb[3]) const noexcept {
  const double inv = 1.0 / o.scale;
  const double u = uv[0] * inv, v = uv[1] * inv;
  const std::uint32_t seed = o.texture_seed * 7919u + 17u;
  double mix = 0.0;      // 0: colour a, 1: colour b
  double mortar = 0.0;   // bricks: weight of the grey mortar
  double noise_amp = 0.18;
  switch (o.material) {
    case Material::floor_tiles:
    case Material::checker:
      mix = soft_checker(u, v);
      break;
    case Material::stripes:
      mix = soft_parity(u);
      break;
    case Material::bands:
      mix = soft_parity(v);
      noise_amp = 0.08;
      break;
    case Material::bricks: {
      // Bricks `scale` wide and scale/2 high; every other course offset by half a brick. Each
      // brick gets its own shade between a and b (the step between bricks is hidden under the
      // mortar); 2 cm mortar joints with 1.5 cm ramps.
      const double row = std::floor(v * 2.0);
      const double bu = u + (static_cast<std::int64_t>(row) & 1 ? 0.5 : 0.0);
      const double col = std::floor(bu);
      mix = cell_value(static_cast<std::int64_t>(col), static_cast<std::int64_t>(row), seed + 5);
      const double half_joint = 0.01 * inv, ramp = 0.015 * inv;  // in brick widths
      mortar = std::max(soft_line(bu, half_joint, ramp), soft_line(v * 2.0, 2.0 * half_joint, 2.0 * ramp));
      break;
    }
  }
  // Fine detail at 1/3 of the feature size so that a pixel moved by a fraction of a cell still
  // shows, and a view-independent (Lambert) light so that shape reads in the picture.
  const double grain = noise_amp * detail(3.0 * u, 3.0 * v, seed);
  const Vec3 light = {-0.37, 0.74, -0.56};  // unit: from the upper left, behind the camera
  const double lambert = 0.45 + 0.55 * std::max(0.0, dot(n, light));
  for (int c = 0; c < 3; ++c) {
    double base = o.color_a[c] + (o.color_b[c] - o.color_a[c]) * mix;
    base = base + (0.62 - base) * mortar;
    rgb[c] = clamp01((base + grain) * lambert);
  }
}

bool Scene::trace(const Ray& ray, Hit* hit) const noexcept {
  double best = 1e300;
  int best_index = -1;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    double t = 0.0;
    if (intersect(objects_[i], ray, best, &t, nullptr, nullptr)) {
      best = t;
      best_index = static_cast<int>(i);
    }
  }
  if (best_index < 0) return false;
  if (hit != nullptr) {
    const Object& o = objects_[static_cast<std::size_t>(best_index)];
    Vec3 normal;
    double uv[2] = {0, 0};
    double t = best;
    // Recompute the winner with its surface details (same arithmetic, so the same t).
    intersect(o, ray, 1e300, &t, &normal, uv);
    hit->z = ray.origin.z + t * ray.direction.z;
    hit->point = at(ray, t);
    hit->object = best_index;
    shade(o, normal, uv, hit->rgb);
  }
  return true;
}

Status Scene::render(const Camera& camera, View* out, int threads) const {
  if (out == nullptr) return Status(StatusCode::null_pointer, "render: null output view");
  if (camera.width <= 0 || camera.height <= 0) {
    return Status(StatusCode::invalid_size, "render: size %dx%d", camera.width, camera.height);
  }
  if (!(camera.horizontal_fov > 0.0 && camera.horizontal_fov < 3.0)) {
    return Status(StatusCode::invalid_option, "render: horizontal fov %g rad", camera.horizontal_fov);
  }
  const int w = camera.width, h = camera.height;
  out->color = Image(w, h, 3);
  out->depth = Image(w, h, 1);
  out->object.assign(static_cast<std::size_t>(w) * h, kNoObject);
  if (out->color.empty() || out->depth.empty()) {
    return Status(StatusCode::invalid_size, "render: cannot allocate %dx%d", w, h);
  }
  float* r = out->color.plane_data(0);
  float* g = out->color.plane_data(1);
  float* b = out->color.plane_data(2);
  float* z = out->depth.plane_data(0);
  const std::ptrdiff_t cs = out->color.stride(), zs = out->depth.stride();
  std::uint8_t* ids = out->object.data();

  const RayGenerator ray(camera);
  auto render_rows = [&](int first, int step) {
    for (int y = first; y < h; y += step) {
      for (int x = 0; x < w; ++x) {
        Hit hit;
        const std::ptrdiff_t ci = y * cs + x, zi = y * zs + x;
        if (trace(ray(x, y), &hit)) {
          r[ci] = hit.rgb[0];
          g[ci] = hit.rgb[1];
          b[ci] = hit.rgb[2];
          z[zi] = static_cast<float>(hit.z);
          ids[static_cast<std::size_t>(y) * w + x] = static_cast<std::uint8_t>(hit.object);
        } else {
          r[ci] = g[ci] = b[ci] = 0.0f;
          z[zi] = INFINITY;
        }
      }
    }
  };
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, h);
  // Rows interleaved over the threads: every pixel is computed the same way whichever thread
  // does it, so the image does not depend on the thread count.
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(render_rows, i, threads);
  render_rows(0, threads);
  for (std::thread& t : pool) t.join();
  return Status();
}

Status Scene::visible_in_both(const Camera& target, const Camera& source, std::vector<std::uint8_t>* out,
                              int threads) const {
  if (out == nullptr) return Status(StatusCode::null_pointer, "visible_in_both: null output");
  if (target.width <= 0 || target.height <= 0 || source.width <= 0 || source.height != target.height) {
    return Status(StatusCode::invalid_size, "visible_in_both: target %dx%d, source %dx%d", target.width,
                  target.height, source.width, source.height);
  }
  const int w = target.width, h = target.height;
  out->assign(static_cast<std::size_t>(w) * h, 0);
  std::uint8_t* mask = out->data();
  const RayGenerator target_ray(target), source_ray(source);
  const double last_column = source.width - 1.0;
  auto rows = [&](int first, int step) {
    for (int y = first; y < h; y += step) {
      for (int x = 0; x < w; ++x) {
        Hit seen, from_source;
        if (!trace(target_ray(x, y), &seen)) continue;
        double u = 0.0;
        source.project(seen.point, &u, nullptr);
        // Only the part of the source row a reprojection can read from.
        if (!(u >= 0.0 && u <= last_column)) continue;
        if (!trace(source_ray(u, y), &from_source)) continue;
        mask[static_cast<std::size_t>(y) * w + x] = std::fabs(from_source.z - seen.z) <= 1e-9 * seen.z;
      }
    }
  };
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, h);
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(rows, i, threads);
  rows(0, threads);
  for (std::thread& t : pool) t.join();
  return Status();
}

Image encode_depth(const Image& linear_z, const DepthDecoder& decoder) {
  if (linear_z.empty()) return Image();
  Image out(linear_z.width(), linear_z.height(), 1);
  if (out.empty()) return out;
  for (int y = 0; y < linear_z.height(); ++y) {
    const float* src = linear_z.plane_data(0) + y * linear_z.stride();
    float* dst = out.plane_data(0) + y * out.stride();
    for (int x = 0; x < linear_z.width(); ++x) dst[x] = decoder.encode(src[x]);
  }
  return out;
}

}  // namespace reproject::scene
