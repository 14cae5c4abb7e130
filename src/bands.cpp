// A call's rows over threads (src/bands.hpp): bands of rows on the library's pool or the caller's
// job system, each with row scratch that outlives the call, checked for cancellation between
// blocks of rows.
#include "src/bands.hpp"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <new>

#include "kernels/memory.hpp"
#include "kernels/rows.hpp"
#include "src/memory.hpp"
#include "src/thread_pool.hpp"

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

// The scratch of one running call. Slot k serves the pool job's participant k (0: the caller), or
// any ParallelFor task that holds it. Sets outlive calls in the cache below, so that a call with
// the sizes of an earlier one allocates nothing, whichever thread makes it.
struct ScratchSet {
  ScratchSlot* slots[kMaxBands] = {};
  int count = 0;
  ScratchSet* next_free = nullptr;

  ScratchSet() noexcept = default;
  ~ScratchSet() {
    for (int k = 0; k < count; ++k) destroy(slots[k]);
  }
  ScratchSet(const ScratchSet&) = delete;
  ScratchSet& operator=(const ScratchSet&) = delete;

  // At least `wanted` slots, the first `prepared` of them sized for f's widths. False when out
  // of memory (what was made stays, for the next call).
  bool reserve(int wanted, int prepared, const Frame& f) noexcept {
    for (; count < wanted; ++count) {
      slots[count] = create<ScratchSlot>();
      if (slots[count] == nullptr) return false;
    }
    for (int k = 0; k < prepared; ++k) {
      if (!prepare_scratch(f, slots[k]->scratch)) return false;
    }
    return true;
  }
};

// The sets no running call holds, in static storage that is never destroyed. A call takes one
// (or makes one) and puts it back when it returns: as many sets as calls have ever run at once,
// on any threads, and release_cached_scratch() frees them all.
struct ScratchCache {
  std::mutex mutex;
  ScratchSet* free = nullptr;
};
ScratchCache& scratch_cache() noexcept {
  alignas(ScratchCache) static unsigned char storage[sizeof(ScratchCache)];
  static ScratchCache* const cache = new (storage) ScratchCache();
  return *cache;
}

// A set for the duration of a call (null when none could be made).
class ScratchSetLease {
 public:
  ScratchSetLease() noexcept {
    ScratchCache& cache = scratch_cache();
    {
      std::lock_guard<std::mutex> lock(cache.mutex);
      set_ = cache.free;
      if (set_ != nullptr) cache.free = set_->next_free;
    }
    if (set_ == nullptr) set_ = create<ScratchSet>();
  }
  ~ScratchSetLease() {
    if (set_ == nullptr) return;
    ScratchCache& cache = scratch_cache();
    std::lock_guard<std::mutex> lock(cache.mutex);
    set_->next_free = cache.free;
    cache.free = set_;
  }
  ScratchSetLease(const ScratchSetLease&) = delete;
  ScratchSetLease& operator=(const ScratchSetLease&) = delete;
  ScratchSet* set() const noexcept { return set_; }

 private:
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
  ScratchSlot* const* slots = nullptr;
  int slot_count = 0;
  const std::atomic<bool>* cancel = nullptr;  // Options::cancel
  std::atomic<bool>* stopped = nullptr;       // set by a band that left rows undone
  std::atomic<bool>* no_memory = nullptr;     // set by a task whose scratch could not be sized
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
      ScratchSlot* candidate = phase.slots[k];
      if (!candidate->busy.load(std::memory_order_relaxed) && !candidate->busy.exchange(true, std::memory_order_acquire))
        slot = candidate;
    }
  }
  // A no-op once sized. A slot beyond the prepared ones that cannot be sized leaves its band
  // undone, and the call returns out_of_memory.
  if (prepare_scratch(phase.frames[0], slot->scratch)) {
    run_band(phase, index, slot->scratch);
  } else {
    phase.no_memory->store(true, std::memory_order_relaxed);
  }
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

Status run_frames(const KernelTable& kernels, Frame* frames, int frame_count, const Options& options,
                  const ParallelFor* jobs) {
  const int height = frames[0].height;
  int threads = 1;
  int bands = 1;
  if (jobs != nullptr) {
    // The job system's width is unknown: size the bands for one thread per hardware thread.
    bands = std::min({height, hardware_threads() * kBandsPerThread, kMaxBands});
  } else {
    threads = options.threads > 0 ? std::min(options.threads, ThreadPool::kMaxThreads) : hardware_threads();
  }
  // The pool only for a call that wants more than one thread of it (it is made on first use).
  const PoolLease pool_lease(jobs == nullptr && threads > 1);
  ThreadPool* pool = pool_lease.pool();
  if (pool != nullptr) bands = std::min({height, threads * kBandsPerThread, kMaxBands});
  const int tasks = bands;

  ScratchSetLease lease;
  ScratchSet* set = lease.set();
  // Pool: one slot per participant (no more than there are tasks), all prepared. Job system: one
  // per task, the first few prepared (as many as a job system with a thread per hardware
  // thread, or 4, uses at once; a wider one sizes its extra slots on first use).
  const int slot_count = jobs != nullptr ? tasks : std::min(threads, tasks);
  const int prepared = jobs != nullptr ? std::min(tasks, std::max(hardware_threads(), 4)) : slot_count;
  if (set == nullptr || !set->reserve(slot_count, prepared, frames[0])) return out_of_memory("reproject", "row scratch");

  float nearest[kMaxBands];
  std::atomic<bool> stopped{false};
  std::atomic<bool> no_memory{false};
  RowPhase phase;
  phase.kernels = &kernels;
  phase.frames = frames;
  phase.pair = frame_count == 2;
  phase.bands = bands;
  phase.nearest = nearest;
  phase.slots = set->slots;
  phase.slot_count = slot_count;
  phase.cancel = options.cancel;
  phase.stopped = &stopped;
  phase.no_memory = &no_memory;
  // What stopped a phase, if anything: memory before cancellation (a band left undone for want of
  // scratch is not the caller's cancel).
  auto outcome = [&]() -> Status {
    if (no_memory.load(std::memory_order_relaxed)) return out_of_memory("reproject", "row scratch");
    if (stopped.load(std::memory_order_relaxed))
      return Status(StatusCode::cancelled, "the cancel flag (Options::cancel; options.cancel in C) was set while the "
                    "call ran: its outputs are unspecified");
    return Status();
  };
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
    if (Status status = outcome(); !status.ok()) return status;
    set_near_key(frames[frame_count - 1], last_key);
    if (frame_count == 2) {  // a mirrored pair's eyes share the key (kernels/frame.hpp)
      const float first_key = mirrored_eyes(frames[0], frames[1]) ? last_key : nearest_key_of(0);
      if (Status status = outcome(); !status.ok()) return status;
      set_near_key(frames[0], first_key);
    }
    phase.near_pass = false;
  }
  run_phase(phase, tasks, pool, slot_count, jobs);
  return outcome();
}

void release_cached_scratch() noexcept {
  ScratchCache& cache = scratch_cache();
  ScratchSet* sets = nullptr;
  {
    std::lock_guard<std::mutex> lock(cache.mutex);
    sets = cache.free;
    cache.free = nullptr;
  }
  while (sets != nullptr) {
    ScratchSet* next = sets->next_free;
    destroy(sets);
    sets = next;
  }
}

}  // namespace detail
}  // namespace reproject
