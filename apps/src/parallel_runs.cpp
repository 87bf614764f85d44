#include "parallel_runs.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <exception>
#include <mutex>

#include <omp.h>

#include "planemap/core/error.h"

namespace planemap {
namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void OnInterrupt(int) {
  g_interrupted = true;
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process at once
}

}  // namespace

ParallelRuns RunInParallel(size_t count, int threads, size_t resumed, size_t total, std::ofstream& append,
                           const std::function<std::string(size_t)>& run, const std::function<std::string(size_t)>& name) {
  g_interrupted = false;
  auto previous = std::signal(SIGINT, OnInterrupt);
  std::mutex mutex;
  std::string failure;
  ParallelRuns result;
  const double start = omp_get_wtime();
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (size_t i = 0; i < count; ++i) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (g_interrupted || !failure.empty()) continue;
    }
    omp_set_num_threads(1);
    std::string text;
    try {
      text = run(i);
    } catch (const std::exception& e) {
      std::lock_guard<std::mutex> lock(mutex);
      if (failure.empty()) failure = name(i) + ": " + e.what();
      continue;
    }
    std::lock_guard<std::mutex> lock(mutex);
    append << text << std::flush;
    ++result.done;
    const double elapsed = omp_get_wtime() - start;
    std::fprintf(stderr, "\r  %zu/%zu runs, %.0f s, about %.0f s to go   ", resumed + result.done, total, elapsed,
                 elapsed / result.done * (count - result.done));
  }
  std::signal(SIGINT, previous);
  std::fprintf(stderr, "\n");
  if (!failure.empty()) throw InputError(failure);
  result.interrupted = g_interrupted;
  return result;
}

}  // namespace planemap
