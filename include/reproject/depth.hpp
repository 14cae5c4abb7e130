// The shared depth decoder (docs/DESIGN.md §3): every encoding reduces to inverse depth w = 1/z as
//   affine:      w = A * d + B      (standard, gl_ndc, reversed, reversed_infinite, infinite, disparity)
//   reciprocal:  w = 1 / d          (linear)
// Kernels are written once per shape, never once per encoding.
#pragma once

#include <cstdint>

#include "reproject/status.hpp"

namespace reproject {

enum class DepthEncoding : std::uint8_t {
  linear,             // stored value is z itself                       w = 1/d
  standard,           // 0 at near, 1 at far (D3D; GL window depth)     w = 1/n + d (n - f)/(n f)
  gl_ndc,             // NDC z in [-1, 1]                               w = ((f + n) - d (f - n))/(2 n f)
  reversed,           // 1 at near, 0 at far                            w = 1/f + d (f - n)/(n f)
  reversed_infinite,  // 1 at near, 0 at infinity                       w = d / n
  infinite,           // 0 at near, 1 at infinity                       w = (1 - d) / n
  disparity,          // a disparity in pixels (with ParallaxModel::from_disparity)   w = d
};
constexpr int kDepthEncodingCount = 7;

// Short stable name, e.g. "reversed_infinite"; parse_encoding accepts the same names (names and
// parsers behave as reproject.hpp says before to_string(Method)).
const char* to_string(DepthEncoding encoding) noexcept;
bool parse_encoding(const char* name, DepthEncoding* out) noexcept;

class DepthDecoder {
 public:
  // Default: linear depth (w = 1/d).
  DepthDecoder() noexcept = default;

  // near/far in view-space units. far is ignored by reversed_infinite and infinite; both are
  // ignored by linear and disparity. Invalid values give a decoder whose validate() says why.
  static DepthDecoder from_near_far(DepthEncoding encoding, double near_plane, double far_plane) noexcept;
  static DepthDecoder linear() noexcept { return DepthDecoder(); }
  static DepthDecoder disparity() noexcept;

  // Reads near/far off a projection matrix, 16 floats in the API's own memory order:
  //  D3D row-vector form, row-major (P[r][c] = m[4r + c]); clip z = P[2][2] z + P[3][2], clip w = z.
  //  GL column-vector form, column-major as glUniformMatrix4fv takes it (M[r][c] = m[4c + r]).
  // `encoding` says which stored value the matrix produces (standard, gl_ndc, reversed,
  // reversed_infinite, infinite); linear and disparity give an invalid decoder.
  static DepthDecoder from_d3d_projection(const float m[16], DepthEncoding encoding) noexcept;
  static DepthDecoder from_gl_projection(const float m[16], DepthEncoding encoding) noexcept;

  Status validate() const noexcept;

  DepthEncoding encoding() const noexcept { return encoding_; }
  double near_plane() const noexcept { return near_; }
  double far_plane() const noexcept { return far_; }

  bool is_affine() const noexcept { return encoding_ != DepthEncoding::linear; }
  float A() const noexcept { return A_; }  // affine shape: w = A d + B (0 for reciprocal)
  float B() const noexcept { return B_; }

  // w = 1/z for a stored value d (affine: fma(A, d, B); reciprocal: 1/d). No clamping: values
  // beyond near/far decode to what the formula gives; the kernels define what they do with them.
  float inverse_depth(float d) const noexcept;
  // z = 1 / inverse_depth(d): +inf at infinity.
  float linear_depth(float d) const noexcept;
  // The stored value for view-space depth z (z may be +inf for the infinite encodings), computed
  // from n and f in double: the inverse of linear_depth, for tests and scene rendering.
  float encode(double z) const noexcept;

 private:
  DepthEncoding encoding_ = DepthEncoding::linear;
  double near_ = 0.0;
  double far_ = 0.0;
  float A_ = 0.0f;
  float B_ = 0.0f;
  bool valid_ = true;
};

}  // namespace reproject
