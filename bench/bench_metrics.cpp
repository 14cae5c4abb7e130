// reproject_bench_metrics: the image-quality metrics (include/reproject/metrics.hpp) on one
// 1920x1080 RGB frame, float32 and uint8, interleaved as an engine or NumPy holds it. One thread:
// the metrics do not split work. docs/QUALITY.md quotes these.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <vector>

#include "reproject/metrics.hpp"

namespace {

constexpr int kWidth = 1920, kHeight = 1080, kChannels = 3;

// A frame and a noisy copy of it, as values 0..1 (float) or 0..255 (bytes).
template <class T>
struct Frames {
  std::vector<T> a, b;
  Frames() : a(static_cast<std::size_t>(kWidth) * kHeight * kChannels), b(a.size()) {
    std::mt19937 random(22);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const float scale = sizeof(T) == 1 ? 255.0f : 1.0f;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const float v = unit(random);
      a[i] = static_cast<T>(v * scale);
      b[i] = static_cast<T>((0.9f * v + 0.1f * unit(random)) * scale);
    }
  }
  reproject::SampleView<T> view(const std::vector<T>& v) const {
    return reproject::SampleView<T>::interleaved(v.data(), kWidth, kHeight, kChannels, kWidth * kChannels);
  }
};

template <class T, bool kSsim>
void bm_metric(benchmark::State& state) {
  static const Frames<T> frames;
  const reproject::SampleView<T> a = frames.view(frames.a), b = frames.view(frames.b);
  double value = 0.0;
  for (auto _ : state) {
    const reproject::Status status = kSsim ? reproject::ssim(a, b, {}, &value) : reproject::psnr(a, b, {}, &value);
    if (!status) {
      state.SkipWithError(status.message());
      break;
    }
    benchmark::DoNotOptimize(value);
  }
  state.counters["Mpix/s"] = benchmark::Counter(static_cast<double>(kWidth) * kHeight * state.iterations(),
                                                benchmark::Counter::kIsRate, benchmark::Counter::kIs1000);
}

BENCHMARK(bm_metric<float, true>)->Name("ssim/float32/1920x1080x3")->Unit(benchmark::kMillisecond);
BENCHMARK(bm_metric<std::uint8_t, true>)->Name("ssim/uint8/1920x1080x3")->Unit(benchmark::kMillisecond);
BENCHMARK(bm_metric<float, false>)->Name("psnr/float32/1920x1080x3")->Unit(benchmark::kMillisecond);
BENCHMARK(bm_metric<std::uint8_t, false>)->Name("psnr/uint8/1920x1080x3")->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
