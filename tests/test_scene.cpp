// Tests of the ray-cast scenes (tools/scene): their stereo camera against DESIGN §4 and the
// library's parallax model, determinism, and the content the other tests and the demo rely on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "scene.hpp"

namespace rs = reproject::scene;
using reproject::DepthDecoder;
using reproject::DepthEncoding;
using reproject::Eye;
using reproject::EyeDirection;
using reproject::Image;
using reproject::ParallaxModel;

namespace {

constexpr double kPi = 3.14159265358979323846;

// x of the eye's ray through (u, v) at depth z: where that ray is when it reaches the plane z.
double ray_x_at_depth(const rs::Camera& cam, double u, double v, double z) {
  const rs::Ray r = cam.ray(u, v);
  return r.origin.x + z * r.direction.x;  // direction.z == 1, origin.z == 0
}

// The continuous column at which `cam` sees the point p, found by ray casting alone: bisect on u
// until the eye's ray through (u, v) passes through p. The ray's x at p's depth grows with u.
double column_by_ray_casting(const rs::Camera& cam, const rs::Vec3& p, double v) {
  double lo = -4.0 * cam.width, hi = 5.0 * cam.width;
  for (int i = 0; i < 200 && hi - lo > 1e-10; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (ray_x_at_depth(cam, mid, v, p.z) < p.x) lo = mid; else hi = mid;
  }
  return 0.5 * (lo + hi);
}

struct EyePair {
  double from, to;
  EyeDirection direction;
  const char* name;
};

const EyePair kPairs[] = {
    {rs::kLeftEye, rs::kRightEye, EyeDirection::left_to_right, "left_to_right"},
    {rs::kRightEye, rs::kLeftEye, EyeDirection::right_to_left, "right_to_left"},
    {rs::kCentreEye, rs::kRightEye, EyeDirection::centre_to_right, "centre_to_right"},
    {rs::kCentreEye, rs::kLeftEye, EyeDirection::centre_to_left, "centre_to_left"},
};

int count_in_column(const rs::View& view, int column, int object) {
  int n = 0;
  for (int y = 0; y < view.height(); ++y) {
    n += view.object[static_cast<std::size_t>(y) * view.width() + column] == object;
  }
  return n;
}

}  // namespace

// A point seen at column x of one eye is seen by the other eye at x + p(w), p from
// StereoCamera::parallax (DESIGN §4), within 1e-3 px. The target column comes from ray casting
// in the other eye (bisection on its rays), so this checks the scene's camera, built from the
// clip-space shear, against the library's parallax model independently of either's formulas.
TEST(SceneCamera, ViewsAgreeWithParallaxModel) {
  const rs::Scene scene = rs::Scene::make();
  const int width = 1920, height = 1080;
  const reproject::StereoCamera stereo = scene.recommended_stereo();
  for (const EyePair& pair : kPairs) {
    SCOPED_TRACE(pair.name);
    const rs::Camera from = scene.camera(width, height, pair.from);
    const rs::Camera to = scene.camera(width, height, pair.to);
    const ParallaxModel model = stereo.parallax(width, pair.direction);
    ASSERT_TRUE(model.validate().ok()) << model.validate().message();
    double worst = 0.0;
    int checked = 0, negative = 0;
    for (int y = 0; y < height; y += 7) {
      for (int x = 0; x < width; x += 5) {
        rs::Hit hit;
        ASSERT_TRUE(scene.trace(from.ray(x, y), &hit));
        const double w = 1.0 / hit.z;
        const double p = static_cast<double>(model.a) + static_cast<double>(model.b) * w;
        const double u = column_by_ray_casting(to, hit.point, y);
        worst = std::max(worst, std::fabs(u - (x + p)));
        // project() is the closed form of the same thing.
        double pu = 0.0, pv = 0.0;
        to.project(hit.point, &pu, &pv);
        EXPECT_NEAR(pu, u, 1e-6);
        EXPECT_NEAR(pv, y, 1e-6);  // horizontal parallax only: same row
        ++checked;
        negative += p < 0.0;
      }
    }
    EXPECT_LT(worst, 1e-3) << "largest |x_target - (x + p(w))| in px";
    EXPECT_GT(checked, 50000);
    EXPECT_GT(negative, 0);
  }
}

// The scene's eyes are the ones the library's stereo projection matrices describe: the same
// points land on the same pixels, and the eye translation is StereoCamera::eye_translation.
TEST(SceneCamera, MatchesStereoProjectionMatrices) {
  const rs::Scene scene = rs::Scene::make();
  const int width = 1280, height = 720;
  const double fov = 70.0 * kPi / 180.0;
  const rs::Camera centre = scene.camera(width, height, rs::kCentreEye, fov);
  const reproject::StereoCamera stereo = centre.stereo;
  const double n = scene.near_plane(), f = scene.far_plane();
  // D3D row-vector perspective, row-major: clip = [x y z 1] P, clip.w = z.
  float mono[16] = {};
  mono[0] = static_cast<float>(1.0 / centre.tan_half_fov_x());
  mono[5] = static_cast<float>(1.0 / centre.tan_half_fov_y());
  mono[10] = static_cast<float>(f / (f - n));
  mono[11] = 1.0f;
  mono[14] = static_cast<float>(-n * f / (f - n));
  for (Eye eye : {Eye::left, Eye::right}) {
    const double sigma = eye == Eye::left ? rs::kLeftEye : rs::kRightEye;
    const rs::Camera cam = centre.with_eye(sigma);
    EXPECT_NEAR(std::fabs(cam.eye_x()), stereo.eye_translation(fov), 1e-12);
    EXPECT_EQ(cam.eye_x() > 0.0, eye == Eye::right);
    float P[16];
    stereo.projection_d3d(mono, eye, P);
    for (int y = 3; y < height; y += 37) {
      for (int x = 1; x < width; x += 29) {
        rs::Hit hit;
        ASSERT_TRUE(scene.trace(centre.ray(x, y), &hit));
        const rs::Vec3& q = hit.point;
        const double clip_x = q.x * P[0] + q.y * P[4] + q.z * P[8] + P[12];
        const double clip_w = q.x * P[3] + q.y * P[7] + q.z * P[11] + P[15];
        const double u_matrix = 0.5 * (clip_x / clip_w + 1.0) * width - 0.5;
        double u = 0.0;
        cam.project(q, &u, nullptr);
        EXPECT_NEAR(u, u_matrix, 2e-3) << "x=" << x << " y=" << y;  // float matrix rounding
      }
    }
  }
}

// Same image, bit for bit, on every call and whatever the thread count.
TEST(Scene, RenderIsDeterministic) {
  const rs::Scene scene = rs::Scene::make();
  for (double sigma : {rs::kLeftEye, rs::kCentreEye, rs::kRightEye}) {
    const rs::Camera cam = scene.camera(640, 360, sigma);
    rs::View a, b;
    ASSERT_TRUE(scene.render(cam, &a, 1).ok());
    ASSERT_TRUE(scene.render(cam, &b, 3).ok());
    for (int y = 0; y < cam.height; ++y) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(0, std::memcmp(a.color.plane_data(c) + y * a.color.stride(),
                                 b.color.plane_data(c) + y * b.color.stride(), sizeof(float) * cam.width));
      }
      ASSERT_EQ(0, std::memcmp(a.depth.plane_data() + y * a.depth.stride(),
                               b.depth.plane_data() + y * b.depth.stride(), sizeof(float) * cam.width));
    }
    EXPECT_EQ(a.object, b.object);
  }
}

// Every pixel sees a surface inside the scene's depth range, with colour in 0..1; near/far
// enclose the range; the encoded depth decodes back to the linear depth.
TEST(Scene, DepthRangeColorAndEncoding) {
  const rs::Scene scene = rs::Scene::make();
  EXPECT_LT(scene.near_plane(), scene.min_depth());
  EXPECT_GT(scene.far_plane(), scene.max_depth());
  for (double fov_deg : {60.0, 110.0}) {
    const rs::Camera cam = scene.camera(480, 270, rs::kLeftEye, fov_deg * kPi / 180.0);
    rs::View view;
    ASSERT_TRUE(scene.render(cam, &view).ok());
    for (int y = 0; y < cam.height; ++y) {
      for (int x = 0; x < cam.width; ++x) {
        const float z = view.depth.plane_data()[y * view.depth.stride() + x];
        ASSERT_GE(z, scene.min_depth());
        ASSERT_LE(z, scene.max_depth());
        for (int c = 0; c < 3; ++c) {
          const float v = view.color.plane_data(c)[y * view.color.stride() + x];
          ASSERT_GE(v, 0.0f);
          ASSERT_LE(v, 1.0f);
        }
      }
    }
    for (DepthEncoding e : {DepthEncoding::standard, DepthEncoding::reversed, DepthEncoding::gl_ndc,
                            DepthEncoding::reversed_infinite}) {
      const DepthDecoder decoder = scene.decoder(e);
      ASSERT_TRUE(decoder.validate().ok()) << decoder.validate().message();
      const Image encoded = rs::encode_depth(view.depth, decoder);
      ASSERT_FALSE(encoded.empty());
      for (int y = 0; y < cam.height; y += 5) {
        for (int x = 0; x < cam.width; x += 3) {
          const double z = view.depth.plane_data()[y * view.depth.stride() + x];
          const double back = decoder.linear_depth(encoded.plane_data()[y * encoded.stride() + x]);
          ASSERT_NEAR(back, z, 2e-3 * z) << reproject::to_string(e);
        }
      }
    }
  }
}

// S = 0.03 and the convergence plane halfway (in parallax) between the nearest and the
// farthest surface.
TEST(Scene, RecommendedStereo) {
  const rs::Scene scene = rs::Scene::make();
  const reproject::StereoCamera stereo = scene.recommended_stereo();
  EXPECT_DOUBLE_EQ(stereo.separation, 0.03);
  EXPECT_GT(stereo.convergence, scene.min_depth());
  EXPECT_LT(stereo.convergence, scene.max_depth());
  const double near_p = 1.0 - stereo.convergence / scene.min_depth();
  const double far_p = 1.0 - stereo.convergence / scene.max_depth();
  EXPECT_NEAR(near_p, -far_p, 1e-12);
}

// The pole is 1.5 to 3 px wide at 1920x1080 in every eye: its width is measured by casting rays
// every 1/256 px across it, and the rendered image shows it (1 to 3 pixels a row).
TEST(Scene, PoleIsAboutTwoPixelsWide) {
  const rs::Scene scene = rs::Scene::make();
  const int pole = scene.find_object("pole");
  ASSERT_GE(pole, 0);
  for (double sigma : {rs::kLeftEye, rs::kCentreEye, rs::kRightEye}) {
    const rs::Camera cam = scene.camera(1920, 1080, sigma);
    // Pole axis at x = -0.8, z = 8; look at the rows where it stands in front of the wall.
    double u0 = 0.0, v_top = 0.0, v_floor = 0.0;
    cam.project({-0.8, 1.0, 8.0}, &u0, &v_top);
    cam.project({-0.8, -1.2, 8.0}, nullptr, &v_floor);
    ASSERT_GT(u0, 10.0);
    ASSERT_LT(u0, cam.width - 10.0);
    const int row = static_cast<int>(std::lround(v_top));
    int samples = 0;
    for (double u = u0 - 6.0; u <= u0 + 6.0; u += 1.0 / 256) {
      rs::Hit hit;
      ASSERT_TRUE(scene.trace(cam.ray(u, row), &hit));
      samples += hit.object == pole;
    }
    const double width_px = samples / 256.0;
    EXPECT_GE(width_px, 1.5);
    EXPECT_LE(width_px, 3.0);

    rs::View view;
    ASSERT_TRUE(scene.render(cam, &view).ok());
    for (int y = static_cast<int>(v_top); y < static_cast<int>(v_floor); y += 11) {
      int n = 0;
      for (int x = 0; x < cam.width; ++x) n += view.object[static_cast<std::size_t>(y) * cam.width + x] == pole;
      EXPECT_GE(n, 1) << "row " << y;
      EXPECT_LE(n, 3) << "row " << y;
    }
  }
}

// Some of the picture is in front of the convergence plane (negative parallax) and some behind,
// and the near sphere is entirely in front.
TEST(Scene, HasNegativeParallax) {
  const rs::Scene scene = rs::Scene::make();
  const rs::Camera cam = scene.camera(960, 540, rs::kCentreEye);
  const ParallaxModel model = cam.stereo.parallax(cam.width, EyeDirection::centre_to_right);
  rs::View view;
  ASSERT_TRUE(scene.render(cam, &view).ok());
  const int near_sphere = scene.find_object("near_sphere");
  ASSERT_GE(near_sphere, 0);
  long negative = 0, positive = 0, sphere_pixels = 0;
  for (int y = 0; y < cam.height; ++y) {
    for (int x = 0; x < cam.width; ++x) {
      const double z = view.depth.plane_data()[y * view.depth.stride() + x];
      const double p = model.a + model.b / z;
      negative += p < 0.0;
      positive += p > 0.0;
      if (view.object[static_cast<std::size_t>(y) * cam.width + x] == near_sphere) {
        ++sphere_pixels;
        EXPECT_LT(p, 0.0);
      }
    }
  }
  const long total = static_cast<long>(cam.width) * cam.height;
  EXPECT_GT(negative, total / 50);
  EXPECT_GT(positive, total / 2);
  EXPECT_GT(sphere_pixels, total / 100);
}

// The edge box touches the left edge of the picture in every eye (column 0), so reprojection
// meets an object cut by the viewport.
TEST(Scene, ObjectTouchesViewportEdge) {
  const rs::Scene scene = rs::Scene::make();
  const int edge_box = scene.find_object("edge_box");
  ASSERT_GE(edge_box, 0);
  for (double sigma : {rs::kLeftEye, rs::kCentreEye, rs::kRightEye}) {
    const rs::Camera cam = scene.camera(960, 540, sigma);
    rs::View view;
    ASSERT_TRUE(scene.render(cam, &view).ok());
    EXPECT_GT(count_in_column(view, 0, edge_box), cam.height / 10) << "sigma " << sigma;
  }
}

// Colour is a property of the surface point, not of the eye: the same point has the same colour
// in the left and the right view (what makes PSNR against the true other eye meaningful).
TEST(Scene, ColorIsViewIndependent) {
  const rs::Scene scene = rs::Scene::make();
  const rs::Camera left = scene.camera(960, 540, rs::kLeftEye);
  const rs::Camera right = left.with_eye(rs::kRightEye);
  int compared = 0, differ = 0;
  for (int y = 0; y < left.height; y += 3) {
    for (int x = 0; x < left.width; x += 3) {
      rs::Hit a, b;
      ASSERT_TRUE(scene.trace(left.ray(x, y), &a));
      double u = 0.0, v = 0.0;
      right.project(a.point, &u, &v);
      if (!scene.trace(right.ray(u, v), &b)) continue;
      if (b.object != a.object || std::fabs(b.z - a.z) > 1e-9 * a.z) continue;  // occluded
      ++compared;
      for (int c = 0; c < 3; ++c) differ += std::fabs(a.rgb[c] - b.rgb[c]) > 1e-5f;
    }
  }
  EXPECT_GT(compared, 40000);
  EXPECT_LT(differ, compared / 1000);  // only where rounding flips a texel boundary
}

TEST(Scene, Names) {
  rs::SceneId id;
  ASSERT_TRUE(rs::parse_scene("room", &id));
  EXPECT_EQ(id, rs::SceneId::room);
  EXPECT_FALSE(rs::parse_scene("nope", &id));
  const rs::Scene scene = rs::Scene::make(rs::SceneId::room);
  EXPECT_STREQ(scene.name(), "room");
  for (const char* name : {"floor", "back_wall", "pole", "sphere", "near_sphere", "edge_box"}) {
    EXPECT_GE(scene.find_object(name), 0) << name;
  }
  EXPECT_EQ(scene.find_object("nope"), -1);
}
