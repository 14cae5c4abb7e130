// The shared depth decoder (docs/DESIGN.md §3, include/reproject/depth.hpp).
//
// Tolerances. Depth buffers are float, so the stored value itself is rounded (relative 2^-24) and
// the decode w = A d + B cancels for the forward encodings (standard, gl_ndc, infinite) where
// |A d| and |B| are both ~1/n while w = 1/z is small: the relative error of z is then bounded by
// about u (2 |A d| + |B| + 2 |w|) / |w|, u = 2^-24, which is ~ u z / n, not by a fixed 1e-5. Where
// that bound is below 1e-5 the tests ask for 1e-5; beyond it they ask for the bound (a wrong formula
// is off by O(1) either way). Reversed, reversed-infinite, linear and disparity have no such
// cancellation and are held to 1e-5 everywhere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "kernels/fma.hpp"
#include "reproject/depth.hpp"

namespace reproject {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kU = 0x1p-24;  // unit roundoff of float

const DepthEncoding kAllEncodings[] = {
    DepthEncoding::linear,   DepthEncoding::standard,          DepthEncoding::gl_ndc,
    DepthEncoding::reversed, DepthEncoding::reversed_infinite, DepthEncoding::infinite,
    DepthEncoding::disparity};

struct NearFar {
  double n, f;
};
const NearFar kPairs[] = {{0.1, 1000.0}, {1.0, 100.0}, {0.5, 50.0}, {0.01, 10.0}, {3.0, 7.0}};

std::vector<double> log_space(double lo, double hi, int count) {
  std::vector<double> out;
  for (int i = 0; i < count; ++i) out.push_back(lo * std::pow(hi / lo, static_cast<double>(i) / (count - 1)));
  out.front() = lo;  // exactly the ends
  out.back() = hi;
  return out;
}

double rel_err(double got, double want) { return std::fabs(got - want) / std::fabs(want); }

// The float-storage bound of the header comment for a decoder whose A, B are (A, B) at stored d.
double storage_bound(double A, double B, double d) {
  const double w = A * d + B;
  return kU * (2.0 * std::fabs(A * d) + std::fabs(B) + 2.0 * std::fabs(w)) / std::fabs(w);
}

bool no_cancellation(DepthEncoding e) {
  return e == DepthEncoding::linear || e == DepthEncoding::reversed || e == DepthEncoding::reversed_infinite ||
         e == DepthEncoding::disparity;
}

// ---------------------------------------------------------------------------------------------
// Textbook projection matrices, built in double from the published formulas, then stored as the
// float[16] the API takes.

// D3D left-handed (D3DXMatrixPerspectiveFovLH), row-vector, row-major P[r][c] = m[4r + c]:
//   xs 0 0 0 / 0 ys 0 0 / 0 0 Q 1 / 0 0 -Q n 0, Q = f / (f - n).
// `encoding` picks the depth row: standard as above; reversed = standard with n and f swapped;
// infinite = its limit f -> inf (Q = 1); reversed_infinite (Q = 0, P32 = n).
struct Matrix {
  float m[16];
};

Matrix d3d_lh(DepthEncoding e, double n, double f, double fovy = 1.0, double aspect = 16.0 / 9.0) {
  double P[4][4] = {};
  const double ys = 1.0 / std::tan(fovy / 2.0), xs = ys / aspect;
  P[0][0] = xs;
  P[1][1] = ys;
  P[2][3] = 1.0;
  switch (e) {
    case DepthEncoding::standard:
      P[2][2] = f / (f - n);
      P[3][2] = -n * f / (f - n);
      break;
    case DepthEncoding::reversed:
      P[2][2] = n / (n - f);
      P[3][2] = -f * n / (n - f);
      break;
    case DepthEncoding::infinite:
      P[2][2] = 1.0;
      P[3][2] = -n;
      break;
    case DepthEncoding::reversed_infinite:
      P[2][2] = 0.0;
      P[3][2] = n;
      break;
    default:
      ADD_FAILURE() << "no D3D matrix for " << to_string(e);
  }
  Matrix out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out.m[4 * r + c] = static_cast<float>(P[r][c]);
  return out;
}

// D3DXMatrixPerspectiveFovRH: view z is negative in front; Q = f / (n - f), P23 = -1, P32 = n Q.
Matrix d3d_rh_standard(double n, double f, double fovy = 1.0, double aspect = 16.0 / 9.0) {
  double P[4][4] = {};
  const double ys = 1.0 / std::tan(fovy / 2.0), xs = ys / aspect;
  P[0][0] = xs;
  P[1][1] = ys;
  P[2][2] = f / (n - f);
  P[2][3] = -1.0;
  P[3][2] = n * f / (n - f);
  Matrix out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out.m[4 * r + c] = static_cast<float>(P[r][c]);
  return out;
}

// GL column-vector, column-major M[r][c] = m[4c + r].
Matrix gl_from(const double M[4][4]) {
  Matrix out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out.m[4 * c + r] = static_cast<float>(M[r][c]);
  return out;
}

// glFrustum(l, r, b, t, n, f) (NDC z in [-1, 1]): 2n/(r-l) 0 (r+l)/(r-l) 0 / 0 2n/(t-b) (t+b)/(t-b) 0
// / 0 0 -(f+n)/(f-n) -2fn/(f-n) / 0 0 -1 0. gluPerspective is the symmetric case.
Matrix gl_frustum(double l, double r, double b, double t, double n, double f) {
  double M[4][4] = {};
  M[0][0] = 2.0 * n / (r - l);
  M[0][2] = (r + l) / (r - l);
  M[1][1] = 2.0 * n / (t - b);
  M[1][2] = (t + b) / (t - b);
  M[2][2] = -(f + n) / (f - n);
  M[2][3] = -2.0 * f * n / (f - n);
  M[3][2] = -1.0;
  return gl_from(M);
}

// gluPerspective(fovy, aspect, n, f): F = cot(fovy/2); F/aspect, F, (f+n)/(n-f), 2fn/(n-f), -1.
Matrix glu_perspective(double fovy, double aspect, double n, double f) {
  double M[4][4] = {};
  const double F = 1.0 / std::tan(fovy / 2.0);
  M[0][0] = F / aspect;
  M[1][1] = F;
  M[2][2] = (f + n) / (n - f);
  M[2][3] = 2.0 * f * n / (n - f);
  M[3][2] = -1.0;
  return gl_from(M);
}

// GL with glClipControl(..., GL_ZERO_TO_ONE) (glm's perspectiveRH_ZO and its reversed and infinite
// variants): stored d = NDC z = -M22 + M23 / z.
//   standard: M22 = f/(n-f), M23 = -fn/(f-n);     reversed: M22 = n/(f-n), M23 = fn/(f-n);
//   infinite: M22 = -1, M23 = -n;                  reversed_infinite: M22 = 0, M23 = n.
Matrix gl_zero_to_one(DepthEncoding e, double n, double f, double fovy = 1.0, double aspect = 16.0 / 9.0) {
  double M[4][4] = {};
  const double F = 1.0 / std::tan(fovy / 2.0);
  M[0][0] = F / aspect;
  M[1][1] = F;
  M[3][2] = -1.0;
  switch (e) {
    case DepthEncoding::standard:
      M[2][2] = f / (n - f);
      M[2][3] = -f * n / (f - n);
      break;
    case DepthEncoding::reversed:
      M[2][2] = n / (f - n);
      M[2][3] = f * n / (f - n);
      break;
    case DepthEncoding::infinite:
      M[2][2] = -1.0;
      M[2][3] = -n;
      break;
    case DepthEncoding::reversed_infinite:
      M[2][2] = 0.0;
      M[2][3] = n;
      break;
    default:
      ADD_FAILURE() << "no GL matrix for " << to_string(e);
  }
  return gl_from(M);
}

// Stored depth of a point at distance z through a D3D matrix (row vector, view z = +z, or -z for a
// right-handed one) and a GL one (column vector, z_eye = -z), in double from the float entries.
double d3d_stored(const Matrix& P, double z_view) {
  const double v[4] = {0.25, -0.5, z_view, 1.0};
  double clip[4] = {};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) clip[c] += v[r] * static_cast<double>(P.m[4 * r + c]);
  return clip[2] / clip[3];
}
double gl_stored(const Matrix& M, double z) {
  const double v[4] = {0.25, -0.5, -z, 1.0};
  double clip[4] = {};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) clip[r] += static_cast<double>(M.m[4 * c + r]) * v[c];
  return clip[2] / clip[3];
}

// How well a float matrix pins n (or f): the entries d = k22 + k32/z are rounded to float, and
// x = k32 / (d_x - k22) amplifies k22's rounding by |k22| / |d_x - k22|.
double plane_tolerance(double k22, double d_x) {
  const double cond = 1.0 + std::fabs(k22) / std::fabs(d_x - k22);
  return std::max(1e-5, 2.0 * FLT_EPSILON * cond);
}

// ---------------------------------------------------------------------------------------------

TEST(DepthEncodingNames, RoundTripAndRejects) {
  const char* const expected[] = {"linear",   "standard", "gl_ndc", "reversed", "reversed_infinite",
                                  "infinite", "disparity"};
  int i = 0;
  for (DepthEncoding e : kAllEncodings) {
    EXPECT_STREQ(to_string(e), expected[i++]);
    DepthEncoding parsed = DepthEncoding::linear;
    ASSERT_TRUE(parse_encoding(to_string(e), &parsed));
    EXPECT_EQ(parsed, e);
  }
  DepthEncoding untouched = DepthEncoding::gl_ndc;
  for (const char* bad : {"", "Standard", "gl-ndc", "reversed infinite", "linear ", "none"})
    EXPECT_FALSE(parse_encoding(bad, &untouched)) << bad;
  EXPECT_EQ(untouched, DepthEncoding::gl_ndc);
  EXPECT_FALSE(parse_encoding(nullptr, &untouched));
  // A null out only checks the name (every enum's parser does so: src/names.hpp).
  EXPECT_TRUE(parse_encoding("linear", nullptr));
  EXPECT_FALSE(parse_encoding("Linear", nullptr));
}

TEST(DepthDecoder, DefaultIsLinearReciprocal) {
  const DepthDecoder decoder;
  EXPECT_TRUE(decoder.validate().ok());
  EXPECT_EQ(decoder.encoding(), DepthEncoding::linear);
  EXPECT_FALSE(decoder.is_affine());
  EXPECT_EQ(decoder.A(), 0.0f);
  EXPECT_EQ(decoder.B(), 0.0f);
  for (float d : {0.1f, 1.0f, 3.0f, 1234.5f}) {
    EXPECT_EQ(decoder.inverse_depth(d), 1.0f / d);
    EXPECT_EQ(decoder.linear_depth(d), 1.0f / (1.0f / d));
  }
  EXPECT_EQ(decoder.inverse_depth(0.0f), std::numeric_limits<float>::infinity());
  EXPECT_EQ(DepthDecoder::linear().encoding(), DepthEncoding::linear);
  const DepthDecoder disparity = DepthDecoder::disparity();
  EXPECT_TRUE(disparity.validate().ok());
  EXPECT_TRUE(disparity.is_affine());
  EXPECT_EQ(disparity.inverse_depth(12.5f), 12.5f);  // w = d
}

// linear_depth(encode(z)) == z over [n, f], log-spaced, every encoding and several n/f pairs.
TEST(DepthDecoder, RoundTripOverNearFar) {
  for (DepthEncoding e : kAllEncodings) {
    double worst = 0.0, worst_ratio = 0.0, worst_near = 0.0;  // worst_near: z <= 10 n
    for (const NearFar& p : kPairs) {
      const DepthDecoder decoder = DepthDecoder::from_near_far(e, p.n, p.f);
      ASSERT_TRUE(decoder.validate().ok()) << to_string(e) << " " << decoder.validate().message();
      EXPECT_EQ(decoder.encoding(), e);
      for (double z : log_space(p.n, p.f, 400)) {
        const float d = decoder.encode(z);
        const double got = decoder.linear_depth(d);
        const double err = rel_err(got, z);
        const double bound = no_cancellation(e) ? 0.0 : storage_bound(decoder.A(), decoder.B(), d);
        const double tol = std::max(1e-5, bound);
        EXPECT_LE(err, tol) << to_string(e) << " n=" << p.n << " f=" << p.f << " z=" << z << " d=" << d;
        worst = std::max(worst, err);
        if (bound > 0.0) worst_ratio = std::max(worst_ratio, err / bound);
        if (z <= 10.0 * p.n) worst_near = std::max(worst_near, err);
      }
      // The ends land on the encoding's stored range (0/1, -1/1, 1/0) to float rounding.
      if (e != DepthEncoding::linear && e != DepthEncoding::disparity) {
        const float at_near = decoder.encode(p.n);
        const float expect_near = (e == DepthEncoding::gl_ndc)                                              ? -1.0f
                                  : (e == DepthEncoding::reversed || e == DepthEncoding::reversed_infinite) ? 1.0f
                                                                                                            : 0.0f;
        EXPECT_NEAR(at_near, expect_near, 1e-6) << to_string(e);
      }
      if (e == DepthEncoding::standard || e == DepthEncoding::gl_ndc) {
        EXPECT_NEAR(decoder.encode(p.f), 1.0f, 1e-6);
      }
      if (e == DepthEncoding::reversed) {
        EXPECT_NEAR(decoder.encode(p.f), 0.0f, 1e-9);
      }
    }
    // Near the camera every encoding meets 1e-5 (the storage bound is small there).
    EXPECT_LE(worst_near, 1e-5) << to_string(e);
    std::printf("  %-17s worst relative error %.3g (z <= 10 n: %.3g)", to_string(e), worst, worst_near);
    if (worst_ratio > 0.0) std::printf(", worst / float-storage bound %.3f", worst_ratio);
    std::printf("\n");
  }
}

// A and B are the DESIGN §3 table's coefficients in double rounded once, and the decode is exactly the
// fused affine map (bit for bit), also outside [near, far].
TEST(DepthDecoder, AffineCoefficientsAreTheDesignFormulas) {
  for (const NearFar& p : kPairs) {
    const double n = p.n, f = p.f;
    struct Expect {
      DepthEncoding e;
      double A, B;
    } const cases[] = {
        {DepthEncoding::standard, (n - f) / (n * f), 1.0 / n},
        {DepthEncoding::gl_ndc, -(f - n) / (2.0 * n * f), (f + n) / (2.0 * n * f)},
        {DepthEncoding::reversed, (f - n) / (n * f), 1.0 / f},
        {DepthEncoding::reversed_infinite, 1.0 / n, 0.0},
        {DepthEncoding::infinite, -1.0 / n, 1.0 / n},
    };
    for (const Expect& c : cases) {
      const DepthDecoder decoder = DepthDecoder::from_near_far(c.e, n, f);
      ASSERT_TRUE(decoder.validate().ok());
      EXPECT_TRUE(decoder.is_affine());
      EXPECT_EQ(decoder.A(), static_cast<float>(c.A)) << to_string(c.e) << " n=" << n << " f=" << f;
      EXPECT_EQ(decoder.B(), static_cast<float>(c.B)) << to_string(c.e) << " n=" << n << " f=" << f;
      EXPECT_EQ(decoder.near_plane(), n);
      if (c.e == DepthEncoding::infinite || c.e == DepthEncoding::reversed_infinite) {
        EXPECT_EQ(decoder.far_plane(), kInf);
      } else {
        EXPECT_EQ(decoder.far_plane(), f);
      }
      // Independently of the algebra: the coefficients put 1/n and 1/f (or 0) at the stored range.
      double d_near = 0.0, d_far = 1.0;
      if (c.e == DepthEncoding::gl_ndc) d_near = -1.0;
      if (c.e == DepthEncoding::reversed || c.e == DepthEncoding::reversed_infinite) d_near = 1.0, d_far = 0.0;
      const double far_w = (c.e == DepthEncoding::infinite || c.e == DepthEncoding::reversed_infinite) ? 0.0 : 1.0 / f;
      EXPECT_NEAR(decoder.A() * d_near + decoder.B(), 1.0 / n, 4e-7 / n) << to_string(c.e);
      EXPECT_NEAR(decoder.A() * d_far + decoder.B(), far_w, 4e-7 / n) << to_string(c.e);
      for (float d : {-3.0f, -1.0f, -0.25f, 0.0f, 1e-7f, 0.3f, 0.5f, 0.999f, 1.0f, 1.5f, 42.0f}) {
        const float w = decoder.inverse_depth(d);
        // Rounded once; not std::fma, which MinGW-w64's C library does not round once (docs/DESIGN.md
        // §8): the software form, which tests/test_fma.cpp holds to the FMA instruction.
        EXPECT_EQ(w, reproject::detail::fma_in_software(decoder.A(), d, decoder.B())) << to_string(c.e) << " d=" << d;
        EXPECT_EQ(decoder.linear_depth(d), 1.0f / w);
      }
    }
  }
}

// Infinite encodings: z = inf is stored as 1 (infinite) or 0 (reversed_infinite) and decodes to
// w = +0 exactly (linear depth +inf); very far points stay within tolerance.
TEST(DepthDecoder, InfiniteEncodingsAtInfinity) {
  for (double n : {0.01, 0.1, 1.0, 3.0}) {
    const DepthDecoder inf = DepthDecoder::from_near_far(DepthEncoding::infinite, n, std::nan(""));
    const DepthDecoder rev = DepthDecoder::from_near_far(DepthEncoding::reversed_infinite, n, -5.0);
    ASSERT_TRUE(inf.validate().ok()) << "far is ignored: " << inf.validate().message();
    ASSERT_TRUE(rev.validate().ok()) << "far is ignored: " << rev.validate().message();
    EXPECT_EQ(inf.encode(kInf), 1.0f);
    EXPECT_EQ(rev.encode(kInf), 0.0f);
    for (const DepthDecoder* decoder : {&inf, &rev}) {
      const float w = decoder->inverse_depth(decoder->encode(kInf));
      EXPECT_EQ(w, 0.0f);
      EXPECT_FALSE(std::signbit(w));
      EXPECT_EQ(decoder->linear_depth(decoder->encode(kInf)), std::numeric_limits<float>::infinity());
    }
    double worst_rev = 0.0;
    for (double z : log_space(n, n * 1e7, 300)) {
      const float d_rev = rev.encode(z);
      const double err_rev = rel_err(rev.linear_depth(d_rev), z);
      EXPECT_LE(err_rev, 1e-5) << "reversed_infinite n=" << n << " z=" << z;
      worst_rev = std::max(worst_rev, err_rev);
      const float d_inf = inf.encode(z);
      if (d_inf == 1.0f) {
        // Float cannot tell z from infinity here (1 - n/z rounds to 1): z must be that far.
        EXPECT_GE(z, n * 1e7 * 0.5) << "infinite n=" << n;
        continue;
      }
      EXPECT_LE(rel_err(inf.linear_depth(d_inf), z), std::max(1e-5, storage_bound(inf.A(), inf.B(), d_inf)))
          << "infinite n=" << n << " z=" << z;
    }
    EXPECT_LE(worst_rev, 1e-5);
  }
}

// near/far read off textbook D3D matrices (row-vector, row-major), rounded to float.
TEST(DepthDecoder, NearFarFromD3DMatrices) {
  double worst_n = 0.0, worst_f = 0.0;
  for (const NearFar& p : kPairs) {
    for (DepthEncoding e : {DepthEncoding::standard, DepthEncoding::reversed, DepthEncoding::infinite,
                            DepthEncoding::reversed_infinite}) {
      const Matrix P = d3d_lh(e, p.n, p.f);
      const DepthDecoder decoder = DepthDecoder::from_d3d_projection(P.m, e);
      ASSERT_TRUE(decoder.validate().ok()) << to_string(e) << ": " << decoder.validate().message();
      EXPECT_EQ(decoder.encoding(), e);
      const double k22 = P.m[10];
      const double d_near = (e == DepthEncoding::reversed || e == DepthEncoding::reversed_infinite) ? 1.0 : 0.0;
      const double err_n = rel_err(decoder.near_plane(), p.n);
      EXPECT_LE(err_n, plane_tolerance(k22, d_near)) << to_string(e) << " n=" << p.n << " f=" << p.f;
      worst_n = std::max(worst_n, err_n);
      if (e == DepthEncoding::standard || e == DepthEncoding::reversed) {
        const double err_f = rel_err(decoder.far_plane(), p.f);
        EXPECT_LE(err_f, plane_tolerance(k22, 1.0 - d_near)) << to_string(e) << " n=" << p.n << " f=" << p.f;
        worst_f = std::max(worst_f, err_f);
        if (e == DepthEncoding::reversed) {
          EXPECT_LE(err_f, 1e-6) << "reversed pins f";
        }
      } else {
        EXPECT_EQ(decoder.far_plane(), kInf);
      }
      // And the decoder inverts what the matrix stores (points behind far are fine for infinite).
      for (double z : log_space(p.n, p.f, 50)) {
        const float d = static_cast<float>(d3d_stored(P, z));
        const double tol = std::max(1e-5, storage_bound(decoder.A(), decoder.B(), d) + 4.0 * kU);
        EXPECT_LE(rel_err(decoder.linear_depth(d), z), tol) << to_string(e) << " z=" << z;
      }
    }
    // Right-handed D3D (view z negative in front, P23 = -1) reads the same planes.
    const Matrix rh = d3d_rh_standard(p.n, p.f);
    const DepthDecoder decoder = DepthDecoder::from_d3d_projection(rh.m, DepthEncoding::standard);
    ASSERT_TRUE(decoder.validate().ok()) << decoder.validate().message();
    EXPECT_LE(rel_err(decoder.near_plane(), p.n), 1e-6);
    EXPECT_LE(rel_err(decoder.far_plane(), p.f), plane_tolerance(p.f / (p.f - p.n), 1.0));
    const float d_mid = static_cast<float>(d3d_stored(rh, -std::sqrt(p.n * p.f)));
    EXPECT_LE(rel_err(decoder.linear_depth(d_mid), std::sqrt(p.n * p.f)), 1e-4);
  }
  // The standard pair n = 1, f = 100 is well conditioned: both planes to 1e-5.
  const Matrix P = d3d_lh(DepthEncoding::standard, 1.0, 100.0);
  const DepthDecoder decoder = DepthDecoder::from_d3d_projection(P.m, DepthEncoding::standard);
  EXPECT_LE(rel_err(decoder.near_plane(), 1.0), 1e-6);
  EXPECT_LE(rel_err(decoder.far_plane(), 100.0), 1e-5);
  std::printf("  D3D: worst relative error near %.3g, far %.3g (far of standard is ill-conditioned in float)\n",
              worst_n, worst_f);
}

// near/far read off textbook GL matrices (column-vector, column-major).
TEST(DepthDecoder, NearFarFromGLMatrices) {
  double worst_n = 0.0, worst_f = 0.0;
  for (const NearFar& p : kPairs) {
    struct Case {
      const char* name;
      Matrix M;
      DepthEncoding e;
    } const cases[] = {
        {"gluPerspective", glu_perspective(1.1, 4.0 / 3.0, p.n, p.f), DepthEncoding::gl_ndc},
        {"glFrustum off-centre", gl_frustum(-0.3 * p.n, 0.5 * p.n, -0.2 * p.n, 0.4 * p.n, p.n, p.f),
         DepthEncoding::gl_ndc},
        {"zero-to-one", gl_zero_to_one(DepthEncoding::standard, p.n, p.f), DepthEncoding::standard},
        {"zero-to-one reversed", gl_zero_to_one(DepthEncoding::reversed, p.n, p.f), DepthEncoding::reversed},
        {"zero-to-one infinite", gl_zero_to_one(DepthEncoding::infinite, p.n, p.f), DepthEncoding::infinite},
        {"zero-to-one reversed infinite", gl_zero_to_one(DepthEncoding::reversed_infinite, p.n, p.f),
         DepthEncoding::reversed_infinite},
    };
    for (const Case& c : cases) {
      const DepthDecoder decoder = DepthDecoder::from_gl_projection(c.M.m, c.e);
      ASSERT_TRUE(decoder.validate().ok()) << c.name << ": " << decoder.validate().message();
      EXPECT_EQ(decoder.encoding(), c.e);
      const double k22 = -static_cast<double>(c.M.m[10]);  // d = -M22 + M23 / z
      const double d_near = c.e == DepthEncoding::gl_ndc                                                  ? -1.0
                            : (c.e == DepthEncoding::reversed || c.e == DepthEncoding::reversed_infinite) ? 1.0
                                                                                                          : 0.0;
      const double d_far = c.e == DepthEncoding::gl_ndc ? 1.0 : 1.0 - d_near;
      const double err_n = rel_err(decoder.near_plane(), p.n);
      EXPECT_LE(err_n, plane_tolerance(k22, d_near)) << c.name << " n=" << p.n << " f=" << p.f;
      worst_n = std::max(worst_n, err_n);
      if (c.e == DepthEncoding::infinite || c.e == DepthEncoding::reversed_infinite) {
        EXPECT_EQ(decoder.far_plane(), kInf) << c.name;
      } else {
        const double err_f = rel_err(decoder.far_plane(), p.f);
        EXPECT_LE(err_f, plane_tolerance(k22, d_far)) << c.name << " n=" << p.n << " f=" << p.f;
        worst_f = std::max(worst_f, err_f);
      }
      for (double z : log_space(p.n, p.f, 50)) {
        const float d = static_cast<float>(gl_stored(c.M, z));
        const double tol = std::max(1e-5, storage_bound(decoder.A(), decoder.B(), d) + 4.0 * kU);
        EXPECT_LE(rel_err(decoder.linear_depth(d), z), tol) << c.name << " z=" << z;
      }
    }
  }
  const Matrix M = glu_perspective(1.0, 1.5, 1.0, 100.0);
  const DepthDecoder decoder = DepthDecoder::from_gl_projection(M.m, DepthEncoding::gl_ndc);
  EXPECT_LE(rel_err(decoder.near_plane(), 1.0), 1e-6);
  EXPECT_LE(rel_err(decoder.far_plane(), 100.0), 1e-5);
  std::printf("  GL: worst relative error near %.3g, far %.3g\n", worst_n, worst_f);
}

void expect_invalid(const DepthDecoder& decoder, const char* must_mention, const std::string& what) {
  const Status status = decoder.validate();
  EXPECT_FALSE(status.ok()) << what;
  EXPECT_EQ(status.code(), StatusCode::invalid_decoder) << what;
  if (must_mention) {
    EXPECT_NE(std::strstr(status.message(), must_mention), nullptr) << what << ": " << status.message();
  }
  // An invalid decoder never decodes to a plausible depth.
  if (decoder.is_affine()) {
    EXPECT_TRUE(std::isnan(decoder.inverse_depth(0.5f))) << what;
  }
}

TEST(DepthDecoder, InvalidNearFar) {
  const double nan = std::nan("");
  for (DepthEncoding e : {DepthEncoding::standard, DepthEncoding::gl_ndc, DepthEncoding::reversed}) {
    const std::string name = to_string(e);
    expect_invalid(DepthDecoder::from_near_far(e, 0.0, 10.0), "near plane 0", name + " n=0");
    expect_invalid(DepthDecoder::from_near_far(e, -0.5, 10.0), "-0.5", name + " n<0");
    expect_invalid(DepthDecoder::from_near_far(e, nan, 10.0), "nan", name + " n=nan");
    expect_invalid(DepthDecoder::from_near_far(e, kInf, 10.0), "inf", name + " n=inf");
    expect_invalid(DepthDecoder::from_near_far(e, 2.0, 2.0), "must be finite and > near plane 2", name + " f=n");
    expect_invalid(DepthDecoder::from_near_far(e, 2.0, 1.5), "1.5", name + " f<n");
    expect_invalid(DepthDecoder::from_near_far(e, 2.0, kInf), "inf", name + " f=inf");
    expect_invalid(DepthDecoder::from_near_far(e, 2.0, nan), "nan", name + " f=nan");
    expect_invalid(DepthDecoder::from_near_far(e, 2.0, -7.0), "-7", name + " f<0");
    EXPECT_TRUE(std::isnan(DepthDecoder::from_near_far(e, -1.0, 10.0).encode(3.0)));
  }
  for (DepthEncoding e : {DepthEncoding::infinite, DepthEncoding::reversed_infinite}) {
    expect_invalid(DepthDecoder::from_near_far(e, 0.0, 10.0), "near plane 0", to_string(e));
    expect_invalid(DepthDecoder::from_near_far(e, -3.0, 10.0), "-3", to_string(e));
    expect_invalid(DepthDecoder::from_near_far(e, kInf, kInf), "inf", to_string(e));
    EXPECT_TRUE(DepthDecoder::from_near_far(e, 0.1, 0.05).validate().ok()) << "far is ignored";
  }
  // Far beyond float's reach: the coefficients would be 0 or infinite.
  expect_invalid(DepthDecoder::from_near_far(DepthEncoding::reversed_infinite, 1e-300, 1.0), "float",
                 "1/n overflows float");
  // Linear and disparity ignore near/far entirely.
  EXPECT_TRUE(DepthDecoder::from_near_far(DepthEncoding::linear, -1.0, nan).validate().ok());
  EXPECT_TRUE(DepthDecoder::from_near_far(DepthEncoding::disparity, 0.0, 0.0).validate().ok());
  EXPECT_EQ(DepthDecoder::from_near_far(DepthEncoding::disparity, 0.0, 0.0).inverse_depth(7.0f), 7.0f);
  // A value outside the enum.
  expect_invalid(DepthDecoder::from_near_far(static_cast<DepthEncoding>(42), 0.1, 10.0), "42", "bad encoding");
}

TEST(DepthDecoder, InvalidMatrices) {
  const Matrix standard = d3d_lh(DepthEncoding::standard, 0.5, 50.0);
  const Matrix reversed = d3d_lh(DepthEncoding::reversed, 0.5, 50.0);
  for (DepthEncoding e : {DepthEncoding::linear, DepthEncoding::disparity}) {
    expect_invalid(DepthDecoder::from_d3d_projection(standard.m, e), "projection matrix", to_string(e));
    expect_invalid(DepthDecoder::from_gl_projection(standard.m, e), "projection matrix", to_string(e));
  }
  // A matrix of the other depth direction reads as far <= near.
  expect_invalid(DepthDecoder::from_d3d_projection(reversed.m, DepthEncoding::standard), "far plane",
                 "reversed matrix read as standard");
  expect_invalid(DepthDecoder::from_d3d_projection(standard.m, DepthEncoding::reversed), "far plane",
                 "standard matrix read as reversed");
  // Orthographic (clip w = 1), NaN entries, no matrix.
  Matrix ortho = {};
  ortho.m[0] = ortho.m[5] = 1.0f;
  ortho.m[10] = 0.02f;
  ortho.m[14] = -0.01f;
  ortho.m[15] = 1.0f;
  expect_invalid(DepthDecoder::from_d3d_projection(ortho.m, DepthEncoding::standard), "not perspective", "ortho");
  expect_invalid(DepthDecoder::from_gl_projection(ortho.m, DepthEncoding::gl_ndc), "not perspective", "ortho GL");
  Matrix broken = standard;
  broken.m[10] = std::numeric_limits<float>::quiet_NaN();
  expect_invalid(DepthDecoder::from_d3d_projection(broken.m, DepthEncoding::standard), "not perspective", "nan");
  expect_invalid(DepthDecoder::from_d3d_projection(nullptr, DepthEncoding::standard), "missing", "null");
  // A near plane behind the camera (a mirrored matrix) is named.
  Matrix mirrored = standard;
  mirrored.m[14] = -mirrored.m[14];
  expect_invalid(DepthDecoder::from_d3d_projection(mirrored.m, DepthEncoding::standard), "-0.5", "n<0");
}

}  // namespace
}  // namespace reproject
