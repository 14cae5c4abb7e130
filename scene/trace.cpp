// Ray casting: where a ray meets each kind of object, and the first surface it meets.
#include <algorithm>
#include <cmath>
#include <utility>

#include "scene.hpp"
#include "scene_internal.hpp"

namespace reproject::scene {
namespace {

// Hits closer than this (in ray parameter, i.e. view-space depth) are ignored: no surface of a
// scene is that close to an eye.
constexpr double kMinT = 1e-6;

}  // namespace

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

}  // namespace reproject::scene
