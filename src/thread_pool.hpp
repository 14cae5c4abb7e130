// Internal: the library's persistent worker threads (Options::threads, DESIGN §6). Not installed.
//
// One pool per process, created on first use with one thread per hardware thread, the calling
// thread included (so hardware_threads() - 1 workers). A call hands the pool a *job*: `count`
// tasks on at most `max_threads` threads. The caller always works on its own job, so a job
// finishes even when every worker is busy elsewhere: several callers at once (or a caller inside
// another job) never deadlock, they just get fewer helpers. Idle workers sleep on a condition
// variable; nothing spins.
//
// A job lives on its caller's stack and the queue is an intrusive list, so running a job
// allocates nothing. The only allocations are the pool itself and its threads, on first use
// and when a call asks for more threads than the pool has (Options::threads > hardware threads
// grows it, up to kMaxThreads).
//
// The whole pool is in this header, included by src/bands.cpp only (the rows over threads): the
// library's source list (top-level CMakeLists.txt) needs no new entry. `inline` keeps a single pool per program
// even if another translation unit includes it.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <new>
#include <system_error>
#include <thread>
#include <vector>

namespace reproject {
namespace detail {

// Hardware threads, at least 1. Read once: the query can read files (and allocate) on Linux.
inline int hardware_threads() noexcept {
  static const int count = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return count;
}

class ThreadPool {
 public:
  // task(context, index, slot) for one index. `slot` names the thread running it within this
  // job: 0 is the calling thread, helpers get 1, 2, ... < max_threads in the order they join.
  // No two threads of one job share a slot, so per-slot scratch needs no locking.
  using Task = void (*)(void* context, int index, int slot);

  static constexpr int kMaxThreads = 256;  // a bound on Options::threads, caller included

  // The process's pool, created on first call; null only if it could not be allocated (callers
  // then run on their own thread).
  static ThreadPool* shared() noexcept;

  // Calls task(context, i, slot) once for every i in [0, count) on at most max_threads threads,
  // the calling thread included, and returns when all have returned. Indices are claimed one at
  // a time from a shared counter (dynamic balance; a task should be a band of rows, not a
  // pixel). Everything a task wrote happens-before the return.
  void run(int count, int max_threads, Task task, void* context) noexcept;

  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

 private:
  struct Job {
    Task task;
    void* context;
    int count;
    int helpers_wanted;
    std::atomic<int> next{0};  // next index to claim
    // Guarded by the pool's mutex:
    int helpers_joined = 0;
    int helpers_active = 0;  // joined and still working: the caller waits for 0
    Job* next_job = nullptr;
    std::condition_variable done;

    Job(Task t, void* c, int n, int helpers) : task(t), context(c), count(n), helpers_wanted(helpers) {}
    void work(int slot) noexcept {
      // Relaxed: the counter only hands out indices; the data a task reads and writes is
      // ordered by the mutex (job published under it, helpers leave under it).
      for (int i = next.fetch_add(1, std::memory_order_relaxed); i < count;
           i = next.fetch_add(1, std::memory_order_relaxed))
        task(context, i, slot);
    }
  };

  // Joins the workers at static destruction (see shared()).
  struct Reaper {
    ThreadPool* pool;
    ~Reaper() {
      if (pool != nullptr) pool->shutdown();
    }
  };

  ThreadPool() = default;
  void grow(int workers) noexcept;  // requires mutex_
  Job* find_job() const noexcept;   // requires mutex_
  void worker_loop() noexcept;
  void shutdown() noexcept;

  std::mutex mutex_;
  std::condition_variable work_;  // a job was queued, or shutdown
  Job* jobs_ = nullptr;           // jobs that may still take helpers, oldest first
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

inline ThreadPool* ThreadPool::shared() noexcept {
  // Created on first use (thread-safe static initialisation) and never deleted: a call made
  // during static destruction, after the reaper below has joined the workers, still finds a
  // valid mutex and simply runs on its own thread. The workers themselves are joined at exit,
  // so no thread is still running library code while the process tears down.
  static ThreadPool* const pool = [] {
    ThreadPool* created = new (std::nothrow) ThreadPool();
    if (created) {
      std::lock_guard<std::mutex> lock(created->mutex_);
      created->grow(hardware_threads() - 1);
    }
    return created;
  }();
  // Constructed after the pool, so destroyed before anything that was constructed earlier and
  // may still call in from its destructor (that call then runs on its own thread). Joining at
  // exit is safe here because a worker only ever waits on this pool's mutex and condition
  // variables. (A Windows DLL unloaded without exiting the process would have to leak the
  // workers instead: DllMain's loader lock forbids joining.)
  static const Reaper reaper{pool};
  (void)reaper;
  return pool;
}

inline void ThreadPool::grow(int workers) noexcept {
  workers = std::min(workers, kMaxThreads - 1);
  if (stopping_ || static_cast<int>(workers_.size()) >= workers) return;
  // Out of memory or out of threads: keep the workers we have; jobs need none to finish.
  try {
    workers_.reserve(static_cast<std::size_t>(workers));
    while (static_cast<int>(workers_.size()) < workers) workers_.emplace_back([this] { worker_loop(); });
  } catch (const std::bad_alloc&) {
  } catch (const std::system_error&) {
  }
}

inline ThreadPool::Job* ThreadPool::find_job() const noexcept {
  for (Job* job = jobs_; job != nullptr; job = job->next_job)
    if (job->helpers_joined < job->helpers_wanted && job->next.load(std::memory_order_relaxed) < job->count)
      return job;
  return nullptr;
}

inline void ThreadPool::worker_loop() noexcept {
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
  }
}

inline void ThreadPool::run(int count, int max_threads, Task task, void* context) noexcept {
  if (count <= 0) return;
  max_threads = std::min(max_threads, kMaxThreads);
  Job job(task, context, count, 0);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (max_threads > 1 && count > 1) grow(max_threads - 1);
    job.helpers_wanted = std::min({max_threads - 1, count - 1, static_cast<int>(workers_.size())});
    if (stopping_) job.helpers_wanted = 0;
    if (job.helpers_wanted > 0) {
      Job** tail = &jobs_;
      while (*tail != nullptr) tail = &(*tail)->next_job;
      *tail = &job;
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

inline void ThreadPool::shutdown() noexcept {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  work_.notify_all();
  // A worker inside a job finishes its claimed tasks first; the job's caller does the rest.
  for (std::thread& worker : workers_)
    if (worker.joinable() && worker.get_id() != std::this_thread::get_id()) worker.join();
}

}  // namespace detail
}  // namespace reproject
