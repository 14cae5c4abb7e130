// Whole views: a scene rendered through a camera, which pixels two eyes both see, and depth
// written in an encoding.
#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include "scene.hpp"
#include "scene_internal.hpp"

namespace reproject::scene {
namespace {

constexpr std::uint8_t kNoObject = 255;

// Runs rows(first, step) on `threads` threads (0: one per hardware thread), rows interleaved:
// every pixel is computed the same way whichever thread does it, so the result does not depend
// on the thread count.
template <class Rows>
void run_interleaved(int height, int threads, const Rows& rows) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, height);
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(rows, i, threads);
  rows(0, threads);
  for (std::thread& t : pool) t.join();
}

}  // namespace

Status Scene::render(const Camera& camera, View* out, int threads) const {
  if (out == nullptr) return Status(StatusCode::null_pointer, "render: null output view");
  if (camera.width <= 0 || camera.height <= 0) {
    return Status(StatusCode::invalid_size, "render: size %dx%d", camera.width, camera.height);
  }
  if (!(camera.horizontal_fov > 0.0 && camera.horizontal_fov < 3.0)) {
    return Status(StatusCode::invalid_option, "render: horizontal fov %g rad", camera.horizontal_fov);
  }
  const int w = camera.width, h = camera.height;
  out->color = Image(w, h, 3);
  out->depth = Image(w, h, 1);
  out->object.assign(static_cast<std::size_t>(w) * h, kNoObject);
  if (out->color.empty() || out->depth.empty()) {
    return Status(StatusCode::invalid_size, "render: cannot allocate %dx%d", w, h);
  }
  float* r = out->color.plane_data(0);
  float* g = out->color.plane_data(1);
  float* b = out->color.plane_data(2);
  float* z = out->depth.plane_data(0);
  const std::ptrdiff_t cs = out->color.stride(), zs = out->depth.stride();
  std::uint8_t* ids = out->object.data();

  const RayGenerator ray(camera);
  auto render_rows = [&](int first, int step) {
    for (int y = first; y < h; y += step) {
      for (int x = 0; x < w; ++x) {
        Hit hit;
        const std::ptrdiff_t ci = y * cs + x, zi = y * zs + x;
        if (trace(ray(x, y), &hit)) {
          r[ci] = hit.rgb[0];
          g[ci] = hit.rgb[1];
          b[ci] = hit.rgb[2];
          z[zi] = static_cast<float>(hit.z);
          ids[static_cast<std::size_t>(y) * w + x] = static_cast<std::uint8_t>(hit.object);
        } else {
          r[ci] = g[ci] = b[ci] = 0.0f;
          z[zi] = INFINITY;
        }
      }
    }
  };
  run_interleaved(h, threads, render_rows);
  return Status();
}

Status Scene::visible_in_both(const Camera& target, const Camera& source, std::vector<std::uint8_t>* out,
                              int threads) const {
  if (out == nullptr) return Status(StatusCode::null_pointer, "visible_in_both: null output");
  if (target.width <= 0 || target.height <= 0 || source.width <= 0 || source.height != target.height) {
    return Status(StatusCode::invalid_size, "visible_in_both: target %dx%d, source %dx%d", target.width,
                  target.height, source.width, source.height);
  }
  const int w = target.width, h = target.height;
  out->assign(static_cast<std::size_t>(w) * h, 0);
  std::uint8_t* mask = out->data();
  const RayGenerator target_ray(target), source_ray(source);
  const double last_column = source.width - 1.0;
  auto rows = [&](int first, int step) {
    for (int y = first; y < h; y += step) {
      for (int x = 0; x < w; ++x) {
        Hit seen, from_source;
        if (!trace(target_ray(x, y), &seen)) continue;
        double u = 0.0;
        source.project(seen.point, &u, nullptr);
        // Only the part of the source row a reprojection can read from.
        if (!(u >= 0.0 && u <= last_column)) continue;
        if (!trace(source_ray(u, y), &from_source)) continue;
        mask[static_cast<std::size_t>(y) * w + x] = std::fabs(from_source.z - seen.z) <= 1e-9 * seen.z;
      }
    }
  };
  run_interleaved(h, threads, rows);
  return Status();
}

Image encode_depth(const Image& linear_z, const DepthDecoder& decoder) {
  if (linear_z.empty()) return Image();
  Image out(linear_z.width(), linear_z.height(), 1);
  if (out.empty()) return out;
  for (int y = 0; y < linear_z.height(); ++y) {
    const float* src = linear_z.plane_data(0) + y * linear_z.stride();
    float* dst = out.plane_data(0) + y * out.stride();
    for (int x = 0; x < linear_z.width(); ++x) dst[x] = decoder.encode(src[x]);
  }
  return out;
}

}  // namespace reproject::scene
