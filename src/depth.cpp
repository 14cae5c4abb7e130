// The shared depth decoder (docs/DESIGN.md §3).
//
// Every perspective encoding is affine in inverse depth, w = A d + B; linear depth is the one
// reciprocal shape, w = 1 / d. A and B come from n and f in double, in the very form of the DESIGN §3 table
// (never by inverting a concatenated matrix, which loses the far end), and are rounded to float once.
#include "reproject/depth.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

#include "kernels/fma.hpp"
#include "src/nan_reason.hpp"

namespace reproject {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Why a decoder is invalid. An invalid decoder has A_ = B_ = NaN (so a caller that skips
// validate() gets NaN, never a plausible depth), and the reason rides in A_'s NaN payload: the class
// has no other room for it (the header is the contract) and validate() wants to say why.
enum class Reason : std::uint32_t {
  none = 0,
  bad_near,                // near not finite or <= 0
  bad_far,                 // far not finite or <= near (standard, gl_ndc, reversed)
  coefficient_range,       // near/far valid but A or B overflows float
  matrix_encoding,         // linear/disparity asked of a projection matrix
  matrix_not_perspective,  // clip w is not proportional to view z, or a needed entry is not finite
  bad_encoding,            // an encoding value outside the enum
};

float reason_nan(Reason reason) noexcept { return detail::nan_with_reason(reason); }
Reason reason_of(float value) noexcept { return detail::reason_in(value, Reason::bad_encoding); }

bool known_encoding(DepthEncoding e) noexcept {
  return static_cast<unsigned>(e) <= static_cast<unsigned>(DepthEncoding::disparity);
}

bool uses_far(DepthEncoding e) noexcept {
  return e == DepthEncoding::standard || e == DepthEncoding::gl_ndc || e == DepthEncoding::reversed;
}

bool uses_near(DepthEncoding e) noexcept {
  return uses_far(e) || e == DepthEncoding::reversed_infinite || e == DepthEncoding::infinite;
}

// A and B of w = A d + B in double, exactly as the DESIGN §3 table writes w. For linear (the reciprocal
// shape) both are 0, as the header promises. n and f must already be valid for the encoding.
void affine_coefficients(DepthEncoding e, double n, double f, double* A, double* B) noexcept {
  switch (e) {
    case DepthEncoding::standard:  // w = 1/n + d (n - f) / (n f)
      *A = (n - f) / (n * f);
      *B = 1.0 / n;
      return;
    case DepthEncoding::gl_ndc:  // w = ((f + n) - d (f - n)) / (2 n f)
      *A = -(f - n) / (2.0 * n * f);
      *B = (f + n) / (2.0 * n * f);
      return;
    case DepthEncoding::reversed:  // w = 1/f + d (f - n) / (n f)
      *A = (f - n) / (n * f);
      *B = 1.0 / f;
      return;
    case DepthEncoding::reversed_infinite:  // w = d / n
      *A = 1.0 / n;
      *B = 0.0;
      return;
    case DepthEncoding::infinite:  // w = (1 - d) / n; A = -B exactly, so d = 1 decodes to w = +0
      *A = -(1.0 / n);
      *B = 1.0 / n;
      return;
    case DepthEncoding::disparity:  // w = d
      *A = 1.0;
      *B = 0.0;
      return;
    case DepthEncoding::linear:
      break;
  }
  *A = 0.0;
  *B = 0.0;
}

// The stored values of an encoding at the near plane and at the far plane (or at infinity).
void stored_range(DepthEncoding e, double* d_near, double* d_far) noexcept {
  switch (e) {
    case DepthEncoding::standard:
      *d_near = 0.0;
      *d_far = 1.0;
      return;
    case DepthEncoding::gl_ndc:
      *d_near = -1.0;
      *d_far = 1.0;
      return;
    case DepthEncoding::reversed:
      *d_near = 1.0;
      *d_far = 0.0;
      return;
    case DepthEncoding::infinite:
      *d_near = 0.0;
      *d_far = 1.0;
      return;
    case DepthEncoding::reversed_infinite:
      *d_near = 1.0;
      *d_far = 0.0;
      return;
    default:
      *d_near = *d_far = std::numeric_limits<double>::quiet_NaN();
      return;
  }
}

}  // namespace

DepthDecoder DepthDecoder::disparity() noexcept {
  DepthDecoder decoder;
  decoder.encoding_ = DepthEncoding::disparity;
  decoder.A_ = 1.0f;
  decoder.B_ = 0.0f;
  return decoder;
}

DepthDecoder DepthDecoder::from_near_far(DepthEncoding encoding, double near_plane, double far_plane) noexcept {
  DepthDecoder decoder;
  decoder.encoding_ = encoding;
  auto fail = [&decoder](Reason reason) {
    decoder.valid_ = false;
    decoder.A_ = reason_nan(reason);
    decoder.B_ = std::numeric_limits<float>::quiet_NaN();
    return decoder;
  };
  if (!known_encoding(encoding)) return fail(Reason::bad_encoding);
  if (encoding == DepthEncoding::linear) return DepthDecoder();
  if (encoding == DepthEncoding::disparity) return DepthDecoder::disparity();

  // near/far are kept even when invalid, so that validate() can name them. The infinite encodings
  // have their far plane at infinity whatever was passed (the header: far is ignored).
  decoder.near_ = near_plane;
  decoder.far_ = uses_far(encoding) ? far_plane : kInf;
  if (!std::isfinite(near_plane) || !(near_plane > 0.0)) return fail(Reason::bad_near);
  if (uses_far(encoding) && (!std::isfinite(far_plane) || !(far_plane > near_plane))) return fail(Reason::bad_far);

  double A = 0.0, B = 0.0;
  affine_coefficients(encoding, decoder.near_, decoder.far_, &A, &B);
  decoder.A_ = static_cast<float>(A);
  decoder.B_ = static_cast<float>(B);
  // Extreme planes can push 1/n or the slope beyond float (overflow, or a slope flushed to 0,
  // which would decode every stored value to the same depth).
  if (!std::isfinite(decoder.A_) || !std::isfinite(decoder.B_) || decoder.A_ == 0.0f)
    return fail(Reason::coefficient_range);
  return decoder;
}

namespace {

// Stored d = k22 + k32 / z for the positive view distance z; the near and far planes are where d
// takes the encoding's near and far values:
//   n = k32 / (d_near - k22),   f = k32 / (d_far - k22).
// For an infinite encoding d_far - k22 is 0 (far = +inf), so f is not computed.
//
// D3D row vector v = (x, y, z, 1), P[r][c] = m[4r + c]: clip z = P22 z + P32, clip w = P23 z + P33.
// GL column vector v = (x, y, z_eye, 1), M[r][c] = m[4c + r]: clip z = M22 z_eye + M23,
// clip w = M32 z_eye + M33. Either way clip z comes from m[10] z_view + m[14] and clip w from
// m[11] z_view + m[15]: one form is the other's transpose and the storage orders are transposed too.
//
// Perspective: m[15] = 0 and clip w = m[11] z_view with m[11] != 0 (1 for D3D left-handed, -1 for
// GL and for D3D right-handed, since clip w = -z_eye = z). Visible points have clip w > 0, so their
// distance is z = m[11] z_view / |m[11]| and d = m[10]/m[11] + m[14] / (|m[11]| z). Dividing by
// m[11] reads either handedness (and a uniformly scaled matrix) alike; for D3D's P23 = 1 it is
// exactly DESIGN §3's n = -P32/P22, f = -P32/(P22 - 1), and for GL's M32 = -1 it is
// n = M23 / (d_near + M22), f = M23 / (d_far + M22).
Reason read_projection(const float* m, DepthEncoding encoding, double* n, double* f) noexcept {
  if (!known_encoding(encoding)) return Reason::bad_encoding;
  if (!uses_near(encoding)) return Reason::matrix_encoding;  // linear, disparity
  if (m == nullptr) return Reason::matrix_not_perspective;
  const double zz = m[10], z1 = m[14], wz = m[11], w1 = m[15];
  if (!(w1 == 0.0) || !(wz != 0.0) || !std::isfinite(wz) || !std::isfinite(zz) || !std::isfinite(z1))
    return Reason::matrix_not_perspective;
  const double k22 = zz / wz, k32 = z1 / std::fabs(wz);
  double d_near, d_far;
  stored_range(encoding, &d_near, &d_far);
  *n = k32 / (d_near - k22);
  *f = uses_far(encoding) ? k32 / (d_far - k22) : kInf;
  return Reason::none;
}

}  // namespace

DepthDecoder DepthDecoder::from_d3d_projection(const float m[16], DepthEncoding encoding) noexcept {
  double n = 0.0, f = 0.0;
  const Reason reason = read_projection(m, encoding, &n, &f);
  if (reason == Reason::none) return from_near_far(encoding, n, f);
  DepthDecoder failed;
  failed.encoding_ = encoding;
  failed.valid_ = false;
  failed.A_ = reason_nan(reason);
  failed.B_ = std::numeric_limits<float>::quiet_NaN();
  return failed;
}

// The GL matrix in glUniformMatrix4fv order occupies the same memory slots as the D3D one (see
// read_projection), so the reading is the same.
DepthDecoder DepthDecoder::from_gl_projection(const float m[16], DepthEncoding encoding) noexcept {
  return from_d3d_projection(m, encoding);
}

Status DepthDecoder::validate() const noexcept {
  if (valid_) return Status();
  const char* name = to_string(encoding_);
  switch (reason_of(A_)) {
    case Reason::bad_near:
      return Status(StatusCode::invalid_decoder,
                    "%s depth: near plane %g (given, or read off the projection matrix) must be finite and > 0", name,
                    near_);
    case Reason::bad_far:
      return Status(StatusCode::invalid_decoder,
                    "%s depth: far plane %g (given, or read off the projection matrix) must be finite and > near "
                    "plane %g",
                    name, far_, near_);
    case Reason::coefficient_range:
      return Status(StatusCode::invalid_decoder,
                    "%s depth: near plane %g, far plane %g give decode coefficients A, B outside float range", name,
                    near_, far_);
    case Reason::matrix_encoding:
      return Status(StatusCode::invalid_decoder,
                    "%s depth cannot be read off a projection matrix (use standard, gl_ndc, reversed, "
                    "reversed_infinite or infinite)",
                    name);
    case Reason::matrix_not_perspective:
      return Status(StatusCode::invalid_decoder,
                    "%s depth: the projection matrix is missing or not perspective (needs clip w proportional to "
                    "view z: finite non-zero w-from-z entry, zero w-from-1 entry)",
                    name);
    case Reason::bad_encoding:
      return Status(StatusCode::invalid_decoder, "depth encoding %u is not a known encoding",
                    static_cast<unsigned>(encoding_));
    case Reason::none:
      break;
  }
  return Status(StatusCode::invalid_decoder, "%s depth: invalid decoder (near plane %g, far plane %g)", name, near_,
                far_);
}

float DepthDecoder::inverse_depth(float d) const noexcept {
  // One fused multiply-add, the same rounding the kernels use (docs/BEHAVIOUR.md: parallax decode).
  if (is_affine()) return detail::fused_madd(A_, d, B_);
  return 1.0f / d;
}

float DepthDecoder::linear_depth(float d) const noexcept { return 1.0f / inverse_depth(d); }

float DepthDecoder::encode(double z) const noexcept {
  if (!valid_) return std::numeric_limits<float>::quiet_NaN();
  if (encoding_ == DepthEncoding::linear) return static_cast<float>(z);
  // Invert w = A d + B in double with the unrounded A, B: d = (1/z - B) / A. z = +inf gives w = 0,
  // the stored value at infinity (1 for infinite, 0 for reversed_infinite, f/(f-n) for standard).
  double A = 0.0, B = 0.0;
  affine_coefficients(encoding_, near_, far_, &A, &B);
  const double w = 1.0 / z;
  return static_cast<float>((w - B) / A);
}

}  // namespace reproject
