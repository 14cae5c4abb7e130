/* The C interface from an installed package: one frame (a box in front of a wall, standard
 * depth) reprojected to the right eye through reproject.h, from a C99 translation unit: as float
 * planes, then as an engine's RGBA8 back buffer and D24S8 depth buffer (reproject_warp_buffers). */
#include <stdio.h>
#include <stdlib.h>

#include "reproject/reproject.h"

enum { W = 320, H = 180, N = W * H };
static float color[3][N], depth[N], right_color[3][N], right_depth[N];
static uint8_t status[N];
/* The engine's buffers: 32-bit pixels, rows of `pitch` bytes (here with no padding). */
static uint32_t back_buffer[N], depth_buffer[N], right_buffer[N], right_depth_buffer[N];

int main(void) {
  reproject_decoder decoder;
  reproject_parallax model;
  reproject_options options;
  reproject_source source = {0};
  reproject_target target = {0};
  unsigned long count[4] = {0};
  int x, y, c;

  if (reproject_decoder_from_near_far(REPROJECT_DEPTH_STANDARD, 0.1, 100.0, &decoder) != REPROJECT_OK ||
      reproject_parallax_from_stereo(0.03, 4.0, W, REPROJECT_LEFT_TO_RIGHT, &model) != REPROJECT_OK) {
    fprintf(stderr, "setup failed: %s\n", reproject_last_error_message());
    return 1;
  }
  for (y = 0; y < H; ++y) {
    for (x = 0; x < W; ++x) {
      const int box = x >= 120 && x < 200 && y >= 60 && y < 120;
      const double z = box ? 2.0 : 8.0;
      color[0][y * W + x] = (float)x / W;
      color[1][y * W + x] = (float)y / H;
      color[2][y * W + x] = box ? 1.0f : 0.25f;
      depth[y * W + x] = (float)((1.0 / 0.1 - 1.0 / z) / (1.0 / 0.1 - 1.0 / 100.0));
    }
  }
  source.color.layout = target.color.layout = REPROJECT_LAYOUT_PLANAR;
  source.color.channels = target.color.channels = 3;
  for (c = 0; c < 3; ++c) {
    source.color.plane[c].data = color[c];
    target.color.plane[c].data = right_color[c];
    source.color.plane[c].width = target.color.plane[c].width = W;
    source.color.plane[c].height = target.color.plane[c].height = H;
    source.color.plane[c].stride = target.color.plane[c].stride = W;
  }
  source.depth.data = depth;
  target.depth.data = right_depth;
  source.depth.width = target.depth.width = target.status.width = W;
  source.depth.height = target.depth.height = target.status.height = H;
  source.depth.stride = target.depth.stride = target.status.stride = W;
  target.status.data = status;

  reproject_options_init(&options); /* exact, holes filled with the background */
  if (reproject_warp(&source, &decoder, &model, &options, &target, NULL) != REPROJECT_OK) {
    fprintf(stderr, "reproject_warp failed: %s\n", reproject_last_error_message());
    return 1;
  }
  for (x = 0; x < N; ++x) {
    if (status[x] > REPROJECT_PIXEL_CLIPPED) return 1;
    ++count[status[x]];
  }
  printf("C: hit %lu, hole %lu, outside %lu, clipped %lu (arch %s)\n", count[0], count[1], count[2], count[3],
         reproject_arch_name(reproject_selected_arch()));
  if (count[REPROJECT_PIXEL_HIT] <= N / 2) return 1;

  /* The same frame as an RGBA8 back buffer and a D24S8 depth buffer (depth in bits 0-23, the
   * stencil byte above: 1 on the box), reprojected in those formats. */
  {
    reproject_source_buffers engine = {0};
    reproject_target_buffers right = {0};
    const int64_t pitch = 4 * W; /* bytes */
    uint32_t box_code;
    unsigned long box = 0;
    for (x = 0; x < N; ++x) {
      const int on_box = x % W >= 120 && x % W < 200 && x / W >= 60 && x / W < 120;
      /* R, G, B, A in memory order: a little-endian word */
      back_buffer[x] = (uint32_t)(color[0][x] * 255.0f) | (uint32_t)(color[1][x] * 255.0f) << 8 |
                       (uint32_t)(color[2][x] * 255.0f) << 16 | 0xFF000000u;
      depth_buffer[x] = (uint32_t)(depth[x] * 16777215.0f + 0.5f) | (uint32_t)on_box << 24;
    }
    box_code = depth_buffer[90 * W + 160] & 0xFFFFFFu;
    engine.pixels.data = back_buffer;
    right.pixels.data = right_buffer;
    engine.pixels.format = right.pixels.format = REPROJECT_COLOR_RGBA8;
    engine.depth_buffer.data = depth_buffer;
    right.depth_buffer.data = right_depth_buffer;
    engine.depth_buffer.format = right.depth_buffer.format = REPROJECT_DEPTH_FORMAT_UNORM24_S8;
    engine.pixels.width = right.pixels.width = engine.depth_buffer.width = right.depth_buffer.width = W;
    engine.pixels.height = right.pixels.height = engine.depth_buffer.height = right.depth_buffer.height = H;
    engine.pixels.stride = right.pixels.stride = engine.depth_buffer.stride = right.depth_buffer.stride = pitch;
    if (reproject_warp_buffers(&engine, &decoder, &model, &options, &right, NULL) != REPROJECT_OK) {
      fprintf(stderr, "reproject_warp_buffers failed: %s\n", reproject_last_error_message());
      return 1;
    }
    /* Each output pixel carries the stencil of the pixel it came from: 1 exactly where the box's
     * depth and blue landed. */
    for (x = 0; x < N; ++x) {
      const uint32_t stencil = right_depth_buffer[x] >> 24, code = right_depth_buffer[x] & 0xFFFFFFu;
      if (stencil != (code == box_code) || stencil != ((right_buffer[x] >> 16 & 0xFFu) == 255u)) {
        fprintf(stderr, "rgba8 + unorm24_s8: pixel %d: stencil %u, depth %u, colour %08x\n", x, (unsigned)stencil,
                (unsigned)code, (unsigned)right_buffer[x]);
        return 1;
      }
      box += stencil;
    }
    printf("C, rgba8 + unorm24_s8: %lu box pixels in the right eye (%lu in the source)\n", box, 80ul * 60ul);
    if (box == 0) return 1;
  }
  return 0;
}
