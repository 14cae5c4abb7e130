// libFuzzer harness for the OpenEXR reader (tools/imageio read_exr with its channel rules, and
// read_depth on a .exr). OpenEXR itself comes from Debian and is not instrumented:
// ASan and the coverage guidance see our reader and what it does with the library's results.
// Checked besides "no crash, no sanitizer report": a failure is one of the reader's content
// errors, has a message and leaves the output empty (colour and depth); a success has colour or
// depth (or both) of one size, bit depth 16 or 32, and names the channels it read.
#include <cstdint>

#include "fuzz/reader_harness.hpp"

namespace {
constexpr const char* kHarness = "fuzz_exr";

// OpenEXR allocates each header attribute at the size the file states (up to 2 GiB) before it
// reads it; under ASan, whose shadow memory is touched for all of it, such an input costs seconds
// instead of microseconds and the run slows to a few executions a second. This walks the first
// header's attributes (name, type, 32-bit size, value) and says whether one states a size beyond
// the end of the file.
bool states_oversized_attribute(const std::uint8_t* data, std::size_t size) {
  std::size_t at = 8;  // magic number and version
  if (size < at) return false;
  // Past a NUL-terminated string; its length, or -1 at the end of the file.
  auto skip_string = [&]() -> long {
    const std::size_t start = at;
    while (at < size && data[at] != 0) ++at;
    if (at >= size) return -1;
    ++at;
    return static_cast<long>(at - start - 1);
  };
  for (int attribute = 0; attribute < 1000; ++attribute) {
    if (skip_string() <= 0) return false;  // an empty name ends the header (or the file ended)
    if (skip_string() < 0) return false;   // the type name (which a damaged file may leave empty)
    if (size - at < 4) return false;
    const std::uint32_t stated = static_cast<std::uint32_t>(data[at]) | static_cast<std::uint32_t>(data[at + 1]) << 8 |
                                 static_cast<std::uint32_t>(data[at + 2]) << 16 |
                                 static_cast<std::uint32_t>(data[at + 3]) << 24;
    at += 4;
    if (stated > size - at) return true;
    at += stated;
  }
  return false;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace reproject;
  // Such inputs still reach the reader, one in eight (chosen by content, so that a run is
  // reproducible): enough to keep the reader's handling of a damaged header under test without
  // letting OpenEXR's allocations set the pace of the whole run.
  if (states_oversized_attribute(data, size)) {
    std::uint32_t hash = 2166136261u;
    for (std::size_t i = 0; i < size; ++i) hash = (hash ^ data[i]) * 16777619u;
    if (hash % 8 != 0) return 0;
  }
  const std::string& path = fuzz::write_scratch(".exr", data, size);

  io::LoadedImage loaded;
  const io::IoStatus status = io::read_exr(path, &loaded);
  if (!status.ok()) {
    FUZZ_CHECK(fuzz::content_error(status.error));
    FUZZ_CHECK(!status.message.empty());
    FUZZ_CHECK(loaded.image.empty() && loaded.depth.empty());
  } else {
    FUZZ_CHECK(!loaded.image.empty() || !loaded.depth.empty());
    if (!loaded.image.empty()) {
      FUZZ_CHECK(fuzz::consistent(loaded.image));
      (void)fuzz::touch_all(loaded.image);
    }
    if (!loaded.depth.empty()) {
      FUZZ_CHECK(fuzz::consistent(loaded.depth) && loaded.depth.channels() == 1);
      FUZZ_CHECK(!loaded.depth_channel.empty());
      (void)fuzz::touch_all(loaded.depth);
    }
    if (!loaded.image.empty() && !loaded.depth.empty())
      FUZZ_CHECK(loaded.image.width() == loaded.depth.width() && loaded.image.height() == loaded.depth.height());
    FUZZ_CHECK(loaded.bit_depth == 16 || loaded.bit_depth == 32);
  }

  // The depth front end (its own channel rule and the one-channel fallback) on the same bytes.
  io::LoadedImage depth;
  const io::IoStatus depth_status = io::read_depth(path, &depth);
  if (!depth_status.ok()) {
    FUZZ_CHECK(fuzz::content_error(depth_status.error));
    FUZZ_CHECK(depth.image.empty());
  } else {
    FUZZ_CHECK(fuzz::consistent(depth.image) && depth.image.channels() == 1);
  }

  // Named channels, which may or may not exist: every other input (each read costs a header parse,
  // and OpenEXR allocates what a damaged header's attribute sizes say, which is slow under ASan).
  if (size % 2 == 1) {
    io::ExrReadOptions options;
    options.color_layer = "ViewLayer.Combined";
    options.depth_channel = "";
    io::LoadedImage named;
    const io::IoStatus named_status = io::read_exr(path, &named, options);
    if (!named_status.ok()) FUZZ_CHECK(fuzz::content_error(named_status.error) && named.image.empty());
    else FUZZ_CHECK(named.depth.empty() && fuzz::consistent(named.image));
  }
  return 0;
}
