// The parallax model and the stereo camera (docs/DESIGN.md §4): p(w) = a + b w pixels.
#include "reproject/parallax.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "kernels/fma.hpp"
#include "src/nan_reason.hpp"

namespace reproject {
namespace {

// Why a factory refused its parameters. A refused model has a = b = NaN (so it cannot be used by
// mistake) and the reason in a's NaN payload: ParallaxModel is two floats by contract, and
// validate() should still be able to say which parameter was wrong.
enum class Reason : std::uint32_t {
  none = 0,
  convergence,   // convergence <= 0 or not finite
  separation,    // separation < 0 or not finite (also interocular / screen_width)
  width,         // width < 1
  screen_width,  // screen_width <= 0 or not finite
  direction,     // an EyeDirection outside the enum
  zero_plane,    // a relative zero-parallax plane outside 0..1
};

float reason_nan(Reason reason) noexcept { return detail::nan_with_reason(reason); }
Reason reason_of(float value) noexcept { return detail::reason_in(value, Reason::zero_plane); }

ParallaxModel refused(Reason reason) noexcept {
  ParallaxModel model;
  model.a = reason_nan(reason);
  model.b = std::numeric_limits<float>::quiet_NaN();
  return model;
}

bool known_direction(EyeDirection d) noexcept {
  return static_cast<unsigned>(d) <= static_cast<unsigned>(EyeDirection::centre_to_right);
}

}  // namespace

// sigma of DESIGN §4: the signed offset from the source eye to the target eye, in units of the
// interaxial distance (+ towards the right eye).
double eye_offset(EyeDirection direction) noexcept {
  switch (direction) {
    case EyeDirection::left_to_right:
      return 1.0;
    case EyeDirection::right_to_left:
      return -1.0;
    case EyeDirection::centre_to_left:
      return -0.5;
    case EyeDirection::centre_to_right:
      return 0.5;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

float ParallaxModel::parallax(float inverse_depth) const noexcept {
  // Fused, as the kernels round it (DESIGN §6: fma on both the scalar and the SIMD side).
  return detail::fused_madd(b, inverse_depth, a);
}

ParallaxModel ParallaxModel::from_stereo(double separation, double convergence, int width,
                                         EyeDirection direction) noexcept {
  if (!known_direction(direction)) return refused(Reason::direction);
  if (!std::isfinite(separation) || !(separation >= 0.0)) return refused(Reason::separation);
  if (!std::isfinite(convergence) || !(convergence > 0.0)) return refused(Reason::convergence);
  if (width < 1) return refused(Reason::width);
  // DESIGN §4: a = sigma S width (parallax at infinity), b = -a c (zero parallax at z = c).
  // Both in double, each rounded to float once.
  const double a = eye_offset(direction) * separation * static_cast<double>(width);
  const double b = -a * convergence;
  ParallaxModel model;
  model.a = static_cast<float>(a);
  model.b = static_cast<float>(b);
  return model;  // a huge product overflows to inf: validate() reports it
}

ParallaxModel ParallaxModel::from_physical(double interocular, double screen_width, double convergence, int width,
                                           EyeDirection direction) noexcept {
  if (!std::isfinite(screen_width) || !(screen_width > 0.0)) return refused(Reason::screen_width);
  if (!std::isfinite(interocular) || !(interocular >= 0.0)) return refused(Reason::separation);
  return from_stereo(interocular / screen_width, convergence, width, direction);
}

// A rectified pair's disparity d = x_left - x_right >= 0 (DepthEncoding::disparity decodes w = d),
// so x_right = x_left - d: left_to_right is p = -d. In general b = -sigma: the centre view sits
// half-way, so centre_to_left is p = +d/2 (b = +0.5) and centre_to_right p = -d/2 (b = -0.5), and
// (centre_to_right) - (centre_to_left) = left_to_right, as for the stereo models.
ParallaxModel ParallaxModel::from_disparity(EyeDirection direction) noexcept {
  if (!known_direction(direction)) return refused(Reason::direction);
  ParallaxModel model;
  model.a = 0.0f;
  model.b = static_cast<float>(-eye_offset(direction));
  return model;
}

// Relative inverse depth v (docs/BEHAVIOUR.md "Relative inverse depth"), decoded as w = v: the
// eyes' parallax is sigma D W (z0 - v), zero at v = z0 and D W apart from v = 0 to v = 1. As a
// stereo model it is a = sigma D W z0 (the parallax at v = 0), b = -sigma D W.
ParallaxModel ParallaxModel::from_relative(double max_parallax, double zero_plane, int width,
                                           EyeDirection direction) noexcept {
  if (!known_direction(direction)) return refused(Reason::direction);
  if (!std::isfinite(max_parallax) || !(max_parallax >= 0.0)) return refused(Reason::separation);
  if (!(zero_plane >= 0.0 && zero_plane <= 1.0)) return refused(Reason::zero_plane);
  if (width < 1) return refused(Reason::width);
  const double span = eye_offset(direction) * max_parallax * static_cast<double>(width);
  ParallaxModel model;
  model.a = static_cast<float>(span * zero_plane);
  model.b = static_cast<float>(-span);
  return model;
}

Status ParallaxModel::validate() const noexcept {
  if (std::isfinite(a) && std::isfinite(b)) return Status();
  switch (reason_of(a)) {
    case Reason::convergence:
      return Status(StatusCode::invalid_model, "parallax model: convergence must be finite and > 0");
    case Reason::separation:
      return Status(StatusCode::invalid_model,
                    "parallax model: separation (interocular / screen width, or the relative maximum parallax) must "
                    "be finite and >= 0");
    case Reason::width:
      return Status(StatusCode::invalid_model, "parallax model: image width must be >= 1");
    case Reason::screen_width:
      return Status(StatusCode::invalid_model, "parallax model: screen width must be finite and > 0");
    case Reason::direction:
      return Status(StatusCode::invalid_model, "parallax model: unknown eye direction");
    case Reason::zero_plane:
      return Status(StatusCode::invalid_model, "parallax model: the relative zero-parallax plane must be in 0..1");
    case Reason::none:
      break;
  }
  if (!std::isfinite(a))
    return Status(StatusCode::invalid_model, "parallax model: a = %g (parallax at infinity) is not finite",
                  static_cast<double>(a));
  return Status(StatusCode::invalid_model, "parallax model: b = %g (pixels per unit inverse depth) is not finite",
                static_cast<double>(b));
}

StereoCamera StereoCamera::from_physical(double interocular, double screen_width, double convergence) noexcept {
  StereoCamera camera;
  // A bad screen width or interocular gives a NaN separation, so parallax() refuses it.
  const bool ok = std::isfinite(screen_width) && screen_width > 0.0 && std::isfinite(interocular) && interocular >= 0.0;
  camera.separation = ok ? interocular / screen_width : std::numeric_limits<double>::quiet_NaN();
  camera.convergence = convergence;
  return camera;
}

// The eyes' frusta meet at the convergence plane, whose visible width is 2 c tan(fov / 2); the
// interaxial over that width is S (eye_translation, below, is the inverse: T = interaxial / 2).
StereoCamera StereoCamera::from_rig(double interaxial, double convergence, double horizontal_fov) noexcept {
  StereoCamera camera;
  constexpr double kPi = 3.14159265358979323846;
  const bool ok = std::isfinite(interaxial) && interaxial >= 0.0 && std::isfinite(convergence) && convergence > 0.0 &&
                  horizontal_fov > 0.0 && horizontal_fov < kPi;
  camera.separation = ok ? interaxial / (2.0 * convergence * std::tan(0.5 * horizontal_fov))
                         : std::numeric_limits<double>::quiet_NaN();
  camera.convergence = convergence;
  return camera;
}

// DESIGN §4: the shear clip.x += side S (clip.w - c) equals translating each eye by side T along
// x and shifting its image by side S (in NDC); matching the parallax between the convergence plane
// and infinity gives P00 T = S c with P00 = 1 / tan(fov / 2).
double StereoCamera::eye_translation(double horizontal_fov) const noexcept {
  return separation * convergence * std::tan(0.5 * horizontal_fov);
}

ParallaxModel StereoCamera::parallax(int width, EyeDirection direction) const noexcept {
  return ParallaxModel::from_stereo(separation, convergence, width, direction);
}

namespace {

// clip.x += side S (clip.w - c) (DESIGN §4), for clip = v * P with P[r][c] = m[4r + c] (D3D) or
// clip = M v with M[r][c] = m[4c + r] (GL): in both, clip x is made by m[0], m[4], m[8], m[12] and
// clip w by m[3], m[7], m[11], m[15]. So add side S times the clip-w entries to the clip-x ones and
// subtract side S c from the constant one. For the usual matrices (clip w = z, i.e. m[11] = 1 for
// D3D, -1 for GL, other w entries 0) this is exactly the header's P20 += side S, P30 -= side S c
// (D3D) and M02 -= side S, M03 -= side S c (GL); written generally it also shears right-handed
// D3D matrices the right way. Double arithmetic, one rounding per entry; `out` may alias `mono`.
void shear(const float mono[16], double side_s, double convergence, float out[16]) noexcept {
  float in[16];
  std::memcpy(in, mono, sizeof in);
  std::memcpy(out, in, sizeof in);
  for (int r = 0; r < 4; ++r) {
    double x = static_cast<double>(in[4 * r]) + side_s * static_cast<double>(in[4 * r + 3]);
    if (r == 3) x -= side_s * convergence;
    out[4 * r] = static_cast<float>(x);
  }
}

double side_of(Eye eye) noexcept { return eye == Eye::left ? -1.0 : 1.0; }

}  // namespace

void StereoCamera::projection_d3d(const float mono[16], Eye eye, float out[16]) const noexcept {
  if (mono == nullptr || out == nullptr) return;
  shear(mono, side_of(eye) * separation, convergence, out);
}

void StereoCamera::projection_gl(const float mono[16], Eye eye, float out[16]) const noexcept {
  if (mono == nullptr || out == nullptr) return;
  shear(mono, side_of(eye) * separation, convergence, out);
}

}  // namespace reproject
