// The main of a benchmark that prints a summary table after Google Benchmark's console report.
#pragma once

#include <cstring>

#include <benchmark/benchmark.h>

namespace planemap {

// Whether the report goes to the console (no --benchmark_format other than console): a summary
// table goes to stdout after the console report only, not into JSON or CSV output.
inline bool ReportsToConsole(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--benchmark_format=", 19) == 0 && std::strcmp(argv[i] + 19, "console") != 0) return false;
  }
  return true;
}

// Runs the registered benchmarks, then summary() if the report goes to the console.
inline int RunBenchmarksThenSummary(int argc, char** argv, void (*summary)()) {
  const bool console = ReportsToConsole(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  if (console) summary();
  benchmark::Shutdown();
  return 0;
}

}  // namespace planemap
