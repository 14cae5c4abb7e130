// Embedding reproject in an engine: the right eye of one frame straight from the engine's own
// buffers, an RGBA8 sRGB back buffer and a D24S8 depth buffer, with no conversion to float.
// The frame is the one of embed.cpp (a box at z = 2 in front of a wall at z = 8, standard depth),
// held as an engine holds it: 32-bit pixels, rows `pitch` bytes apart, the box marked 1 in stencil.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <thread>
#include <vector>

#include "reproject/reproject.hpp"

namespace {

// An engine's job system, reduced to its core: task(i) for every i in [0, count), the even ones on
// the calling thread and the odd ones on a worker, returning when both are done.
void run_jobs(void* /*context*/, int count, void (*task)(void*, int), void* task_context) {
  std::thread worker([=] {
    for (int i = 1; i < count; i += 2) task(task_context, i);
  });
  for (int i = 0; i < count; i += 2) task(task_context, i);
  worker.join();
}

}  // namespace

int main() {
  using namespace reproject;
  const int width = 320;
  const int height = 180;
  const int pitch = (width * 4 + 511) / 512 * 512;  // bytes per row: the engine pads rows to 512 bytes
  const int row_pixels = pitch / 4;
  const DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::standard, 0.1, 100.0);
  const std::uint32_t box_stencil = 1;

  // Pixels are R, G, B, A bytes in memory order (a little-endian word 0xAABBGGRR); depth words
  // hold the 24-bit depth code in bits 0-23 and the stencil in bits 24-31 (D24_UNORM_S8_UINT).
  std::vector<std::uint32_t> back_buffer(static_cast<std::size_t>(row_pixels) * height);
  std::vector<std::uint32_t> depth_buffer(back_buffer.size());
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const bool box = x >= 120 && x < 200 && y >= 60 && y < 120;
      const std::uint32_t r = 255u * x / width, g = 255u * y / height, b = box ? 255u : 137u, a = 255u;
      back_buffer[y * row_pixels + x] = r | g << 8 | b << 16 | a << 24;
      const std::uint32_t code = formats::float_to_unorm(decoder.encode(box ? 2.0 : 8.0), 24);
      depth_buffer[y * row_pixels + x] = code | (box ? box_stencil : 0u) << 24;
    }
  }

  // Interaxial 3% of the screen width, zero parallax at z = 4: the box comes out of the screen.
  const ParallaxModel model = StereoCamera{0.03, 4.0}.parallax(width, EyeDirection::left_to_right);
  Options options;  // Method::exact, holes filled with the background

  // The other eye in the same formats: colour blended in linear light, depth as D24S8 (each
  // pixel keeps the stencil of the source pixel it came from), and the status of every pixel.
  std::vector<std::uint32_t> right_buffer(back_buffer.size());
  std::vector<std::uint32_t> right_depth(back_buffer.size());
  std::vector<std::uint8_t> status(static_cast<std::size_t>(width) * height);
  SourceView source;
  source.color = ColorView::packed(ColorFormat::rgba8_srgb, back_buffer.data(), width, height, pitch);
  source.depth_buffer = DepthBuffer::of(DepthFormat::unorm24_s8, depth_buffer.data(), width, height, pitch);
  TargetView target;
  target.color = MutableColorView::packed(ColorFormat::rgba8_srgb, right_buffer.data(), width, height, pitch);
  target.depth_buffer = MutableDepthBuffer::of(DepthFormat::unorm24_s8, right_depth.data(), width, height, pitch);
  target.status = BytePlane{status.data(), width, height, width};

  const Status result = reproject::reproject(source, decoder, model, options, target);
  if (!result) {
    std::fprintf(stderr, "reproject failed: %s\n", result.message());
    return 1;
  }

  unsigned long count[4] = {};  // indexed by PixelStatus
  for (std::uint8_t s : status) {
    if (s > static_cast<std::uint8_t>(PixelStatus::clipped)) {
      std::fprintf(stderr, "unexpected status byte %u\n", static_cast<unsigned>(s));
      return 1;
    }
    ++count[s];
  }
  // Where the box landed in the right eye, by its stencil: one row through its middle.
  int box_begin = -1, box_end = -1;
  for (int x = 0; x < width; ++x) {
    if (right_depth[90 * row_pixels + x] >> 24 == box_stencil) {
      if (box_begin < 0) box_begin = x;
      box_end = x + 1;
    }
  }
  std::printf("RGBA8 sRGB + D24S8, pitch %d bytes: hit %lu, hole %lu, outside %lu, clipped %lu; "
              "box (stencil %u) at columns %d-%d of row 90, was 120-199\n",
              pitch, count[0], count[1], count[2], count[3], box_stencil, box_begin, box_end - 1);

  // The same call on the engine's job system instead of the library's threads: the same bytes.
  std::vector<std::uint32_t> jobs_buffer(back_buffer.size());
  target.color = MutableColorView::packed(ColorFormat::rgba8_srgb, jobs_buffer.data(), width, height, pitch);
  target.depth_buffer = MutableDepthBuffer{};
  target.status = BytePlane{};
  const Status jobs_result = reproject::reproject(source, decoder, model, options, target, ParallelFor{nullptr, run_jobs});
  if (!jobs_result) {
    std::fprintf(stderr, "reproject on the job system failed: %s\n", jobs_result.message());
    return 1;
  }
  bool same = true;
  for (int y = 0; y < height; ++y) {
    same = same && std::memcmp(&jobs_buffer[y * row_pixels], &right_buffer[y * row_pixels], width * 4u) == 0;
  }
  std::printf("on the engine's job system: %s\n", same ? "the same pixels" : "DIFFERENT pixels");
  return same && count[0] > static_cast<unsigned long>(width) * height / 2 && box_begin >= 0 && box_begin != 120 ? 0 : 1;
}
