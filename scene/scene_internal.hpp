// What the scene's own files share (not for its users, who include scene.hpp): vector arithmetic
// and the per-camera ray generator.
#pragma once

#include "scene.hpp"

namespace reproject::scene {

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline Vec3 at(const Ray& r, double t) {
  return {r.origin.x + t * r.direction.x, r.origin.y + t * r.direction.y, r.origin.z + t * r.direction.z};
}

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

}  // namespace reproject::scene
