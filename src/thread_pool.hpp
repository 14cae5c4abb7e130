// Internal: the library's persistent worker threads (Options::threads, DESIGN §6). Not installed.
//
// One pool per process, created by the first call that wants more than one thread, with one
// thread per hardware thread, the calling thread included (so hardware_threads() - 1 workers). A
// call hands the pool a *job*: `count` tasks on at most `max_threads` threads. The caller always
// works on its own job, so a job finishes even when every worker is busy elsewhere: several
// callers at once (or a caller inside another job) never deadlock, they just get fewer helpers.
// Idle workers sleep on a condition variable. Two short waits spin first, because waking a
// sleeping thread costs tens of microseconds (bench/design_measurements.md: about 30 us per
// two-thread call on a 2-core Xeon VM): a caller whose own tasks are done spins up
// to kCallerSpin for its helpers' last tasks, and a worker whose job is done spins up to
// kWorkerSpin for the next job (back-to-back calls: the views of a frame, the benchmarks), as
// OpenMP runtimes do. Then both sleep; a worker never spins longer than kWorkerSpin per job.
//
// A job lives on its caller's stack and the queue is an intrusive list, so running a job takes no
// memory. The pool itself comes from the library's allocator (kernels/memory.hpp) and its threads
// from the operating system (src/os_thread.hpp); a pool that cannot be made, or a thread that
// cannot be started, means fewer threads, never an error: the output does not depend on them.
// A call that wants one thread, or runs on the caller's ParallelFor, never makes the pool.
// release_thread_pool() (reproject::release_memory) joins the workers and frees the pool.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

#include "src/os_thread.hpp"

namespace reproject {
namespace detail {

// Hardware threads, at least 1. Read once: the query can read files (and allocate) on Linux.
int hardware_threads() noexcept;

class ThreadPool {
 public:
  // task(context, index, slot) for one index. `slot` names the thread running it within this
  // job: 0 is the calling thread, helpers get 1, 2, ... < max_threads in the order they join.
  // No two threads of one job share a slot, so per-slot scratch needs no locking.
  using Task = void (*)(void* context, int index, int slot);

  static constexpr int kMaxThreads = 256;  // a bound on Options::threads, caller included
  static constexpr std::chrono::microseconds kCallerSpin{200};
  static constexpr std::chrono::microseconds kWorkerSpin{50};

  ThreadPool() noexcept = default;
  ~ThreadPool() { stop(); }
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  // Calls task(context, i, slot) once for every i in [0, count) on at most max_threads threads,
  // the calling thread included, and returns when all have returned. Indices are claimed one at
  // a time from a shared counter (dynamic balance; a task should be a band of rows, not a
  // pixel). Everything a task wrote happens-before the return.
  void run(int count, int max_threads, Task task, void* context) noexcept;

  // Starts workers up to `workers` (fewer if the OS refuses some).
  void grow(int workers) noexcept;
  // Stops and joins the workers (the destructor does it too); later jobs run on their callers.
  void stop() noexcept;

 private:
  struct Job {
    Task task;
    void* context;
    int count;
    int helpers_wanted;
    std::atomic<int> next{0};  // next index to claim
    // Guarded by the pool's mutex:
    int helpers_joined = 0;
    // Joined and still working: the caller waits for 0. Changed under the lock; atomic so that
    // the caller's spin may read it without (its return is still decided under the lock).
    std::atomic<int> helpers_active{0};
    Job* next_job = nullptr;
    std::condition_variable done;

    Job(Task t, void* c, int n, int helpers) : task(t), context(c), count(n), helpers_wanted(helpers) {}
    void work(int slot) noexcept;
  };

  Job* find_job() const noexcept;  // requires mutex_
  static void worker_entry(void* pool) noexcept;
  void worker_loop() noexcept;

  std::mutex mutex_;
  std::condition_variable work_;  // a job was queued, or shutdown
  Job* jobs_ = nullptr;           // jobs that may still take helpers, oldest first
  bool stopping_ = false;
  std::atomic<unsigned> queued_{0};  // jobs queued and stops so far: what a spinning worker watches
  int worker_count_ = 0;
  OsThread workers_[kMaxThreads - 1];
};

// The process's pool for one call's duration, if `wanted`: made (with its workers) by the first
// lease that wants it; null when not wanted or when it could not be allocated (the call then
// runs on its own thread). While a lease is held the pool is not released.
class PoolLease {
 public:
  explicit PoolLease(bool wanted) noexcept;
  ~PoolLease();
  PoolLease(const PoolLease&) = delete;
  PoolLease& operator=(const PoolLease&) = delete;
  ThreadPool* pool() const noexcept { return pool_; }

 private:
  ThreadPool* pool_;
};

// Joins the pool's workers and gives its memory back, unless a call holds it (then it stays).
void release_thread_pool() noexcept;

}  // namespace detail
}  // namespace reproject
