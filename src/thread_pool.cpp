// The library's worker threads (src/thread_pool.hpp).
#include "src/thread_pool.hpp"

#include <algorithm>
#include <new>
#include <thread>

#include "kernels/memory.hpp"

#if defined(__x86_64__) || defined(__i386__) || defined(_M_X64) || defined(_M_IX86)
#include <immintrin.h>
#define REPROJECT_SPIN_PAUSE() _mm_pause()
#elif (defined(__aarch64__) || defined(__arm__)) && (defined(__GNUC__) || defined(__clang__))
#define REPROJECT_SPIN_PAUSE() __asm__ __volatile__("yield")
#else
#define REPROJECT_SPIN_PAUSE() ((void)0)
#endif

namespace reproject {
namespace detail {

int hardware_threads() noexcept {
  static const int count = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return count;
}

namespace {

// Spins (a pause per test, to spare the other hardware thread of a core) while keep_waiting()
// holds, for at most `limit`.
template <class Condition>
void spin_while(std::chrono::microseconds limit, const Condition& keep_waiting) noexcept {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (keep_waiting() && std::chrono::steady_clock::now() < until) REPROJECT_SPIN_PAUSE();
}

}  // namespace

void ThreadPool::Job::work(int slot) noexcept {
  // Relaxed: the counter only hands out indices; the data a task reads and writes is ordered by
  // the mutex (job published under it, helpers leave under it).
  for (int i = next.fetch_add(1, std::memory_order_relaxed); i < count; i = next.fetch_add(1, std::memory_order_relaxed))
    task(context, i, slot);
}

void ThreadPool::grow(int workers) noexcept {
  std::lock_guard<std::mutex> lock(mutex_);
  workers = std::min(workers, kMaxThreads - 1);
  // A thread the OS refuses is simply not there: jobs need none to finish.
  while (!stopping_ && worker_count_ < workers && workers_[worker_count_].start(&ThreadPool::worker_entry, this))
    ++worker_count_;
}

ThreadPool::Job* ThreadPool::find_job() const noexcept {
  for (Job* job = jobs_; job != nullptr; job = job->next_job)
    if (job->helpers_joined < job->helpers_wanted && job->next.load(std::memory_order_relaxed) < job->count) return job;
  return nullptr;
}

void ThreadPool::worker_entry(void* pool) noexcept { static_cast<ThreadPool*>(pool)->worker_loop(); }

void ThreadPool::worker_loop() noexcept {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    Job* job = nullptr;
    work_.wait(lock, [&] { return stopping_ || (job = find_job()) != nullptr; });
    if (stopping_) return;  // a job in progress is finished by its caller
    const int slot = ++job->helpers_joined;
    ++job->helpers_active;
    lock.unlock();
    job->work(slot);
    lock.lock();
    // Notified under the lock: once the caller sees 0 it returns and the job is gone.
    if (--job->helpers_active == 0) job->done.notify_one();
    // With no job waiting, the next one, if it comes soon, without a wake-up (thread_pool.hpp).
    // The loop's wait looks at the queue before it sleeps, so a job queued meanwhile is not missed.
    if (!stopping_ && find_job() == nullptr) {
      const unsigned seen = queued_.load(std::memory_order_relaxed);
      lock.unlock();
      spin_while(kWorkerSpin, [&] { return queued_.load(std::memory_order_relaxed) == seen; });
      lock.lock();
    }
  }
}

void ThreadPool::run(int count, int max_threads, Task task, void* context) noexcept {
  if (count <= 0) return;
  max_threads = std::min(max_threads, kMaxThreads);
  if (max_threads > 1 && count > 1) grow(max_threads - 1);
  Job job(task, context, count, 0);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job.helpers_wanted = stopping_ ? 0 : std::min({max_threads - 1, count - 1, worker_count_});
    if (job.helpers_wanted > 0) {
      Job** tail = &jobs_;
      while (*tail != nullptr) tail = &(*tail)->next_job;
      *tail = &job;
      queued_.fetch_add(1, std::memory_order_relaxed);
    }
  }
  if (job.helpers_wanted == 0) {
    job.work(0);
    return;
  }
  // Wakes as many sleepers as there are helper places; busy workers look at the queue anyway
  // before they sleep again.
  for (int i = 0; i < job.helpers_wanted; ++i) work_.notify_one();
  job.work(0);
  // Every index is claimed: the helpers' last tasks end soon, and a sleeping caller would wake
  // late (thread_pool.hpp).
  spin_while(kCallerSpin, [&] { return job.helpers_active.load(std::memory_order_relaxed) != 0; });

  std::unique_lock<std::mutex> lock(mutex_);
  // Every index is claimed: take the job off the queue so no helper joins late, then wait for
  // the helpers still running a task.
  for (Job** link = &jobs_; *link != nullptr; link = &(*link)->next_job) {
    if (*link == &job) {
      *link = job.next_job;
      break;
    }
  }
  job.done.wait(lock, [&] { return job.helpers_active == 0; });
}

void ThreadPool::stop() noexcept {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    queued_.fetch_add(1, std::memory_order_relaxed);
  }
  work_.notify_all();
  // A worker inside a job finishes its claimed tasks first; the job's caller does the rest.
  for (int i = 0; i < worker_count_; ++i) workers_[i].join();
  worker_count_ = 0;
}

namespace {

// Who holds the pool. In static storage that is never destroyed (no destructor runs at exit), so
// a call made during static destruction still finds a valid mutex and runs on its own thread.
struct PoolHolder {
  std::mutex mutex;
  ThreadPool* pool = nullptr;
  int leases = 0;
  bool exiting = false;
};
PoolHolder& holder() noexcept {
  alignas(PoolHolder) static unsigned char storage[sizeof(PoolHolder)];
  static PoolHolder* const h = new (storage) PoolHolder();
  return *h;
}

// Joins the workers at exit (a worker must not run library code while the process tears down).
// Safe because a worker only ever waits on its pool's mutex and condition variables. (A Windows
// DLL unloaded without exiting the process would have to leak the workers instead: DllMain's
// loader lock forbids joining.)
// Its memory is kept (the host's allocator may be gone by then; release_memory() frees it).
struct Reaper {
  ~Reaper() {
    PoolHolder& h = holder();
    std::lock_guard<std::mutex> lock(h.mutex);
    h.exiting = true;
    if (h.pool != nullptr && h.leases == 0) h.pool->stop();
  }
};

}  // namespace

PoolLease::PoolLease(bool wanted) noexcept : pool_(nullptr) {
  if (!wanted) return;
  static const Reaper reaper;  // registered on first use, so destroyed before earlier statics
  (void)reaper;
  PoolHolder& h = holder();
  std::lock_guard<std::mutex> lock(h.mutex);
  if (h.pool == nullptr && !h.exiting) {
    h.pool = create<ThreadPool>();
    if (h.pool != nullptr) h.pool->grow(hardware_threads() - 1);
  }
  pool_ = h.pool;
  if (pool_ != nullptr) ++h.leases;
}

PoolLease::~PoolLease() {
  if (pool_ == nullptr) return;
  PoolHolder& h = holder();
  std::lock_guard<std::mutex> lock(h.mutex);
  --h.leases;
}

void release_thread_pool() noexcept {
  PoolHolder& h = holder();
  std::lock_guard<std::mutex> lock(h.mutex);
  if (h.pool == nullptr || h.leases != 0) return;
  destroy(h.pool);  // its destructor joins the workers
  h.pool = nullptr;
}

}  // namespace detail
}  // namespace reproject
