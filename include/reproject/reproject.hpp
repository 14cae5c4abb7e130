// reproject: synthesise another eye's view from one view (colour + depth) by moving each pixel
// horizontally by its parallax (docs/DESIGN.md). One entry point; every method shares the decoder, the
// per-row parallax decode and the resolve stage, so their outputs mean the same thing.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>

#include "reproject/depth.hpp"
#include "reproject/image.hpp"
#include "reproject/parallax.hpp"
#include "reproject/memory.hpp"
#include "reproject/status.hpp"

namespace reproject {

// How a target pixel searches its row for the source pixel that lands on it (DESIGN §6).
enum class Method : std::uint8_t {
  scanline,  // one source pixel a step over the allowed range: exact inside it, O(range)
  march16,   // fixed march (Options::march_steps, default 16), re-projection with the hit sample
  single,    // one depth sample at the probe parallax, re-projected
  secant,    // adaptive march over the parallax the row can reach, then secant refinement
  exact,     // forward sweep in occlusion-compatible order: the reference
};
constexpr int kMethodCount = 5;
// Names. Every enum of the API has a short stable name (to_string; "unknown" for a value outside
// the enum) and a parser that accepts the same names: parse_*(name, out) returns whether `name` is
// one, and then writes the value to *out unless `out` is null (so a null `out` only checks the
// name); a null or unknown name returns false and writes nothing.
const char* to_string(Method method) noexcept;
bool parse_method(const char* name, Method* out) noexcept;  // "scanline", "march16", ...

// Instruction sets the kernels can be compiled for: the x86 ones on x86-64 (sse = SSE4.1,
// avx2 = AVX2 + FMA + F16C, avx512 = AVX-512 F/CD/DQ/BW), neon (Advanced SIMD) on AArch64, and
// the scalar references everywhere. Every SIMD kernel is bit-identical to its scalar reference
// with the same FMA policy: scalar, avx2, avx512 and neon fuse multiply-adds and so give the same
// bits as each other on every processor; sse (no FMA instructions) does not, and matches the
// scalar reference built without fusing.
enum class Arch : std::uint8_t { scalar, sse, avx2, avx512, neon };
constexpr int kArchCount = 5;
const char* to_string(Arch arch) noexcept;
bool parse_arch(const char* name, Arch* out) noexcept;  // "scalar", "sse", "avx2", "avx512", "neon"
// Compiled in (for the target processor: x86 sets on x86-64, neon on AArch64; none with the CMake
// option REPROJECT_SIMD=OFF), and supported by this CPU and operating system.
bool arch_supported(Arch arch) noexcept;
// The instruction set calls use when Options::arch is unset: the best supported, chosen once, or
// the one named by the environment variable REPROJECT_FORCE_ARCH (scalar|sse|avx2|avx512|neon) when
// it is supported. A forced name that is unknown or not supported here selects the best supported
// set, and the first call says so in one line on stderr. (On AVX-512, the first rgba8_srgb call
// also times two ways of reading the sRGB tables, about 0.2 ms once; REPROJECT_SRGB_LOOKUP=
// gathers|permutes fixes the way: docs/BEHAVIOUR.md, "Instruction sets and FMA policy".)
Arch selected_arch() noexcept;

// The library's version, "MAJOR.MINOR.PATCH" (the CMake project's version): static storage, never
// null. The C interface's reproject_version(), the Python package's __version__ and
// `reproject --version` print the same string.
const char* version() noexcept;

// Per target pixel, in the optional status plane.
enum class PixelStatus : std::uint8_t {
  hit = 0,      // the ray meets the surface on a segment that is not a wall
  hole = 1,     // the ray meets a wall (disocclusion): filled per HoleFill
  outside = 2,  // the crossing lies off the source row: colour per EdgeMode
  clipped = 3,  // the surface is nearer than the allowed negative parallax at the ray's near end
};

enum class HoleFill : std::uint8_t {
  background,  // colour and depth of the wall's farther endpoint ("repeat background")
  foreground,  // of its nearer endpoint
  none,        // colour and depth of hole pixels are not written
};
constexpr int kHoleFillCount = 3;
const char* to_string(HoleFill fill) noexcept;
bool parse_hole_fill(const char* name, HoleFill* out) noexcept;  // "background", "foreground", "none"

enum class EdgeMode : std::uint8_t {
  clamp,   // outside pixels take the edge pixel's colour and depth
  none,    // outside pixels' colour and depth are not written (status only)
  black,   // colour 0 in every channel; depth of the edge pixel
  mirror,  // colour and depth read at x* reflected about the edge pixel (-x*, or 2 (Ws-1) - x*)
};
constexpr int kEdgeModeCount = 4;
const char* to_string(EdgeMode edge) noexcept;
bool parse_edge_mode(const char* name, EdgeMode* out) noexcept;  // "clamp", "none", "black", "mirror"

struct Options {
  Method method = Method::exact;
  // Largest crossed ("out of the screen") parallax the search allows, in pixels, >= 0: the ray's
  // near end has parallax p_near = sign(b) * max_negative_parallax. Unset: the most negative
  // parallax present in the frame, so nothing is clipped (scanline, march16 and secant find it
  // with one pass over the depth; single and exact need no pass, as they never search from it).
  std::optional<float> max_negative_parallax;
  float hole_threshold = 1.0f;  // tau, pixels (>= 0): segment [j, j+1] is a wall if p[j+1] - p[j] > tau
  HoleFill hole_fill = HoleFill::background;
  EdgeMode edge = EdgeMode::clamp;
  int guard = 0;  // guard band columns on each side of the source: target width = source width - 2 guard
  std::optional<float> probe_parallax;  // `single`: parallax of its one sample; unset: a (infinity)
  int march_steps = 16;                 // `march16`: number of equal steps (1..1024)
  // `secant`: most march steps per 16-pixel tile (1..4096). Spans up to this many pixels are
  // walked column by column (exact); wider ones take this many equal steps and refine by secant,
  // and can then step over a feature thinner than one step.
  int secant_max_steps = 256;
  std::optional<Arch> arch;             // unset: selected_arch(); an unsupported one is an error
  // Rows are split over this many threads of the library's persistent pool (the calling thread
  // is one of them); 0: one per hardware thread; 1: the calling thread only. Ignored by the
  // overloads that take a ParallelFor. The output does not depend on it, bit for bit.
  int threads = 0;
  // A request to stop, owned by the caller and set from any thread (or a signal handler: a
  // lock-free store) while the call runs: the rows are run in blocks of a few rows and the flag is
  // read before each, so the call returns StatusCode::cancelled soon after it is set (an 8K frame
  // within a few tens of milliseconds at one thread, with the slowest method). The outputs are
  // then unspecified: some rows written, others not. Checked after validation: an invalid call
  // still returns its error. Null: the call cannot be stopped. The library only reads it.
  const std::atomic<bool>* cancel = nullptr;
};

// An engine's own job system: `run` must call task(task_context, i) once for every i in
// [0, count), in any order and on any threads, and return when all calls have returned. A call
// runs it once, or twice when the default near limit needs its pass over the depth.
struct ParallelFor {
  void* context = nullptr;
  void (*run)(void* context, int count, void (*task)(void* task_context, int index), void* task_context) = nullptr;
};

// The view being reprojected. Depth and colour have the same size: the target's width plus
// 2 * guard columns, and its height. Depth is a float plane (`depth`) or a depth buffer in any
// DepthFormat (`depth_buffer`): set exactly one of them. (Every member has a default, so that
// brace initialisation of the first few, e.g. SourceView{color, depth}, is warning-free.)
struct SourceView {
  ColorView color{};
  FloatPlane depth{};
  DepthBuffer depth_buffer{};
};

// Outputs. Colour is required (same channel count, layout and format as the source); depth (same
// encoding and format as the source: `depth` for float depth, `depth_buffer` for any format),
// status (PixelStatus bytes) and source_x (x* in source columns, i.e. counted from the source's
// first column, guard band included) are written when their data pointer is non-null. No output
// may overlap an input or another output.
struct TargetView {
  MutableColorView color{};
  MutableFloatPlane depth{};
  BytePlane status{};
  MutableFloatPlane source_x{};
  MutableDepthBuffer depth_buffer{};
};

// Reprojects `source` into `target`. Validates everything once, then runs the method over every
// row. A frame of width or height 0 is valid and writes nothing.
Status reproject(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target) noexcept;

// The same, with the rows split over the caller's job system instead of the library's pool.
Status reproject(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target, const ParallelFor& jobs) noexcept;

// Centre view to both eyes in one call: `centre_to_right` is the model for the right eye
// (e.g. StereoCamera::parallax(width, EyeDirection::centre_to_right)); the left eye uses its
// mirror (-a, -b). Each eye's default near limit is its own frame's.
Status reproject_pair(const SourceView& centre, const DepthDecoder& decoder,
                      const ParallaxModel& centre_to_right, const Options& options,
                      const TargetView& left, const TargetView& right) noexcept;
Status reproject_pair(const SourceView& centre, const DepthDecoder& decoder,
                      const ParallaxModel& centre_to_right, const Options& options,
                      const TargetView& left, const TargetView& right, const ParallelFor& jobs) noexcept;

}  // namespace reproject
