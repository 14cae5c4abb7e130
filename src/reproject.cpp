// The entry points: validate everything once (never inside the pixel loops), then run the rows,
// split in bands over the library's thread pool or the caller's job system.
#include "reproject/reproject.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <type_traits>
#include <vector>

#include "kernels/dispatch.hpp"
#include "kernels/frame.hpp"
#include "kernels/rows.hpp"
#include "src/reproject_internal.hpp"
#include "src/thread_pool.hpp"
#include "src/view_bounds.hpp"

namespace reproject {
namespace {

// Widths above this would make integer column coordinates inexact in float.
constexpr int kMaxWidth = 1 << 22;

// A view's rows as bytes (view_bounds.hpp), with the name its messages use.
struct NamedView {
  detail::ViewBytes bytes;
  const char* name = "";
};

template <class T>
NamedView named(const PlaneView<T>& plane, int per_pixel, const char* name) {
  return NamedView{detail::view_bytes(plane, per_pixel), name};
}
template <class Byte>
NamedView named(const DepthBufferT<Byte>& depth, const char* name) {
  return named(PlaneView<Byte>{depth.data, depth.width, depth.height, depth.stride}, bytes_per_pixel(depth.format), name);
}
template <class T>
int colour_views(const ColorViewT<T>& color, NamedView* out, const char* name) {
  if (color.format != ColorFormat::float32) {
    out[0] = named(color.pixels, bytes_per_pixel(color.format), name);
    return 1;
  }
  const bool interleaved = color.layout == ColorLayout::interleaved_rgba;
  for (int c = 0; c < (interleaved ? 1 : color.channels); ++c) out[c] = named(color.plane[c], interleaved ? 4 : 1, name);
  return interleaved ? 1 : color.channels;
}

// The source depth's size, without forming its stride in bytes (detail::depth_buffer_of does,
// which validation must not do before the stride is checked).
struct Size {
  int width = 0;
  int height = 0;
};
Size depth_size(const SourceView& source) {
  if (source.depth_buffer.data != nullptr) return Size{source.depth_buffer.width, source.depth_buffer.height};
  return Size{source.depth.width, source.depth.height};
}

template <class T>
Status check_plane(const PlaneView<T>& plane, int width, int height, int elements_per_pixel, const char* name,
                   const char* unit = "elements") {
  if (plane.data == nullptr) return Status(StatusCode::null_pointer, "%s: data is null", name);
  if (plane.width < 0 || plane.height < 0)
    return Status(StatusCode::invalid_size, "%s: negative size %dx%d", name, plane.width, plane.height);
  if (plane.width != width || plane.height != height)
    return Status(StatusCode::size_mismatch, "%s: size %dx%d, expected %dx%d", name, plane.width, plane.height, width, height);
  return detail::check_view_bytes(plane, elements_per_pixel, name, unit);
}

template <class T>
Status check_color(const ColorViewT<T>& color, int width, int height, const char* name) {
  if (color.layout != ColorLayout::planar && color.layout != ColorLayout::interleaved_rgba)
    return Status(StatusCode::invalid_option, "%s: unknown colour layout %d", name, static_cast<int>(color.layout));
  if (static_cast<unsigned>(color.format) >= static_cast<unsigned>(kColorFormatCount))
    return Status(StatusCode::invalid_option, "%s: unknown colour format %d", name, static_cast<int>(color.format));
  const bool interleaved = color.layout == ColorLayout::interleaved_rgba;
  if (color.format != ColorFormat::float32) {
    // Packed RGBA pixels in an engine format (ColorView::packed).
    if (!interleaved || color.channels != 4)
      return Status(StatusCode::size_mismatch, "%s: %s is interleaved RGBA (4 channels); this view says %d %s", name,
                    to_string(color.format), color.channels, interleaved ? "interleaved" : "planar");
    const Status status = check_plane(color.pixels, width, height, bytes_per_pixel(color.format), "pixels", "bytes");
    if (!status.ok()) return Status(status.code(), "%s %s %s", name, to_string(color.format), status.message());
    return Status();
  }
  if (interleaved ? color.channels != 4 : (color.channels < 1 || color.channels > 4))
    return Status(StatusCode::size_mismatch, "%s: %d channels (planar takes 1..4, interleaved RGBA 4)", name, color.channels);
  static const char* const kPlaneNames[4] = {"plane 0", "plane 1", "plane 2", "plane 3"};
  for (int c = 0; c < (interleaved ? 1 : color.channels); ++c) {
    const Status status = check_plane(color.plane[c], width, height, interleaved ? 4 : 1, kPlaneNames[c]);
    if (!status.ok()) return Status(status.code(), "%s %s", name, status.message());
  }
  return Status();
}

// A depth buffer (source or output) of the frame's size; strides in bytes.
// A source's rgba8_packed_linear range is checked; a target's is not read (the output is stored
// with the source's range).
template <class Byte>
Status check_depth_buffer(const DepthBufferT<Byte>& depth, int width, int height, const char* name) {
  if (static_cast<unsigned>(depth.format) >= static_cast<unsigned>(kDepthFormatCount))
    return Status(StatusCode::invalid_option, "%s: unknown depth format %d", name, static_cast<int>(depth.format));
  const PlaneView<Byte> bytes{depth.data, depth.width, depth.height, depth.stride};
  Status status = check_plane(bytes, width, height, bytes_per_pixel(depth.format), name, "bytes");
  if (!status.ok()) return Status(status.code(), "%s (%s)", status.message(), to_string(depth.format));
  if (depth.format == DepthFormat::float32 &&
      (reinterpret_cast<std::uintptr_t>(depth.data) % alignof(float) != 0 || depth.stride % 4 != 0))
    return Status(StatusCode::invalid_stride, "%s: float32 depth rows must start on 4-byte boundaries (data %p, stride %td bytes)",
                  name, static_cast<const void*>(depth.data), depth.stride);
  if (std::is_const<Byte>::value && depth.format == DepthFormat::rgba8_packed_linear &&
      !(std::isfinite(depth.linear_near) && std::isfinite(depth.linear_far) && depth.linear_far != depth.linear_near &&
        std::isfinite(depth.linear_far - depth.linear_near)))
    return Status(StatusCode::invalid_option, "%s: rgba8_packed_linear range [%g, %g] must be finite, not empty, "
                  "and its length a finite float", name, depth.linear_near, depth.linear_far);
  return Status();
}

// Depth is given once: the float plane or the depth buffer.
template <class View>
Status check_one_depth(const View& view, const char* name) {
  if (view.depth.data != nullptr && view.depth_buffer.data != nullptr)
    return Status(StatusCode::invalid_option, "%s: both depth (a float plane) and depth_buffer are set; set one", name);
  return Status();
}

Status check_options(const Options& options) {
  if (static_cast<unsigned>(options.method) >= static_cast<unsigned>(kMethodCount))
    return Status(StatusCode::invalid_option, "method: unknown value %d", static_cast<int>(options.method));
  if (options.hole_fill != HoleFill::background && options.hole_fill != HoleFill::foreground && options.hole_fill != HoleFill::none)
    return Status(StatusCode::invalid_option, "hole_fill: unknown value %d", static_cast<int>(options.hole_fill));
  if (static_cast<unsigned>(options.edge) > static_cast<unsigned>(EdgeMode::mirror))
    return Status(StatusCode::invalid_option, "edge: unknown value %d", static_cast<int>(options.edge));
  if (!(options.hole_threshold >= 0.0f) || !std::isfinite(options.hole_threshold))
    return Status(StatusCode::invalid_option, "hole_threshold: %g is not a finite value >= 0", options.hole_threshold);
  if (options.guard < 0) return Status(StatusCode::invalid_option, "guard: %d is negative", options.guard);
  if (options.march_steps < 1 || options.march_steps > 1024)
    return Status(StatusCode::invalid_option, "march_steps: %d is outside 1..1024", options.march_steps);
  if (options.secant_max_steps < 1 || options.secant_max_steps > 4096)
    return Status(StatusCode::invalid_option, "secant_max_steps: %d is outside 1..4096", options.secant_max_steps);
  if (options.max_negative_parallax &&
      (!(*options.max_negative_parallax >= 0.0f) || !std::isfinite(*options.max_negative_parallax)))
    return Status(StatusCode::invalid_option, "max_negative_parallax: %g is not a finite value >= 0",
                  *options.max_negative_parallax);
  if (options.probe_parallax && !std::isfinite(*options.probe_parallax))
    return Status(StatusCode::invalid_option, "probe_parallax: %g is not finite", *options.probe_parallax);
  if (options.arch && !arch_supported(*options.arch))
    return Status(StatusCode::invalid_option, "arch: %s is not supported by this build and CPU", to_string(*options.arch));
  if (options.threads < 0) return Status(StatusCode::invalid_option, "threads: %d is negative", options.threads);
  return Status();
}

Status check_jobs(const ParallelFor& jobs) {
  if (jobs.run == nullptr) return Status(StatusCode::invalid_option, "jobs: ParallelFor::run is null");
  return Status();
}

// A depth buffer or float plane that is not used must be empty: one with its size or format set
// and no data is a buffer the caller meant to give and did not (docs/ERRORS.md, null_pointer).
Status check_unused_depth(const SourceView& source) {
  const DepthBuffer& buffer = source.depth_buffer;
  if (buffer.data == nullptr && (buffer.width != 0 || buffer.height != 0 || buffer.format != DepthFormat::float32))
    return Status(StatusCode::null_pointer, "source depth_buffer: data is null, but its size (%dx%d) and format (%s) are "
                  "set: give its data, or zero it and give depth", buffer.width, buffer.height, to_string(buffer.format));
  if (buffer.data != nullptr && source.depth.data == nullptr && (source.depth.width != 0 || source.depth.height != 0))
    return Status(StatusCode::null_pointer, "source depth: data is null, but its size (%dx%d) is set, beside "
                  "depth_buffer: zero it", source.depth.width, source.depth.height);
  return Status();
}

// Everything but the target: the decoder, the model, the options and the source.
Status check_inputs(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                    const Options& options) {
  Status status = decoder.validate();
  if (!status.ok()) return status;
  status = model.validate();
  if (!status.ok()) return status;
  status = check_options(options);
  if (!status.ok()) return status;
  if (!(status = check_one_depth(source, "source")).ok()) return status;
  if (!(status = check_unused_depth(source)).ok()) return status;
  const Size depth = depth_size(source);
  if (depth.width < 0 || depth.height < 0)
    return Status(StatusCode::invalid_size, "source depth: negative size %dx%d", depth.width, depth.height);
  if (depth.width > kMaxWidth)
    return Status(StatusCode::invalid_size, "source depth: width %d is above the maximum %d", depth.width, kMaxWidth);
  if (depth.width == 0 || depth.height == 0) {
    // An empty frame, unless no depth was given at all beside a colour of some size: then the
    // depth is missing, not empty.
    const int color_width = source.color.width(), color_height = source.color.height();
    if (source.depth.data == nullptr && source.depth_buffer.data == nullptr && color_width > 0 && color_height > 0)
      return Status(StatusCode::null_pointer, "source depth: data is null (neither depth nor depth_buffer has any) "
                    "for a %dx%d colour", color_width, color_height);
    return Status();
  }
  if (source.depth_buffer.data == nullptr) {
    status = check_plane(source.depth, depth.width, depth.height, 1, "source depth");
  } else {
    status = check_depth_buffer(source.depth_buffer, depth.width, depth.height, "source depth_buffer");
  }
  if (!status.ok()) return status;
  status = check_color(source.color, depth.width, depth.height, "source colour");
  if (!status.ok()) return status;
  if (depth.width - 2 * static_cast<long long>(options.guard) < 1)
    return Status(StatusCode::invalid_size, "guard: %d columns on each side leave no target columns of a %d-wide source",
                  options.guard, depth.width);
  return Status();
}

DepthFormat source_depth_format(const SourceView& source) {
  return source.depth_buffer.data != nullptr ? source.depth_buffer.format : DepthFormat::float32;
}

Status check_target(const SourceView& source, const Options& options, const TargetView& target, const char* name) {
  const Size source_size = depth_size(source);
  const int width = source_size.width - 2 * options.guard;
  const int height = source_size.height;
  const DepthFormat depth_format = source_depth_format(source);
  char label[64];
  std::snprintf(label, sizeof label, "%s colour", name);
  Status status = check_color(target.color, width, height, label);
  if (!status.ok()) return status;
  if (target.color.format != source.color.format)
    return Status(StatusCode::size_mismatch, "%s: format %s, the source's is %s", label, to_string(target.color.format),
                  to_string(source.color.format));
  if (target.color.layout != source.color.layout || target.color.channels != source.color.channels)
    return Status(StatusCode::size_mismatch, "%s: %d channels %s, the source has %d %s", label, target.color.channels,
                  target.color.layout == ColorLayout::planar ? "planar" : "interleaved",
                  source.color.channels, source.color.layout == ColorLayout::planar ? "planar" : "interleaved");
  if (!(status = check_one_depth(target, name)).ok()) return status;
  if (target.depth.data) {
    std::snprintf(label, sizeof label, "%s depth", name);
    if (depth_format != DepthFormat::float32)
      return Status(StatusCode::size_mismatch, "%s: a float plane, but the source depth is %s: output depth goes to "
                    "depth_buffer in the source's format", label, to_string(depth_format));
    if (!(status = check_plane(target.depth, width, height, 1, label)).ok()) return status;
  }
  if (target.depth_buffer.data) {
    std::snprintf(label, sizeof label, "%s depth_buffer", name);
    if (target.depth_buffer.format != depth_format)
      return Status(StatusCode::size_mismatch, "%s: format %s, the source depth is %s", label,
                    to_string(target.depth_buffer.format), to_string(depth_format));
    if (!(status = check_depth_buffer(target.depth_buffer, width, height, label)).ok()) return status;
  }
  if (target.status.data) {
    std::snprintf(label, sizeof label, "%s status", name);
    if (!(status = check_plane(target.status, width, height, 1, label)).ok()) return status;
  }
  if (target.source_x.data) {
    std::snprintf(label, sizeof label, "%s source_x", name);
    if (!(status = check_plane(target.source_x, width, height, 1, label)).ok()) return status;
  }
  return Status();
}

// Outputs may share a byte neither with an input nor with each other; the bytes between rows
// are no one's, so the halves of one side-by-side buffer may be an input and an output.
Status check_aliasing(const SourceView& source, const TargetView* const* targets, const char* const* names,
                      int target_count) {
  NamedView inputs[5];
  int input_count = 0;
  inputs[input_count++] = source.depth_buffer.data != nullptr ? named(source.depth_buffer, "source depth_buffer")
                                                              : named(source.depth, 1, "source depth");
  input_count += colour_views(source.color, inputs + input_count, "source colour");

  // Per target: its name and the names of its outputs, for the messages.
  char labels[2][4][32];
  NamedView outputs[18];
  int output_count = 0;
  for (int i = 0; i < target_count; ++i) {
    const TargetView& target = *targets[i];
    static const char* const kFields[4] = {"colour", "depth", "status", "source_x"};
    for (int f = 0; f < 4; ++f) std::snprintf(labels[i][f], sizeof labels[i][f], "%s %s", names[i], kFields[f]);
    output_count += colour_views(target.color, outputs + output_count, labels[i][0]);
    outputs[output_count++] = target.depth_buffer.data != nullptr ? named(target.depth_buffer, labels[i][1])
                                                                  : named(target.depth, 1, labels[i][1]);
    outputs[output_count++] = named(target.status, 1, labels[i][2]);
    outputs[output_count++] = named(target.source_x, 1, labels[i][3]);
  }
  for (int o = 0; o < output_count; ++o) {
    for (int i = 0; i < input_count; ++i)
      if (detail::views_touch(outputs[o].bytes, inputs[i].bytes))
        return Status(StatusCode::aliasing, "%s overlaps %s", outputs[o].name, inputs[i].name);
    for (int p = o + 1; p < output_count; ++p)
      if (detail::views_touch(outputs[o].bytes, outputs[p].bytes))
        return Status(StatusCode::aliasing, "%s overlaps %s", outputs[o].name, outputs[p].name);
  }
  return Status();
}

// A validated target with the outputs it does not want (null data) cleared: their other fields
// were never checked, and the plan must not compute with them (a float depth plane's stride is
// taken in bytes).
TargetView wanted_outputs(const TargetView& target) {
  TargetView clean = target;
  if (clean.depth.data == nullptr) clean.depth = MutableFloatPlane{};
  if (clean.depth_buffer.data == nullptr) clean.depth_buffer = MutableDepthBuffer{};
  if (clean.status.data == nullptr) clean.status = BytePlane{};
  if (clean.source_x.data == nullptr) clean.source_x = MutableFloatPlane{};
  return clean;
}
// The same for the source's depth: the one that is not used is cleared.
SourceView used_depth(const SourceView& source) {
  SourceView clean = source;
  if (clean.depth_buffer.data != nullptr) clean.depth = FloatPlane{};
  return clean;
}

// Options::arch was checked by check_options.
const detail::KernelTable& kernels_for(const Options& options) {
  return *detail::compiled_kernels(options.arch ? *options.arch : selected_arch());
}

bool empty_frame(const SourceView& source) {
  const Size depth = depth_size(source);
  return depth.width == 0 || depth.height == 0;
}

// ---- Rows over threads --------------------------------------------------------------------------
// A call runs in at most two parallel phases over bands of contiguous rows: the default near
// limit (each band's nearest key, reduced in band order) and then the rows. A pair's two eyes
// share each phase. Rows are independent and the reduction is the sequential one regrouped, so
// the output does not depend on the number of threads or bands, bit for bit.

// Several bands per thread: a thread that finishes early takes another (rows differ in cost:
// walls, holes, secant's adaptive march), and the last band to finish is short.
constexpr int kBandsPerThread = 8;
// A bound on the bands of one frame, so that the per-call arrays live on the stack.
constexpr int kMaxBands = 512;

using detail::Frame;
using detail::KernelTable;
using detail::RowScratch;
using detail::ThreadPool;

// One thread's row scratch, on cache lines of its own (a task writes its row pointer).
struct alignas(64) ScratchSlot {
  RowScratch scratch;
  std::atomic<bool> busy{false};  // held by a ParallelFor task for its duration
};

// The scratch of the calls made from one thread. Slot k serves the pool job's participant k
// (0: the caller), or any ParallelFor task that holds it. It outlives the call so that a call
// with the sizes of an earlier one allocates nothing; the calling thread owns it because it is
// blocked in the call for as long as anyone uses it.
struct ScratchSet {
  std::vector<std::unique_ptr<ScratchSlot>> slots;
  bool in_use = false;

  // At least `count` slots, the first `prepared` of them sized for f's widths.
  void reserve(int count, int prepared, const Frame& f) {
    while (static_cast<int>(slots.size()) < count) slots.push_back(std::make_unique<ScratchSlot>());
    for (int k = 0; k < prepared; ++k) detail::prepare_scratch(f, slots[static_cast<std::size_t>(k)]->scratch);
  }
};

// The calling thread's set, or a fresh one when a call is made from inside another on the same
// thread (a job system that runs other work while it waits): that call allocates its scratch.
class ScratchSetLease {
 public:
  ScratchSetLease() {
    thread_local ScratchSet reused;
    set_ = reused.in_use ? &fresh_ : &reused;
    set_->in_use = true;
  }
  ~ScratchSetLease() { set_->in_use = false; }
  ScratchSetLease(const ScratchSetLease&) = delete;
  ScratchSetLease& operator=(const ScratchSetLease&) = delete;
  ScratchSet& set() { return *set_; }

 private:
  ScratchSet fresh_;
  ScratchSet* set_;
};

// Each band runs its rows in blocks of about this many pixels, and reads Options::cancel before
// each block. An 8K row is 7680 pixels, so a block is 2 rows there: at one thread with the
// slowest configuration measured (scanline on the scalar reference over a wide parallax range,
// about 4 ms a row) a cancel is seen within about 10 ms. The check is one relaxed load per block:
// reproject_bench A/B against the unblocked driver showed no difference beyond its run-to-run noise.
constexpr int kBlockPixels = 1 << 14;

// What every task of a phase reads. Task i is band i of the frame, or of both eyes of a pair
// (frames[0] left, frames[1] right), which share each source row and the near pass.
struct RowPhase {
  const KernelTable* kernels = nullptr;
  const Frame* frames = nullptr;
  bool pair = false;
  int near_frame = 0;  // the frame whose near pass runs (the right eye's serves a mirrored pair)
  int bands = 1;
  bool near_pass = false;  // true: nearest[i] = band i's nearest key; false: run band i's rows
  float* nearest = nullptr;
  std::unique_ptr<ScratchSlot>* slots = nullptr;
  int slot_count = 0;
  const std::atomic<bool>* cancel = nullptr;  // Options::cancel
  std::atomic<bool>* stopped = nullptr;       // set by a band that left rows undone
};

void run_band(const RowPhase& phase, int band, RowScratch& scratch) {
  const Frame& f = phase.frames[phase.near_pass ? phase.near_frame : (phase.pair ? 1 : 0)];
  const int begin = static_cast<int>(static_cast<long long>(f.height) * band / phase.bands);
  const int end = static_cast<int>(static_cast<long long>(f.height) * (band + 1) / phase.bands);
  const int block = std::max(1, kBlockPixels / std::max(1, f.source_width));
  // Blocks of one band, in order: the near pass's maximum over them is the band's, bit for bit
  // (std::max from key_far keeps the first of equal keys, wherever the blocks split).
  float nearest = f.key_far;
  for (int y = begin; y < end;) {
    if (phase.cancel != nullptr && phase.cancel->load(std::memory_order_relaxed)) {
      phase.stopped->store(true, std::memory_order_relaxed);
      break;
    }
    const int stop = end - y > block ? y + block : end;
    if (phase.near_pass)
      nearest = std::max(nearest, detail::nearest_key_in_rows(f, *phase.kernels, y, stop));
    else if (phase.pair)
      detail::run_pair_rows(phase.frames[0], phase.frames[1], *phase.kernels, scratch, y, stop);
    else
      detail::run_rows(f, *phase.kernels, scratch, y, stop);
    y = stop;
  }
  if (phase.near_pass) phase.nearest[band] = nearest;
}

// The pool names the thread's slot; the caller prepared every slot the job can use. The tasks
// are noexcept: nothing may unwind into the pool or into a caller's job system.
void pool_task(void* context, int index, int slot) noexcept {
  const RowPhase& phase = *static_cast<const RowPhase*>(context);
  run_band(phase, index, phase.slots[slot]->scratch);
}

// A job system's threads are not ours to name: a task takes any free slot. There are as many
// slots as tasks, so one is free; lowest first, so that slots beyond the job system's
// concurrency stay unused (their buffers never sized).
void jobs_task(void* context, int index) noexcept {
  const RowPhase& phase = *static_cast<const RowPhase*>(context);
  ScratchSlot* slot = nullptr;
  while (slot == nullptr) {
    for (int k = 0; k < phase.slot_count && slot == nullptr; ++k) {
      ScratchSlot* candidate = phase.slots[k].get();
      if (!candidate->busy.load(std::memory_order_relaxed) && !candidate->busy.exchange(true, std::memory_order_acquire))
        slot = candidate;
    }
  }
  detail::prepare_scratch(phase.frames[0], slot->scratch);  // a no-op once sized
  run_band(phase, index, slot->scratch);
  slot->busy.store(false, std::memory_order_release);
}

void run_phase(RowPhase& phase, int count, ThreadPool* pool, int threads, const ParallelFor* jobs) {
  if (jobs != nullptr) {
    jobs->run(jobs->context, count, jobs_task, &phase);
  } else if (pool != nullptr) {
    pool->run(count, threads, pool_task, &phase);
  } else {
    for (int i = 0; i < count; ++i) pool_task(&phase, i, 0);
  }
}

// Runs every row of `frame_count` frames (one, or a pair's two eyes) planned from one source
// with `options`; completes their near limit first when the options leave it to the data.
// `jobs` null: the library's pool with Options::threads. Returns false when Options::cancel
// stopped it (some rows, or the near pass, left undone).
bool run_frames(const KernelTable& kernels, Frame* frames, int frame_count, const Options& options,
                const ParallelFor* jobs) {
  const int height = frames[0].height;
  int threads = 1;
  int bands = 1;
  ThreadPool* pool = nullptr;
  if (jobs != nullptr) {
    // The job system's width is unknown: size the bands for one thread per hardware thread.
    bands = std::min({height, detail::hardware_threads() * kBandsPerThread, kMaxBands});
  } else {
    threads = options.threads > 0 ? std::min(options.threads, ThreadPool::kMaxThreads) : detail::hardware_threads();
    if (threads > 1) {
      pool = ThreadPool::shared();
      bands = std::min({height, threads * kBandsPerThread, kMaxBands});
    }
  }
  const int tasks = bands;

  ScratchSetLease lease;
  ScratchSet& set = lease.set();
  // Pool: one slot per participant (no more than there are tasks), all prepared. Job system: one
  // per task, the first few prepared (as many as a job system with a thread per hardware
  // thread, or 4, uses at once; a wider one sizes its extra slots on first use).
  const int slot_count = jobs != nullptr ? tasks : std::min(threads, tasks);
  const int prepared = jobs != nullptr ? std::min(tasks, std::max(detail::hardware_threads(), 4)) : slot_count;
  set.reserve(slot_count, prepared, frames[0]);

  float nearest[kMaxBands];
  std::atomic<bool> stopped{false};
  RowPhase phase;
  phase.kernels = &kernels;
  phase.frames = frames;
  phase.pair = frame_count == 2;
  phase.bands = bands;
  phase.nearest = nearest;
  phase.slots = set.slots.data();
  phase.slot_count = slot_count;
  phase.cancel = options.cancel;
  phase.stopped = &stopped;
  if (detail::near_pass_needed(frames[0])) {
    // Frame k's nearest key: its bands' keys reduced in band order from key_far, as the
    // sequential pass over the whole frame does.
    phase.near_pass = true;
    auto nearest_key_of = [&](int k) {
      phase.near_frame = k;
      run_phase(phase, tasks, pool, slot_count, jobs);
      float key = frames[k].key_far;
      for (int b = 0; b < bands; ++b) key = std::max(key, nearest[b]);
      return key;
    };
    const float last_key = nearest_key_of(frame_count - 1);
    if (stopped.load(std::memory_order_relaxed)) return false;
    detail::set_near_key(frames[frame_count - 1], last_key);
    if (frame_count == 2) {  // a mirrored pair's eyes share the key (kernels/frame.hpp)
      const float first_key = detail::mirrored_eyes(frames[0], frames[1]) ? last_key : nearest_key_of(0);
      if (stopped.load(std::memory_order_relaxed)) return false;
      detail::set_near_key(frames[0], first_key);
    }
    phase.near_pass = false;
  }
  run_phase(phase, tasks, pool, slot_count, jobs);
  return !stopped.load(std::memory_order_relaxed);
}

Status cancelled() {
  return Status(StatusCode::cancelled, "the cancel flag (Options::cancel; options.cancel in C) was set while the call "
                "ran: its outputs are unspecified");
}

Status reproject_one(const KernelTable& kernels, const SourceView& source, const DepthDecoder& decoder,
                     const ParallaxModel& model, const Options& options, const TargetView& target,
                     const ParallelFor* jobs) {
  Status status = check_inputs(source, decoder, model, options);
  if (!status.ok() || empty_frame(source)) return status;
  if (!(status = check_target(source, options, target, "target")).ok()) return status;
  const TargetView* targets[1] = {&target};
  const char* names[1] = {"target"};
  if (!(status = check_aliasing(source, targets, names, 1)).ok()) return status;
  Frame frame = detail::plan_frame(used_depth(source), decoder, model, options, wanted_outputs(target));
  return run_frames(kernels, &frame, 1, options, jobs) ? Status() : cancelled();
}

Status reproject_two(const SourceView& centre, const DepthDecoder& decoder, const ParallaxModel& centre_to_right,
                     const Options& options, const TargetView& left, const TargetView& right,
                     const ParallelFor* jobs) {
  const ParallaxModel centre_to_left{-centre_to_right.a, -centre_to_right.b};
  Status status = check_inputs(centre, decoder, centre_to_right, options);
  if (!status.ok() || empty_frame(centre)) return status;
  if (!(status = check_target(centre, options, left, "left")).ok()) return status;
  if (!(status = check_target(centre, options, right, "right")).ok()) return status;
  const TargetView* targets[2] = {&left, &right};
  const char* names[2] = {"left", "right"};
  if (!(status = check_aliasing(centre, targets, names, 2)).ok()) return status;

  const SourceView source = used_depth(centre);
  Frame frames[2] = {detail::plan_frame(source, decoder, centre_to_left, options, wanted_outputs(left)),
                     detail::plan_frame(source, decoder, centre_to_right, options, wanted_outputs(right))};
  return run_frames(kernels_for(options), frames, 2, options, jobs) ? Status() : cancelled();
}

}  // namespace

namespace detail {

Status reproject_with(const KernelTable& kernels, const SourceView& source, const DepthDecoder& decoder,
                      const ParallaxModel& model, const Options& options, const TargetView& target) {
  return reproject_one(kernels, source, decoder, model, options, target, nullptr);
}

}  // namespace detail

Status reproject(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target) noexcept {
  Status status = check_options(options);
  if (!status.ok()) return status;
  return reproject_one(kernels_for(options), source, decoder, model, options, target, nullptr);
}

Status reproject(const SourceView& source, const DepthDecoder& decoder, const ParallaxModel& model,
                 const Options& options, const TargetView& target, const ParallelFor& jobs) noexcept {
  Status status = check_jobs(jobs);
  if (!status.ok()) return status;
  if (!(status = check_options(options)).ok()) return status;
  return reproject_one(kernels_for(options), source, decoder, model, options, target, &jobs);
}

Status reproject_pair(const SourceView& centre, const DepthDecoder& decoder, const ParallaxModel& centre_to_right,
                      const Options& options, const TargetView& left, const TargetView& right) noexcept {
  return reproject_two(centre, decoder, centre_to_right, options, left, right, nullptr);
}

Status reproject_pair(const SourceView& centre, const DepthDecoder& decoder, const ParallaxModel& centre_to_right,
                      const Options& options, const TargetView& left, const TargetView& right,
                      const ParallelFor& jobs) noexcept {
  const Status status = check_jobs(jobs);
  if (!status.ok()) return status;
  return reproject_two(centre, decoder, centre_to_right, options, left, right, &jobs);
}

}  // namespace reproject
