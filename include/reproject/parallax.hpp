// The parallax model (docs/DESIGN.md §4): a point at inverse depth w seen at source x appears in the
// target at x + p(w), with p(w) = a + b w pixels.
#pragma once

#include <cstdint>

#include "reproject/status.hpp"

namespace reproject {

// Which eye is synthesised from which view; gives the signed eye offset sigma of DESIGN §4.
enum class EyeDirection : std::uint8_t {
  left_to_right,    // sigma = +1
  right_to_left,    // sigma = -1
  centre_to_left,   // sigma = -1/2
  centre_to_right,  // sigma = +1/2
};
constexpr int kEyeDirectionCount = 4;
// "left-to-right", ...; parse_direction also accepts the underscore spelling ("left_to_right").
// Names and parsers behave as reproject.hpp says before to_string(Method).
const char* to_string(EyeDirection direction) noexcept;
bool parse_direction(const char* name, EyeDirection* out) noexcept;
double eye_offset(EyeDirection direction) noexcept;                   // sigma

enum class Eye : std::uint8_t { left, right };

struct ParallaxModel {
  float a = 0.0f;  // parallax at infinity (w = 0), pixels
  float b = 0.0f;  // pixels per unit of inverse depth

  // p(w) = a + b w, fused (the kernels' rounding).
  float parallax(float inverse_depth) const noexcept;

  // Stereo camera with parallel axes and sheared frusta converging at `convergence`:
  // a = sigma * separation * width, b = -a * convergence. separation = interaxial / virtual
  // screen width (0 .. ~0.1); width = source image width in pixels (without guard band).
  static ParallaxModel from_stereo(double separation, double convergence, int width,
                                   EyeDirection direction) noexcept;
  // Physical units: separation = interocular / screen_width (same length unit for both).
  static ParallaxModel from_physical(double interocular, double screen_width, double convergence,
                                     int width, EyeDirection direction) noexcept;
  // Rectified pair with a disparity map (DepthEncoding::disparity): left_to_right gives
  // p = -disparity (a = 0, b = -1); right_to_left gives p = +disparity.
  static ParallaxModel from_disparity(EyeDirection direction = EyeDirection::left_to_right) noexcept;
  // Relative inverse depth v (a monocular depth model's output: 0 the farthest, 1 the nearest,
  // decoded by DepthDecoder::disparity() as w = v; docs/BEHAVIOUR.md "Relative inverse depth"):
  // p = sigma * max_parallax * width * (zero_plane - v). max_parallax (>= 0, a fraction of the
  // width) is the parallax between the eyes from v = 0 to v = 1; zero_plane (0..1) is the v on
  // the screen (zero parallax): nearer values come out in front of it.
  static ParallaxModel from_relative(double max_parallax, double zero_plane, int width,
                                     EyeDirection direction) noexcept;

  // invalid_model when a or b is not finite, or when a factory got convergence <= 0, a negative
  // or non-finite separation (or max_parallax), width < 1, screen_width <= 0 or a zero_plane
  // outside 0..1 (such factories return NaN a, b).
  Status validate() const noexcept;
};

// The standard stereo projection (DESIGN §4): each eye's clip x is shifted by
// side * separation * (clip.w - convergence), side = -1 left, +1 right.
struct StereoCamera {
  double separation = 0.0;   // interaxial / virtual screen width
  double convergence = 1.0;  // view-space distance of the zero-parallax plane

  static StereoCamera from_physical(double interocular, double screen_width, double convergence) noexcept;
  // A renderer's rig (Blender's off-axis stereo: interocular distance, convergence distance, the
  // camera's horizontal field of view in radians): S = interaxial / (2 convergence tan(fov / 2)),
  // the interaxial over the width of the view at the convergence distance. interaxial and
  // convergence in one unit (the scene's). A negative or non-finite interaxial, a convergence
  // <= 0 or a field of view outside (0, pi) gives a NaN separation, which parallax() refuses.
  static StereoCamera from_rig(double interaxial, double convergence, double horizontal_fov) noexcept;
  // Half the interaxial distance in view-space units: T = separation * convergence * tan(fov/2),
  // the camera translation equivalent to the projection shear. fov in radians.
  double eye_translation(double horizontal_fov) const noexcept;
  ParallaxModel parallax(int width, EyeDirection direction) const noexcept;

  // The eye's projection from a mono one, in the same memory order as DepthDecoder takes:
  // D3D row-major row-vector (P[2][0] += side S, P[3][0] -= side S c) or
  // GL column-major column-vector (M[0][2] -= side S, M[0][3] -= side S c, since clip.w = -z_eye).
  void projection_d3d(const float mono[16], Eye eye, float out[16]) const noexcept;
  void projection_gl(const float mono[16], Eye eye, float out[16]) const noexcept;
};

}  // namespace reproject
