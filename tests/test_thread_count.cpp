// Threads only when asked (docs/BEHAVIOUR.md "Memory", "Threads"): a process that calls only with
// Options::threads = 1 or through its own ParallelFor never starts a thread; a call that wants
// more starts the pool's; release_memory() joins them. Its own executable, because it counts
// every thread of the process (/proc/self/task on Linux, a Toolhelp snapshot on Windows).
#include <gtest/gtest.h>

#include <vector>

#include "reproject/reproject.hpp"

#if defined(__linux__)
#include <dirent.h>
#elif defined(_WIN32)
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include <tlhelp32.h>
#endif

namespace reproject {
namespace {

// Threads of this process now; -1 where the platform gives no count.
int threads_in_process() {
#if defined(__linux__)
  DIR* tasks = opendir("/proc/self/task");
  if (tasks == nullptr) return -1;
  int count = 0;
  while (const dirent* entry = readdir(tasks)) count += entry->d_name[0] != '.';
  closedir(tasks);
  return count;
#elif defined(_WIN32)
  const HANDLE snapshot = CreateToolhelp32Snapshot(TH32CS_SNAPTHREAD, 0);
  if (snapshot == INVALID_HANDLE_VALUE) return -1;
  THREADENTRY32 entry;
  entry.dwSize = sizeof entry;
  int count = 0;
  for (BOOL more = Thread32First(snapshot, &entry); more; more = Thread32Next(snapshot, &entry))
    count += entry.th32OwnerProcessID == GetCurrentProcessId();
  CloseHandle(snapshot);
  return count;
#else
  return -1;
#endif
}

void calling_thread_jobs(void*, int count, void (*task)(void*, int), void* task_context) {
  for (int i = 0; i < count; ++i) task(task_context, i);
}

Status call(int threads, bool pair, bool jobs, Method method) {
  const int width = 64, height = 32;
  std::vector<float> depth(static_cast<std::size_t>(width) * height, 0.5f), color(depth.size(), 0.25f);
  std::vector<float> out[2] = {std::vector<float>(depth.size()), std::vector<float>(depth.size())};
  for (int x = 0; x < width; x += 7) depth[static_cast<std::size_t>(x)] = 0.1f;
  SourceView source;
  source.depth = FloatPlane{depth.data(), width, height, width};
  source.color = ColorView::planar({FloatPlane{color.data(), width, height, width}});
  TargetView target[2];
  for (int e = 0; e < 2; ++e) target[e].color = MutableColorView::planar({MutableFloatPlane{out[e].data(), width, height, width}});
  Options options;
  options.threads = threads;
  options.method = method;
  const DepthDecoder decoder = DepthDecoder::from_near_far(DepthEncoding::standard, 1.0, 20.0);
  const ParallaxModel model = ParallaxModel::from_stereo(0.05, 3.0, width, EyeDirection::centre_to_right);
  const ParallelFor parallel{nullptr, calling_thread_jobs};
  if (pair) return jobs ? reproject_pair(source, decoder, model, options, target[0], target[1], parallel)
                        : reproject_pair(source, decoder, model, options, target[0], target[1]);
  return jobs ? reproject(source, decoder, model, options, target[0], parallel)
              : reproject(source, decoder, model, options, target[0]);
}

TEST(ThreadCount, ThreadsOnlyWhenAsked) {
  const int at_start = threads_in_process();
  if (at_start < 0) GTEST_SKIP() << "no way to count a process's threads on this platform";
  ASSERT_EQ(at_start, 1) << "the test process should start with its main thread alone";
  for (Method method : {Method::scanline, Method::march16, Method::single, Method::secant, Method::exact}) {
    for (bool pair : {false, true}) {
      ASSERT_TRUE(call(1, pair, false, method).ok());
      ASSERT_TRUE(call(0, pair, true, method).ok());  // a job system: threads is not read
      EXPECT_EQ(threads_in_process(), 1) << to_string(method) << (pair ? " pair" : "") << " started a thread";
    }
  }
  for (int round = 0; round < 2; ++round) {
    ASSERT_TRUE(call(2, false, false, Method::exact).ok());
    EXPECT_GE(threads_in_process(), 2) << "a call with threads = 2 started no pool thread";
    release_memory();
    EXPECT_EQ(threads_in_process(), 1) << "release_memory() left pool threads running";
    EXPECT_EQ(memory_in_use(), 0u);
  }
}

}  // namespace
}  // namespace reproject
