// The parallax model and the stereo camera (docs/DESIGN.md §4, include/reproject/parallax.hpp).
//
// The central check: rendering a point twice, with the left and the right stereo projections built
// by StereoCamera from a mono matrix, puts its two images exactly p(w) pixels apart, where w is what
// the DepthDecoder read off the same mono matrix makes of the point's stored (float) depth, and p
// is the ParallaxModel the same camera gives. The matrices, the decoder and the model are three
// independent pieces of code checked against each other; the projection arithmetic is done here in
// double from the float matrices, in each API's own convention.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "kernels/fma.hpp"
#include "reproject/depth.hpp"
#include "reproject/parallax.hpp"

namespace reproject {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

const EyeDirection kDirections[] = {EyeDirection::left_to_right, EyeDirection::right_to_left,
                                    EyeDirection::centre_to_left, EyeDirection::centre_to_right};

enum class Api { d3d_lh, d3d_rh, gl };

struct Matrix {
  float m[16];
};

// Mono projections from the published formulas (D3DXMatrixPerspectiveFovLH/RH, gluPerspective,
// and GL with a [0, 1] depth range), in double, stored as float in each API's memory order.
// D3D: P[r][c] = m[4r + c], row vector. GL: M[r][c] = m[4c + r], column vector.
Matrix mono_matrix(Api api, DepthEncoding e, double n, double f, double fovy, double aspect) {
  const double ys = 1.0 / std::tan(fovy / 2.0), xs = ys / aspect;
  double X[4][4] = {};  // P (D3D) or M (GL), in mathematical [row][col] order
  X[0][0] = xs;
  X[1][1] = ys;
  Matrix out;
  if (api == Api::gl) {
    X[3][2] = -1.0;
    switch (e) {
      case DepthEncoding::gl_ndc:
        X[2][2] = (f + n) / (n - f);
        X[2][3] = 2.0 * f * n / (n - f);
        break;
      case DepthEncoding::standard:
        X[2][2] = f / (n - f);
        X[2][3] = -f * n / (f - n);
        break;
      case DepthEncoding::reversed:
        X[2][2] = n / (f - n);
        X[2][3] = f * n / (f - n);
        break;
      case DepthEncoding::infinite:
        X[2][2] = -1.0;
        X[2][3] = -n;
        break;
      case DepthEncoding::reversed_infinite:
        X[2][2] = 0.0;
        X[2][3] = n;
        break;
      default:
        ADD_FAILURE();
    }
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) out.m[4 * c + r] = static_cast<float>(X[r][c]);
    return out;
  }
  if (api == Api::d3d_rh) {  // only standard: Q = f / (n - f)
    X[2][2] = f / (n - f);
    X[2][3] = -1.0;
    X[3][2] = n * f / (n - f);
  } else {
    X[2][3] = 1.0;
    switch (e) {
      case DepthEncoding::standard:
        X[2][2] = f / (f - n);
        X[3][2] = -n * f / (f - n);
        break;
      case DepthEncoding::reversed:
        X[2][2] = n / (n - f);
        X[3][2] = -f * n / (n - f);
        break;
      case DepthEncoding::infinite:
        X[2][2] = 1.0;
        X[3][2] = -n;
        break;
      case DepthEncoding::reversed_infinite:
        X[2][2] = 0.0;
        X[3][2] = n;
        break;
      default:
        ADD_FAILURE();
    }
  }
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out.m[4 * r + c] = static_cast<float>(X[r][c]);
  return out;
}

// A point at view-space (x, y) and distance z in front of the camera (h = 1), or the direction
// (x, y, z) (h = 0: a point at infinity), projected in double from the float matrix.
struct Projected {
  double ndc_x, ndc_z;
};
Projected project(Api api, const Matrix& mat, double x, double y, double z, double h = 1.0) {
  double clip[4] = {};
  if (api == Api::gl) {  // clip = M v, v = (x, y, z_eye = -z, h)
    const double v[4] = {x, y, -z, h};
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) clip[r] += static_cast<double>(mat.m[4 * c + r]) * v[c];
  } else {  // clip = v P, v = (x, y, z_view, h); right-handed views look down -z
    const double v[4] = {x, y, api == Api::d3d_rh ? -z : z, h};
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) clip[c] += v[r] * static_cast<double>(mat.m[4 * r + c]);
  }
  return {clip[0] / clip[3], clip[2] / clip[3]};
}

double pixel_x(double ndc_x, int width) { return (ndc_x + 1.0) / 2.0 * width - 0.5; }

void stereo_pair(Api api, const StereoCamera& camera, const Matrix& mono, Matrix* left, Matrix* right) {
  if (api == Api::gl) {
    camera.projection_gl(mono.m, Eye::left, left->m);
    camera.projection_gl(mono.m, Eye::right, right->m);
  } else {
    camera.projection_d3d(mono.m, Eye::left, left->m);
    camera.projection_d3d(mono.m, Eye::right, right->m);
  }
}

DepthDecoder decoder_for(Api api, const Matrix& mono, DepthEncoding e) {
  return api == Api::gl ? DepthDecoder::from_gl_projection(mono.m, e) : DepthDecoder::from_d3d_projection(mono.m, e);
}

// ---------------------------------------------------------------------------------------------

TEST(StereoRenderTwice, ProjectedPairsArePParallaxApart) {
  struct Case {
    const char* name;
    Api api;
    DepthEncoding e;
    double n, f;
  } const cases[] = {
      {"D3D LH standard", Api::d3d_lh, DepthEncoding::standard, 0.5, 200.0},
      {"D3D LH reversed", Api::d3d_lh, DepthEncoding::reversed, 0.1, 1000.0},
      {"D3D LH infinite", Api::d3d_lh, DepthEncoding::infinite, 0.5, kInf},
      {"D3D LH reversed_infinite", Api::d3d_lh, DepthEncoding::reversed_infinite, 0.1, kInf},
      {"D3D RH standard", Api::d3d_rh, DepthEncoding::standard, 0.5, 200.0},
      {"GL gluPerspective gl_ndc", Api::gl, DepthEncoding::gl_ndc, 0.5, 200.0},
      {"GL [0,1] standard", Api::gl, DepthEncoding::standard, 0.5, 200.0},
      {"GL [0,1] reversed", Api::gl, DepthEncoding::reversed, 0.1, 1000.0},
      {"GL [0,1] reversed_infinite", Api::gl, DepthEncoding::reversed_infinite, 0.1, kInf},
  };
  const int width = 1280;
  const double fovy = 1.0, aspect = 16.0 / 9.0;
  for (const StereoCamera camera : {StereoCamera{0.05, 3.0}, StereoCamera{0.02, 10.0}, StereoCamera{0.08, 1.5}}) {
    for (const Case& c : cases) {
      const Matrix mono = mono_matrix(c.api, c.e, c.n, c.f, fovy, aspect);
      Matrix left, right;
      stereo_pair(c.api, camera, mono, &left, &right);
      const DepthDecoder decoder = decoder_for(c.api, mono, c.e);
      ASSERT_TRUE(decoder.validate().ok()) << c.name << ": " << decoder.validate().message();

      // Depths log-uniform from a quarter of the convergence distance (parallax -3a) to far away.
      const double z_lo = std::max(c.n, camera.convergence / 4.0), z_hi = std::min(c.f, 300.0);
      std::mt19937 rng(1234);
      std::uniform_real_distribution<double> unit(0.0, 1.0), ndc(-1.1, 1.1);
      const double xs = static_cast<double>(mono.m[0]), ys = static_cast<double>(mono.m[5]);
      double worst = 0.0;
      int nearer_than_convergence = 0;
      for (int i = 0; i < 2000; ++i) {
        const double z = z_lo * std::pow(z_hi / z_lo, unit(rng));
        const double x = ndc(rng) * z / xs, y = ndc(rng) * z / ys;
        nearer_than_convergence += z < camera.convergence;
        const Projected pc = project(c.api, mono, x, y, z);
        const Projected pl = project(c.api, left, x, y, z);
        const Projected pr = project(c.api, right, x, y, z);
        // The shear touches clip x only: all three eyes store the same depth.
        const float d = static_cast<float>(pc.ndc_z);
        ASSERT_EQ(static_cast<float>(pl.ndc_z), d);
        ASSERT_EQ(static_cast<float>(pr.ndc_z), d);
        const float w = decoder.inverse_depth(d);
        const double xc = pixel_x(pc.ndc_x, width), xl = pixel_x(pl.ndc_x, width), xr = pixel_x(pr.ndc_x, width);
        const struct {
          EyeDirection direction;
          double from, to;
        } moves[] = {{EyeDirection::left_to_right, xl, xr},
                     {EyeDirection::right_to_left, xr, xl},
                     {EyeDirection::centre_to_left, xc, xl},
                     {EyeDirection::centre_to_right, xc, xr}};
        for (const auto& move : moves) {
          const ParallaxModel model = camera.parallax(width, move.direction);
          const double p = model.parallax(w);
          const double err = std::fabs((move.to - move.from) - p);
          worst = std::max(worst, err);
          ASSERT_LE(err, 1e-4) << c.name << " " << to_string(move.direction) << " S=" << camera.separation
                               << " c=" << camera.convergence << " z=" << z << " measured " << move.to - move.from
                               << " model " << p;
        }
      }
      EXPECT_GT(nearer_than_convergence, 100) << "some points must be out of the screen";
      std::printf("  S=%.2f c=%4.1f %-28s worst |measured - p(w)| = %.2e px\n", camera.separation, camera.convergence,
                  c.name, worst);
    }
  }
}

// The equivalent camera translation T (half the interaxial): found here by projection alone and
// compared with eye_translation().
TEST(StereoCamera, EyeTranslationReproducesTheShear) {
  const int width = 1920;
  for (Api api : {Api::d3d_lh, Api::gl}) {
    for (double fovy : {0.6, 1.0, 1.4}) {
      const double aspect = 1.6;
      const DepthEncoding e = api == Api::gl ? DepthEncoding::gl_ndc : DepthEncoding::standard;
      const Matrix mono = mono_matrix(api, e, 0.2, 500.0, fovy, aspect);
      const StereoCamera camera{0.06, 4.0};
      Matrix left, right;
      stereo_pair(api, camera, mono, &left, &right);
      // Sheared pair: parallax (right minus left) at the convergence plane and at infinity.
      const double x0 = 0.7, y0 = -0.3;
      auto sheared = [&](double h) {
        const double z = h == 0.0 ? 1.0 : camera.convergence;
        const double scale = h == 0.0 ? 1.0 / camera.convergence : 1.0;  // same direction
        return pixel_x(project(api, right, x0 * scale, y0 * scale, z, h).ndc_x, width) -
               pixel_x(project(api, left, x0 * scale, y0 * scale, z, h).ndc_x, width);
      };
      const double shear_delta = sheared(1.0) - sheared(0.0);
      EXPECT_NEAR(sheared(1.0), 0.0, 1e-6) << "zero parallax at the convergence plane";
      // Parallel cameras (the mono matrix) moved by -t (left) and +t (right) along x, t = 1: a
      // point at infinity does not move, a point at distance c does.
      auto parallel = [&](double t, double h) {
        const double z = h == 0.0 ? 1.0 : camera.convergence;
        const double scale = h == 0.0 ? 1.0 / camera.convergence : 1.0;
        const double xr = x0 * scale - t * h, xl = x0 * scale + t * h;  // view x relative to each eye
        return pixel_x(project(api, mono, xr, y0 * scale, z, h).ndc_x, width) -
               pixel_x(project(api, mono, xl, y0 * scale, z, h).ndc_x, width);
      };
      const double per_unit = parallel(1.0, 1.0) - parallel(1.0, 0.0);
      const double T = shear_delta / per_unit;
      const double fovx = 2.0 * std::atan(aspect * std::tan(fovy / 2.0));
      const double expected = camera.separation * camera.convergence * std::tan(fovx / 2.0);
      EXPECT_NEAR(camera.eye_translation(fovx), expected, 1e-15 * expected);
      EXPECT_NEAR(T / camera.eye_translation(fovx), 1.0, 1e-5) << "fovy=" << fovy;
      // With that T, translated parallel cameras plus the constant image shift side * S * width / 2
      // reproduce each sheared eye at every depth.
      std::mt19937 rng(7);
      std::uniform_real_distribution<double> unit(0.0, 1.0), ndc(-1.0, 1.0);
      const double t = camera.eye_translation(fovx);
      const double xs = static_cast<double>(mono.m[0]);
      for (int i = 0; i < 200; ++i) {
        const double z = 1.0 * std::pow(400.0, unit(rng));
        const double x = ndc(rng) * z / xs, y = 0.5;
        const double sheared_r = pixel_x(project(api, right, x, y, z).ndc_x, width);
        const double sheared_l = pixel_x(project(api, left, x, y, z).ndc_x, width);
        const double moved_r = pixel_x(project(api, mono, x - t, y, z).ndc_x, width) + camera.separation * width / 2;
        const double moved_l = pixel_x(project(api, mono, x + t, y, z).ndc_x, width) - camera.separation * width / 2;
        ASSERT_NEAR(sheared_r, moved_r, 1e-4) << "z=" << z;
        ASSERT_NEAR(sheared_l, moved_l, 1e-4) << "z=" << z;
      }
    }
  }
}

// The stereo matrices differ from the mono one in the two clip-x entries the header names.
TEST(StereoCamera, ProjectionEntries) {
  const StereoCamera camera{0.05, 3.0};
  for (Api api : {Api::d3d_lh, Api::gl}) {
    const Matrix mono =
        mono_matrix(api, api == Api::gl ? DepthEncoding::gl_ndc : DepthEncoding::standard, 0.5, 100.0, 1.0, 1.5);
    for (Eye eye : {Eye::left, Eye::right}) {
      const double side = eye == Eye::left ? -1.0 : 1.0;
      Matrix out;
      if (api == Api::gl)
        camera.projection_gl(mono.m, eye, out.m);
      else
        camera.projection_d3d(mono.m, eye, out.m);
      for (int i = 0; i < 16; ++i) {
        if (i == 8 || i == 12) continue;
        EXPECT_EQ(out.m[i], mono.m[i]) << i;
      }
      if (api == Api::gl) {
        // M[0][2] = m[8] -= side S; M[0][3] = m[12] -= side S c (clip w = -z_eye).
        EXPECT_EQ(out.m[8], static_cast<float>(mono.m[8] - side * camera.separation));
        EXPECT_EQ(out.m[12], static_cast<float>(mono.m[12] - side * camera.separation * camera.convergence));
      } else {
        // P[2][0] = m[8] += side S; P[3][0] = m[12] -= side S c.
        EXPECT_EQ(out.m[8], static_cast<float>(mono.m[8] + side * camera.separation));
        EXPECT_EQ(out.m[12], static_cast<float>(mono.m[12] - side * camera.separation * camera.convergence));
      }
      // In place gives the same.
      Matrix in_place = mono;
      if (api == Api::gl)
        camera.projection_gl(in_place.m, eye, in_place.m);
      else
        camera.projection_d3d(in_place.m, eye, in_place.m);
      EXPECT_EQ(std::memcmp(in_place.m, out.m, sizeof out.m), 0);
    }
  }
}

TEST(ParallaxModel, StereoFigures) {
  // S = 0.05, c = 3, width 1280: a = 64 px at infinity, b = -192 px per unit of 1/z.
  const ParallaxModel lr = ParallaxModel::from_stereo(0.05, 3.0, 1280, EyeDirection::left_to_right);
  ASSERT_TRUE(lr.validate().ok());
  EXPECT_FLOAT_EQ(lr.a, 64.0f);
  EXPECT_FLOAT_EQ(lr.b, -192.0f);
  EXPECT_EQ(lr.a, static_cast<float>(0.05 * 1280.0));
  EXPECT_EQ(lr.b, static_cast<float>(-(0.05 * 1280.0) * 3.0));
  EXPECT_EQ(lr.parallax(0.0f), lr.a);                    // at infinity
  EXPECT_NEAR(lr.parallax(1.0f / 3.0f), 0.0f, 2e-5f);    // at the convergence plane
  EXPECT_NEAR(lr.parallax(1.0f / 1.5f), -64.0f, 2e-5f);  // half the convergence distance: -a
  // b w + a rounded once (not std::fma: MinGW-w64's is not; tests/test_fma.cpp checks this one).
  for (float w : {0.0f, 0.01f, 0.3f, 1.0f / 3.0f, 2.0f, 10.0f})
    EXPECT_EQ(lr.parallax(w), reproject::detail::fma_in_software(lr.b, w, lr.a)) << w;
  // Signs: sigma = +1, -1, -1/2, +1/2.
  EXPECT_EQ(eye_offset(EyeDirection::left_to_right), 1.0);
  EXPECT_EQ(eye_offset(EyeDirection::right_to_left), -1.0);
  EXPECT_EQ(eye_offset(EyeDirection::centre_to_left), -0.5);
  EXPECT_EQ(eye_offset(EyeDirection::centre_to_right), 0.5);
  EXPECT_FLOAT_EQ(ParallaxModel::from_stereo(0.05, 3.0, 1280, EyeDirection::centre_to_left).a, -32.0f);
  // Zero separation is a valid (null) model; b == 0 with a != 0 is a constant shift.
  const ParallaxModel none = ParallaxModel::from_stereo(0.0, 3.0, 1280, EyeDirection::left_to_right);
  EXPECT_TRUE(none.validate().ok());
  EXPECT_EQ(none.parallax(5.0f), 0.0f);
  EXPECT_TRUE((ParallaxModel{12.0f, 0.0f}).validate().ok());
}

// left->right = (centre->right) - (centre->left): going left->centre undoes centre->left.
TEST(ParallaxModel, DirectionsCompose) {
  for (double S : {0.01, 0.033, 0.1})
    for (double c : {0.7, 3.0, 25.0})
      for (int width : {1, 641, 1920}) {
        const auto m = [&](EyeDirection d) { return ParallaxModel::from_stereo(S, c, width, d); };
        const ParallaxModel lr = m(EyeDirection::left_to_right), rl = m(EyeDirection::right_to_left);
        const ParallaxModel cl = m(EyeDirection::centre_to_left), cr = m(EyeDirection::centre_to_right);
        EXPECT_EQ(cr.a - cl.a, lr.a);
        EXPECT_EQ(cr.b - cl.b, lr.b);
        EXPECT_EQ(cl.a + cr.a, 0.0f);  // the two half-steps are opposite
        EXPECT_EQ(cl.b + cr.b, 0.0f);
        EXPECT_EQ(rl.a, -lr.a);
        EXPECT_EQ(rl.b, -lr.b);
      }
  const auto d = [](EyeDirection dir) { return ParallaxModel::from_disparity(dir); };
  EXPECT_EQ(d(EyeDirection::left_to_right).a, 0.0f);
  EXPECT_EQ(d(EyeDirection::left_to_right).b, -1.0f);
  EXPECT_EQ(d(EyeDirection::right_to_left).b, 1.0f);
  EXPECT_EQ(d(EyeDirection::centre_to_left).b, 0.5f);
  EXPECT_EQ(d(EyeDirection::centre_to_right).b, -0.5f);
  EXPECT_EQ(ParallaxModel::from_disparity().b, -1.0f);
  EXPECT_EQ(d(EyeDirection::centre_to_right).b - d(EyeDirection::centre_to_left).b, d(EyeDirection::left_to_right).b);
  for (EyeDirection dir : kDirections) {
    EXPECT_TRUE(d(dir).validate().ok());
    EXPECT_EQ(d(dir).a, 0.0f);
  }
  // With the disparity decoder (w = d), left->right moves a pixel of disparity 7 by -7.
  EXPECT_EQ(d(EyeDirection::left_to_right).parallax(DepthDecoder::disparity().inverse_depth(7.0f)), -7.0f);
}

TEST(ParallaxModel, FromPhysicalIsFromStereo) {
  for (double io : {0.0, 0.063, 0.065})
    for (double sw : {0.5, 1.2, 7.0})
      for (EyeDirection dir : kDirections) {
        const ParallaxModel phys = ParallaxModel::from_physical(io, sw, 2.5, 1024, dir);
        const ParallaxModel st = ParallaxModel::from_stereo(io / sw, 2.5, 1024, dir);
        EXPECT_EQ(phys.a, st.a);
        EXPECT_EQ(phys.b, st.b);
        const StereoCamera camera = StereoCamera::from_physical(io, sw, 2.5);
        EXPECT_EQ(camera.separation, io / sw);
        EXPECT_EQ(camera.convergence, 2.5);
        EXPECT_EQ(camera.parallax(1024, dir).a, st.a);
        EXPECT_EQ(camera.parallax(1024, dir).b, st.b);
      }
  // Comfort figure of DESIGN §4: 6.5 cm eyes on a 1.3 m screen, 1300 px: |p| <= S width = 65 px.
  EXPECT_FLOAT_EQ(ParallaxModel::from_physical(0.065, 1.3, 2.0, 1300, EyeDirection::left_to_right).a, 65.0f);
}

TEST(StereoCamera, FromRigIsTheInteraxialOverTheConvergencePlanesWidth) {
  // Blender's defaults: interocular 0.065, convergence 1.95, a 50 mm lens on a 36 mm sensor.
  const double fov = 2.0 * std::atan(18.0 / 50.0);
  const StereoCamera rig = StereoCamera::from_rig(0.065, 1.95, fov);
  EXPECT_DOUBLE_EQ(rig.separation, 0.065 / (2.0 * 1.95 * 18.0 / 50.0));  // 0.0463
  EXPECT_EQ(rig.convergence, 1.95);
  // The inverse of eye_translation: the eyes sit half the interaxial from the centre.
  EXPECT_NEAR(rig.eye_translation(fov), 0.0325, 1e-12);
  // At 1920 px the two eyes see infinity S W = 88.9 px apart.
  EXPECT_NEAR(rig.parallax(1920, EyeDirection::left_to_right).a, 1920 * 0.065 / (3.9 * 0.36), 1e-3);
  const double pi = 3.14159265358979323846;
  for (double bad_fov : {0.0, -0.5, pi, 4.0, std::nan("")}) {
    EXPECT_TRUE(std::isnan(StereoCamera::from_rig(0.065, 1.95, bad_fov).separation)) << bad_fov;
  }
  EXPECT_TRUE(std::isnan(StereoCamera::from_rig(-0.065, 1.95, fov).separation));
  EXPECT_TRUE(std::isnan(StereoCamera::from_rig(0.065, 0.0, fov).separation));
  EXPECT_EQ(StereoCamera::from_rig(0.065, 1.95, fov).parallax(640, EyeDirection::left_to_right).validate().code(),
            StatusCode::ok);
  EXPECT_EQ(StereoCamera::from_rig(0.065, 1.95, 0.0).parallax(640, EyeDirection::left_to_right).validate().code(),
            StatusCode::invalid_model);
}

TEST(ParallaxModel, FromRelativeSpansTheMaximumAndIsZeroAtThePlane) {
  const DepthDecoder relative = DepthDecoder::disparity();  // w = v
  for (EyeDirection dir : kDirections) {
    const ParallaxModel m = ParallaxModel::from_relative(0.04, 0.25, 1000, dir);
    ASSERT_TRUE(m.validate().ok());
    const float sigma = static_cast<float>(eye_offset(dir));
    EXPECT_FLOAT_EQ(m.parallax(relative.inverse_depth(0.25f)), 0.0f);
    EXPECT_FLOAT_EQ(m.parallax(relative.inverse_depth(0.0f)), sigma * 40.0f * 0.25f);   // farthest: behind
    EXPECT_FLOAT_EQ(m.parallax(relative.inverse_depth(1.0f)), -sigma * 40.0f * 0.75f);  // nearest: in front
  }
  // The pair's eyes (centre to each side) are the left-to-right model's span apart.
  const ParallaxModel right = ParallaxModel::from_relative(0.04, 0.5, 1000, EyeDirection::centre_to_right);
  const ParallaxModel left = ParallaxModel::from_relative(0.04, 0.5, 1000, EyeDirection::centre_to_left);
  EXPECT_FLOAT_EQ(right.parallax(1.0f) - left.parallax(1.0f) - (right.parallax(0.0f) - left.parallax(0.0f)), -40.0f);
  // As a near-to-far sign, it moves like a disparity map: nearer is more crossed, left to right.
  EXPECT_LT(ParallaxModel::from_relative(0.04, 0.0, 100, EyeDirection::left_to_right).b, 0.0f);
  const auto lr = EyeDirection::left_to_right;
  EXPECT_TRUE(ParallaxModel::from_relative(0.0, 1.0, 100, lr).validate().ok());
  EXPECT_EQ(ParallaxModel::from_relative(0.03, 1.5, 100, lr).validate().code(), StatusCode::invalid_model);
  EXPECT_NE(std::strstr(ParallaxModel::from_relative(0.03, -0.1, 100, lr).validate().message(), "zero-parallax plane"),
            nullptr);
  EXPECT_NE(std::strstr(ParallaxModel::from_relative(-0.03, 0.5, 100, lr).validate().message(), "maximum parallax"),
            nullptr);
  EXPECT_EQ(ParallaxModel::from_relative(0.03, std::nan(""), 100, lr).validate().code(), StatusCode::invalid_model);
  EXPECT_EQ(ParallaxModel::from_relative(0.03, 0.5, 0, lr).validate().code(), StatusCode::invalid_model);
}

void expect_invalid(const ParallaxModel& model, const char* must_mention, const std::string& what) {
  const Status status = model.validate();
  EXPECT_EQ(status.code(), StatusCode::invalid_model) << what;
  EXPECT_TRUE(std::isnan(model.a) || std::isinf(model.a) || std::isnan(model.b) || std::isinf(model.b)) << what;
  if (must_mention) {
    EXPECT_NE(std::strstr(status.message(), must_mention), nullptr) << what << ": " << status.message();
  }
}

TEST(ParallaxModel, InvalidInputs) {
  const double nan = std::nan("");
  const auto lr = EyeDirection::left_to_right;
  expect_invalid(ParallaxModel::from_stereo(0.05, 0.0, 640, lr), "convergence", "c = 0");
  expect_invalid(ParallaxModel::from_stereo(0.05, -2.0, 640, lr), "convergence", "c < 0");
  expect_invalid(ParallaxModel::from_stereo(0.05, nan, 640, lr), "convergence", "c nan");
  expect_invalid(ParallaxModel::from_stereo(0.05, kInf, 640, lr), "convergence", "c inf");
  expect_invalid(ParallaxModel::from_stereo(-0.01, 3.0, 640, lr), "separation", "S < 0");
  expect_invalid(ParallaxModel::from_stereo(nan, 3.0, 640, lr), "separation", "S nan");
  expect_invalid(ParallaxModel::from_stereo(kInf, 3.0, 640, lr), "separation", "S inf");
  expect_invalid(ParallaxModel::from_stereo(0.05, 3.0, 0, lr), "width", "width 0");
  expect_invalid(ParallaxModel::from_stereo(0.05, 3.0, -640, lr), "width", "width < 0");
  expect_invalid(ParallaxModel::from_stereo(0.05, 3.0, 640, static_cast<EyeDirection>(9)), "direction", "dir");
  expect_invalid(ParallaxModel::from_physical(0.065, 0.0, 3.0, 640, lr), "screen width", "sw = 0");
  expect_invalid(ParallaxModel::from_physical(0.065, -1.0, 3.0, 640, lr), "screen width", "sw < 0");
  expect_invalid(ParallaxModel::from_physical(0.065, nan, 3.0, 640, lr), "screen width", "sw nan");
  expect_invalid(ParallaxModel::from_physical(-0.065, 1.0, 3.0, 640, lr), "separation", "io < 0");
  expect_invalid(ParallaxModel::from_physical(0.065, 1.0, 0.0, 640, lr), "convergence", "c = 0 physical");
  expect_invalid(StereoCamera::from_physical(0.065, 0.0, 3.0).parallax(640, lr), nullptr, "camera sw = 0");
  expect_invalid((StereoCamera{0.05, -1.0}).parallax(640, lr), "convergence", "camera c < 0");
  expect_invalid(ParallaxModel::from_disparity(static_cast<EyeDirection>(9)), "direction", "disparity dir");
  // Hand-made models: the message names the non-finite field.
  expect_invalid(ParallaxModel{std::numeric_limits<float>::quiet_NaN(), -3.0f}, "a = nan", "a nan");
  expect_invalid(ParallaxModel{std::numeric_limits<float>::infinity(), -3.0f}, "a = inf", "a inf");
  expect_invalid(ParallaxModel{5.0f, -std::numeric_limits<float>::infinity()}, "b = -inf", "b -inf");
  // Parameters so large that a overflows float.
  expect_invalid(ParallaxModel::from_stereo(1e30, 1e30, 1 << 30, lr), "inf", "overflow");
}

TEST(StereoDirectionNames, RoundTrip) {
  const char* const dashed[] = {"left-to-right", "right-to-left", "centre-to-left", "centre-to-right"};
  const char* const underscored[] = {"left_to_right", "right_to_left", "centre_to_left", "centre_to_right"};
  for (int i = 0; i < 4; ++i) {
    EXPECT_STREQ(to_string(kDirections[i]), dashed[i]);
    EyeDirection parsed = EyeDirection::left_to_right;
    ASSERT_TRUE(parse_direction(dashed[i], &parsed));
    EXPECT_EQ(parsed, kDirections[i]);
    parsed = EyeDirection::left_to_right;
    ASSERT_TRUE(parse_direction(underscored[i], &parsed));
    EXPECT_EQ(parsed, kDirections[i]);
  }
  EyeDirection untouched = EyeDirection::centre_to_left;
  for (const char* bad : {"", "left", "Left-to-right", "center-to-left", "left-to-right "})
    EXPECT_FALSE(parse_direction(bad, &untouched)) << bad;
  EXPECT_EQ(untouched, EyeDirection::centre_to_left);
  EXPECT_FALSE(parse_direction(nullptr, &untouched));
  // A null out only checks the name (every enum's parser does so: src/names.hpp).
  EXPECT_TRUE(parse_direction("left-to-right", nullptr));
  EXPECT_FALSE(parse_direction("left", nullptr));
}

}  // namespace
}  // namespace reproject
