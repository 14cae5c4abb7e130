// libFuzzer harness for a whole `reproject warp` (tools/cli: run_warp, with the tool's own file
// handling), from fuzzer-chosen colour and depth file bytes together. The input is
//   byte 0: the colour file's format (PNG, PFM, EXR) and the depth file's, 3 x 3;
//   byte 1: the method (5) and the camera: linear depth, standard depth or a disparity map (3);
//   bytes 2-3: the colour file's length (little-endian; the rest is the depth file).
// Checked besides "no crash, no sanitizer report":
//  * the command returns 0 or throws the tool's Failure with an input (3) or runtime (1) code and
//    a message: the flags are fixed and valid and the outputs writable, so never usage (2) or
//    output (4), and no other exception;
//  * on success every output exists, reads back at the target's size, the status holds only the
//    four statuses; on failure no output exists (all or nothing);
//  * either way no temporary file is left next to the outputs.
// Frames larger than 2^20 pixels are skipped (their headers are the reader harnesses' business):
// a whole warp of one would take far longer than libFuzzer's time per input.
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cli.hpp"
#include "fuzz/reader_harness.hpp"

namespace {

using namespace reproject;
constexpr const char* kHarness = "fuzz_warp";
constexpr long long kMaxPixels = 1LL << 20;

// This process's scratch directory (inputs and outputs), removed at exit with what it holds.
const std::string& scratch_dir() {
  static const std::string dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string d = std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/reproject-fuzz-warp." +
                    std::to_string(static_cast<long>(getpid()));
    if (mkdir(d.c_str(), 0700) != 0 && errno != EEXIST) fuzz::fail(kHarness, "cannot create the scratch directory");
    return d;
  }();
  return dir;
}

std::vector<std::string> entries(const std::string& dir) {
  std::vector<std::string> names;
  if (DIR* d = opendir(dir.c_str())) {
    while (const dirent* e = readdir(d)) {
      const std::string name = e->d_name;
      if (name != "." && name != "..") names.push_back(name);
    }
    closedir(d);
  }
  return names;
}

void clear(const std::string& dir) {
  for (const std::string& name : entries(dir)) std::remove((dir + "/" + name).c_str());
}

void write_file(const std::string& path, const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) fuzz::fail(kHarness, "cannot create an input file");
  const bool written = std::fwrite(data, 1, size, f) == size;
  if (std::fclose(f) != 0 || !written) fuzz::fail(kHarness, "cannot write an input file");
}

const char* const kExtensions[] = {".png", ".pfm", ".exr"};
const char* const kMethods[] = {"exact", "scanline", "march16", "single", "secant"};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // run_warp prints a line per success: keep the fuzzer's output readable.
  if (std::freopen("/dev/null", "w", stdout) == nullptr) return 0;
  // Made first, so that the name outlives the clean-up registered after it.
  (void)scratch_dir();
  std::atexit([] {
    clear(scratch_dir());
    rmdir(scratch_dir().c_str());
  });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 4) return 0;
  const std::string& dir = scratch_dir();
  clear(dir);
  const std::size_t color_size = std::min<std::size_t>(size - 4, data[2] | (data[3] << 8));
  const std::string color = dir + "/colour" + kExtensions[data[0] % 3];
  const std::string depth = dir + "/depth" + kExtensions[(data[0] / 3) % 3];
  write_file(color, data + 4, color_size);
  write_file(depth, data + 4 + color_size, size - 4 - color_size);

  io::ImageInfo info;
  if (io::read_image_info(color, &info).ok() && static_cast<long long>(info.width) * info.height > kMaxPixels) return 0;
  if (io::read_depth_info(depth, &info).ok() && static_cast<long long>(info.width) * info.height > kMaxPixels) return 0;

  const std::string out = dir + "/out.pfm", out_depth = dir + "/out-depth.exr", status = dir + "/status.png";
  std::vector<std::string> words = {"reproject", "warp", "--color", color, "--depth", depth, "--out", out,
                                    "--out-depth", out_depth, "--status", status, "--threads", "1",
                                    "--method", kMethods[data[1] % 5]};
  switch ((data[1] / 5) % 3) {
    case 0: words.insert(words.end(), {"--encoding", "linear", "--convergence", "3"}); break;
    case 1: words.insert(words.end(), {"--encoding", "standard", "--near", "0.5", "--far", "50", "--convergence", "3"}); break;
    default: words.insert(words.end(), {"--disparity", "--unknown-depth", "nan"}); break;
  }
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);

  bool ok = false;
  try {
    FUZZ_CHECK(cli::run_warp(static_cast<int>(argv.size()) - 1, argv.data()) == cli::kExitOk);
    ok = true;
  } catch (const cli::Failure& failure) {
    if (failure.code != cli::kExitInput && failure.code != cli::kExitRuntime) {
      std::fprintf(stderr, "fuzz_warp: exit %d: %s\n", failure.code, failure.message.c_str());
    }
    FUZZ_CHECK(failure.code == cli::kExitInput || failure.code == cli::kExitRuntime);
    FUZZ_CHECK(!failure.message.empty());
  } catch (...) {
    fuzz::fail(kHarness, "an exception other than cli::Failure escaped run_warp");
  }

  // Nothing but the inputs and, on success, the three outputs.
  for (const std::string& name : entries(dir)) {
    const bool input = dir + "/" + name == color || dir + "/" + name == depth;
    const bool output = name == "out.pfm" || name == "out-depth.exr" || name == "status.png";
    if (!input && !(ok && output)) std::fprintf(stderr, "fuzz_warp: left behind: %s\n", name.c_str());
    FUZZ_CHECK(input || (ok && output));
  }
  if (ok) {
    io::LoadedImage color_out, depth_out, status_out;
    FUZZ_CHECK(io::read_image(out, &color_out).ok());
    FUZZ_CHECK(io::read_depth(out_depth, &depth_out).ok());
    FUZZ_CHECK(io::read_depth(status, &status_out).ok());
    const Image& s = status_out.image;
    FUZZ_CHECK(fuzz::consistent(color_out.image) && fuzz::consistent(depth_out.image) && fuzz::consistent(s));
    FUZZ_CHECK(depth_out.image.width() == s.width() && color_out.image.width() == s.width());
    FUZZ_CHECK(depth_out.image.height() == s.height() && color_out.image.height() == s.height());
    for (int y = 0; y < s.height(); ++y)
      for (int x = 0; x < s.width(); ++x) FUZZ_CHECK(s.plane(0).row(y)[x] <= 3.0f);
  }
  return 0;
}
