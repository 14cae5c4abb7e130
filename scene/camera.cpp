// The stereo camera of a scene: its eyes' rays and the projection back to pixels, and the
// scene's recommended stereo parameters and depth decoder.
#include <cmath>

#include "scene.hpp"
#include "scene_internal.hpp"

namespace reproject::scene {

double Camera::tan_half_fov_x() const noexcept { return std::tan(0.5 * horizontal_fov); }

double Camera::tan_half_fov_y() const noexcept {
  return tan_half_fov_x() * static_cast<double>(height) / static_cast<double>(width);
}

double Camera::eye_x() const noexcept {
  // docs/DESIGN.md §4: T = S c tan(fov/2) is half the interaxial; the eye at sigma is at 2 sigma T.
  return 2.0 * sigma * stereo.separation * stereo.convergence * tan_half_fov_x();
}

Ray Camera::ray(double u, double v) const noexcept { return RayGenerator(*this)(u, v); }

void Camera::project(const Vec3& p, double* u, double* v) const noexcept {
  const double ndc_x = (p.x - eye_x()) / (p.z * tan_half_fov_x()) + 2.0 * sigma * stereo.separation;
  const double ndc_y = p.y / (p.z * tan_half_fov_y());
  if (u != nullptr) *u = 0.5 * (ndc_x + 1.0) * width - 0.5;
  if (v != nullptr) *v = 0.5 * (1.0 - ndc_y) * height - 0.5;
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

}  // namespace reproject::scene
