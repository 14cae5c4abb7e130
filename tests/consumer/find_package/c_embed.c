/* The C interface from an installed package: one frame (a box in front of a wall, standard
 * depth) reprojected to the right eye through reproject.h, from a C99 translation unit. */
#include <stdio.h>
#include <stdlib.h>

#include "reproject/reproject.h"

enum { W = 320, H = 180, N = W * H };
static float color[3][N], depth[N], right_color[3][N], right_depth[N];
static uint8_t status[N];

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
  return count[REPROJECT_PIXEL_HIT] > N / 2 ? 0 : 1;
}
