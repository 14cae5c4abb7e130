// Embedding reproject: synthesise the right eye of one frame with one call.
// The frame is made here: a colour gradient, and a box at z = 2 in front of a wall at z = 8,
// stored as standard depth (0 at near, 1 at far).
#include <cstdint>
#include <cstdio>
#include <vector>

#include "reproject/reproject.hpp"

int main() {
  using namespace reproject;
  const int width = 320;
  const int height = 180;
  const DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::standard, 0.1, 100.0);

  Image color(width, height, 3);  // three planes: R, G, B
  Image depth(width, height);
  const MutableFloatPlane red = color.mutable_plane(0), green = color.mutable_plane(1),
                          blue = color.mutable_plane(2), stored_depth = depth.mutable_plane();
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const bool box = x >= 120 && x < 200 && y >= 60 && y < 120;
      red.row(y)[x] = static_cast<float>(x) / width;
      green.row(y)[x] = static_cast<float>(y) / height;
      blue.row(y)[x] = box ? 1.0f : 0.25f;
      stored_depth.row(y)[x] = decoder.encode(box ? 2.0 : 8.0);
    }
  }

  // Interaxial 3% of the screen width, zero parallax at z = 4: the box comes out of the screen.
  const ParallaxModel model = StereoCamera{0.03, 4.0}.parallax(width, EyeDirection::left_to_right);
  Options options;  // Method::exact, holes filled with the background

  Image right_color(width, height, 3);
  Image right_depth(width, height);
  std::vector<std::uint8_t> status(static_cast<std::size_t>(width) * height);
  SourceView source;
  source.color = color.color();
  source.depth = depth.plane();
  TargetView target;
  target.color = right_color.mutable_color();
  target.depth = right_depth.mutable_plane();
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
  std::printf("hit %lu, hole %lu, outside %lu, clipped %lu\n", count[0], count[1], count[2], count[3]);
  return 0;
}
