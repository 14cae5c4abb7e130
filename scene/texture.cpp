// The colour of a surface point: procedural textures (lattice value noise over an integer hash,
// soft-edged checkers, stripes and bricks) and the materials built from them, under one fixed
// light. Colour is a function of the surface point only (never of the ray), so that a point has
// the same colour in every eye and a reprojected pixel can be compared with the true other eye.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "scene.hpp"
#include "scene_internal.hpp"

namespace reproject::scene {
namespace {

std::uint32_t hash3(std::int64_t x, std::int64_t y, std::uint32_t seed) {
  // Fold the lattice coordinates and the seed together, then scramble with multiply/xor-shift
  // rounds so that neighbouring cells get unrelated values.
  std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full + seed;
  h ^= h >> 31;
  h *= 0xD6E8FEB86659FD93ull;
  h ^= h >> 29;
  h *= 0x9FB21C651E98DF25ull;
  h ^= h >> 32;
  return static_cast<std::uint32_t>(h);
}

double cell_value(std::int64_t x, std::int64_t y, std::uint32_t seed) {
  return (hash3(x, y, seed) >> 8) * (1.0 / 16777216.0);  // [0, 1)
}

// Smooth value noise in [0, 1), feature size 1 in (u, v).
double value_noise(double u, double v, std::uint32_t seed) {
  const double fu = std::floor(u), fv = std::floor(v);
  const auto iu = static_cast<std::int64_t>(fu);
  const auto iv = static_cast<std::int64_t>(fv);
  double su = u - fu, sv = v - fv;
  su = su * su * (3.0 - 2.0 * su);  // smoothstep: no visible lattice creases
  sv = sv * sv * (3.0 - 2.0 * sv);
  const double n00 = cell_value(iu, iv, seed), n10 = cell_value(iu + 1, iv, seed);
  const double n01 = cell_value(iu, iv + 1, seed), n11 = cell_value(iu + 1, iv + 1, seed);
  const double top = n00 + (n10 - n00) * su;
  const double bottom = n01 + (n11 - n01) * su;
  return top + (bottom - top) * sv;
}

// Two octaves centred on 0, amplitude about +-0.5: detail at the feature size and at a quarter.
double detail(double u, double v, std::uint32_t seed) {
  return 0.65 * (value_noise(u, v, seed) - 0.5) + 0.35 * (value_noise(4.0 * u, 4.0 * v, seed + 1) - 0.5);
}

// Texture edges are ramps, not steps: a step is aliased by the one-ray-per-pixel rendering, and
// then even a perfect reprojection (which must interpolate between pixels) differs from the true
// other eye at every texel edge, drowning the geometric errors the demo is meant to show. The
// ramps are narrow (kEdge of a cell on each side of the edge), so a misplaced pixel still shows.
constexpr double kEdge = 0.04;

// Square wave of period 2 in u (0 on even cells, 1 on odd ones) with linear ramps of half-width
// kEdge around each integer, passing 0.5 at the integer.
double soft_parity(double u) {
  const double cell = std::floor(u);
  const double own = (static_cast<std::int64_t>(cell) & 1) != 0 ? 1.0 : 0.0;
  const double f = u - cell;
  const double edge_distance = std::min(f, 1.0 - f);
  const double weight = edge_distance >= kEdge ? 1.0 : 0.5 + 0.5 * edge_distance / kEdge;
  return own * weight + (1.0 - own) * (1.0 - weight);
}

// Checkerboard, the soft exclusive-or of the two square waves.
double soft_checker(double u, double v) {
  const double a = soft_parity(u), b = soft_parity(v);
  return a + b - 2.0 * a * b;
}

// 1 within `half_width` of an integer of u, falling linearly to 0 over `ramp` beyond (all in
// units of u): a joint line.
double soft_line(double u, double half_width, double ramp) {
  const double f = u - std::floor(u);
  const double d = std::min(f, 1.0 - f);
  return std::min(1.0, std::max(0.0, (half_width + ramp - d) / ramp));
}

float clamp01(double x) { return static_cast<float>(std::min(1.0, std::max(0.0, x))); }

}  // namespace

void Scene::shade(const Object& o, const Vec3& n, const double uv[2], float rgb[3]) const noexcept {
  const double inv = 1.0 / o.scale;
  const double u = uv[0] * inv, v = uv[1] * inv;
  const std::uint32_t seed = o.texture_seed * 7919u + 17u;
  double mix = 0.0;      // 0: colour a, 1: colour b
  double mortar = 0.0;   // bricks: weight of the grey mortar
  double noise_amp = 0.18;
  switch (o.material) {
    case Material::floor_tiles:
    case Material::checker:
      mix = soft_checker(u, v);
      break;
    case Material::stripes:
      mix = soft_parity(u);
      break;
    case Material::bands:
      mix = soft_parity(v);
      noise_amp = 0.08;
      break;
    case Material::bricks: {
      // Bricks `scale` wide and scale/2 high; every other course offset by half a brick. Each
      // brick gets its own shade between a and b (the step between bricks is hidden under the
      // mortar); 2 cm mortar joints with 1.5 cm ramps.
      const double row = std::floor(v * 2.0);
      const double bu = u + (static_cast<std::int64_t>(row) & 1 ? 0.5 : 0.0);
      const double col = std::floor(bu);
      mix = cell_value(static_cast<std::int64_t>(col), static_cast<std::int64_t>(row), seed + 5);
      const double half_joint = 0.01 * inv, ramp = 0.015 * inv;  // in brick widths
      mortar = std::max(soft_line(bu, half_joint, ramp), soft_line(v * 2.0, 2.0 * half_joint, 2.0 * ramp));
      break;
    }
  }
  // Fine detail at 1/3 of the feature size so that a pixel moved by a fraction of a cell still
  // shows, and a view-independent (Lambert) light so that shape reads in the picture.
  const double grain = noise_amp * detail(3.0 * u, 3.0 * v, seed);
  const Vec3 light = {-0.37, 0.74, -0.56};  // unit: from the upper left, behind the camera
  const double lambert = 0.45 + 0.55 * std::max(0.0, dot(n, light));
  for (int c = 0; c < 3; ++c) {
    double base = o.color_a[c] + (o.color_b[c] - o.color_a[c]) * mix;
    base = base + (0.62 - base) * mortar;
    rgb[c] = clamp01((base + grain) * lambert);
  }
}

}  // namespace reproject::scene
