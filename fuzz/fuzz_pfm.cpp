// libFuzzer harness for the PFM reader (tools/imageio read_pfm, and read_depth on a .pfm).
// Checked besides "no crash, no sanitizer report": a failure is one of the reader's content
// errors, has a message and leaves the output empty; a success gives 1 ("Pf") or 3 ("PF") planes
// of the header's size, bit depth 32, and the float bits of the file (so the planes are read
// whole: ASan checks they are as large as stated).
#include <cstdint>

#include "fuzz/reader_harness.hpp"

namespace {
constexpr const char* kHarness = "fuzz_pfm";
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace reproject;
  const std::string& path = fuzz::write_scratch(".pfm", data, size);

  io::LoadedImage loaded;
  const io::IoStatus status = io::read_pfm(path, &loaded);
  if (!status.ok()) {
    FUZZ_CHECK(fuzz::content_error(status.error));
    FUZZ_CHECK(!status.message.empty());
    FUZZ_CHECK(loaded.image.empty());
  } else {
    FUZZ_CHECK(fuzz::consistent(loaded.image));
    FUZZ_CHECK(loaded.image.channels() == 1 || loaded.image.channels() == 3);
    FUZZ_CHECK(loaded.bit_depth == 32);
    // A success needs every pixel's bytes: the file holds at least the header's pixels.
    const unsigned long long pixels = static_cast<unsigned long long>(loaded.image.width()) * loaded.image.height();
    FUZZ_CHECK(size >= pixels * 4ull * static_cast<unsigned>(loaded.image.channels()));
    (void)fuzz::touch_all(loaded.image);
  }

  io::LoadedImage depth;
  const io::IoStatus depth_status = io::read_depth(path, &depth);
  if (!depth_status.ok()) {
    FUZZ_CHECK(fuzz::content_error(depth_status.error));
    FUZZ_CHECK(depth.image.empty());
  } else {
    FUZZ_CHECK(status.ok() && loaded.image.channels() == 1);
    FUZZ_CHECK(fuzz::consistent(depth.image) && depth.image.channels() == 1);
  }
  return 0;
}
