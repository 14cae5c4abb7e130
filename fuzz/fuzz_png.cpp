// libFuzzer harness for the PNG reader (tools/imageio read_png, and read_depth on a .png). Checked
// besides "no crash, no sanitizer report": a failure is one of the reader's documented content
// errors, has a message and leaves the output empty; a success gives 1-4 planes of the stated size,
// bit depth 8 or 16, and every value a stored integer within 0 .. 2^bit_depth - 1.
#include <cmath>
#include <cstdint>

#include "fuzz/reader_harness.hpp"

namespace {
constexpr const char* kHarness = "fuzz_png";
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace reproject;
  const std::string& path = fuzz::write_scratch(".png", data, size);

  io::LoadedImage loaded;
  const io::IoStatus status = io::read_png(path, &loaded);
  if (!status.ok()) {
    FUZZ_CHECK(fuzz::content_error(status.error));
    FUZZ_CHECK(!status.message.empty());
    FUZZ_CHECK(loaded.image.empty());
  } else {
    FUZZ_CHECK(fuzz::consistent(loaded.image));
    FUZZ_CHECK(loaded.bit_depth == 8 || loaded.bit_depth == 16);
    const float max_value = loaded.bit_depth == 8 ? 255.0f : 65535.0f;
    for (int c = 0; c < loaded.image.channels(); ++c) {
      const FloatPlane plane = loaded.image.plane(c);
      for (int y = 0; y < plane.height; ++y)
        for (int x = 0; x < plane.width; ++x) {
          const float v = plane.row(y)[x];
          FUZZ_CHECK(v >= 0.0f && v <= max_value && v == std::floor(v));
        }
    }
  }

  // The depth front end on the same bytes: grey only, or a content error.
  io::LoadedImage depth;
  const io::IoStatus depth_status = io::read_depth(path, &depth);
  if (!depth_status.ok()) {
    FUZZ_CHECK(fuzz::content_error(depth_status.error));
    FUZZ_CHECK(depth.image.empty());
  } else {
    FUZZ_CHECK(status.ok());
    FUZZ_CHECK(fuzz::consistent(depth.image) && depth.image.channels() == 1);
  }
  return 0;
}
