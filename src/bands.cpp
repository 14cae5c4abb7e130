// A call's rows over threads (src/bands.hpp): bands of rows on the library's pool or the caller's
// job system, each with row scratch that outlives the call, checked for cancellation between
// blocks of rows.
#include "src/bands.hpp"

#include <algorithm>
#include <atomic>
#include <memory>
#include <new>
#include <vector>

#include "kernels/rows.hpp"
#include "src/thread_pool.hpp"

#if defined(_WIN32)
#ifndef NOMINMAX
#define NOMINMAX  // no min and max macros (std::max below)
#endif
#include <windows.h>  // FlsAlloc; after the other headers, whose names its near and far macros would hit
#endif

namespace reproject {
namespace detail {
namespace {

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
    for (int k = 0; k < prepared; ++k) prepare_scratch(f, slots[static_cast<std::size_t>(k)]->scratch);
  }
};

// The calling thread's set, freed when the thread ends; null if the system gives none.
#if defined(_WIN32)
// Windows: held in a fiber-local slot, whose callback frees it when the thread ends. Not a
// thread_local with a destructor: MinGW-w64's GCC emulates thread_local storage and frees that
// storage before such destructors run, which then read and free freed memory at every thread
// exit (docs/ARCHITECTURE.md, "Windows": found by ThreadsHardening under Wine).
void WINAPI free_scratch_set(void* set) { delete static_cast<ScratchSet*>(set); }

ScratchSet* thread_scratch_set() noexcept {
  static const DWORD slot = FlsAlloc(free_scratch_set);
  if (slot == FLS_OUT_OF_INDEXES) return nullptr;
  auto* set = static_cast<ScratchSet*>(FlsGetValue(slot));
  if (set == nullptr) {
    set = new (std::nothrow) ScratchSet;
    if (set != nullptr && !FlsSetValue(slot, set)) {
      delete set;
      set = nullptr;
    }
  }
  return set;
}
#else
ScratchSet* thread_scratch_set() noexcept {
  thread_local ScratchSet set;
  return &set;
}
#endif

// The calling thread's set, or a fresh one when a call is made from inside another on the same
// thread (a job system that runs other work while it waits): that call allocates its scratch.
class ScratchSetLease {
 public:
  ScratchSetLease() {
    ScratchSet* reused = thread_scratch_set();
    set_ = reused == nullptr || reused->in_use ? &fresh_ : reused;
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
      nearest = std::max(nearest, nearest_key_in_rows(f, *phase.kernels, y, stop));
    else if (phase.pair)
      run_pair_rows(phase.frames[0], phase.frames[1], *phase.kernels, scratch, y, stop);
    else
      run_rows(f, *phase.kernels, scratch, y, stop);
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
  prepare_scratch(phase.frames[0], slot->scratch);  // a no-op once sized
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

}  // namespace

bool run_frames(const KernelTable& kernels, Frame* frames, int frame_count, const Options& options,
                const ParallelFor* jobs) {
  const int height = frames[0].height;
  int threads = 1;
  int bands = 1;
  ThreadPool* pool = nullptr;
  if (jobs != nullptr) {
    // The job system's width is unknown: size the bands for one thread per hardware thread.
    bands = std::min({height, hardware_threads() * kBandsPerThread, kMaxBands});
  } else {
    threads = options.threads > 0 ? std::min(options.threads, ThreadPool::kMaxThreads) : hardware_threads();
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
  const int prepared = jobs != nullptr ? std::min(tasks, std::max(hardware_threads(), 4)) : slot_count;
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
  if (near_pass_needed(frames[0])) {
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
    set_near_key(frames[frame_count - 1], last_key);
    if (frame_count == 2) {  // a mirrored pair's eyes share the key (kernels/frame.hpp)
      const float first_key = mirrored_eyes(frames[0], frames[1]) ? last_key : nearest_key_of(0);
      if (stopped.load(std::memory_order_relaxed)) return false;
      set_near_key(frames[0], first_key);
    }
    phase.near_pass = false;
  }
  run_phase(phase, tasks, pool, slot_count, jobs);
  return !stopped.load(std::memory_order_relaxed);
}

}  // namespace detail
}  // namespace reproject
