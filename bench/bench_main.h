// The main of a benchmark that prints a summary table after Google Benchmark's console report.
#pragma once

#include <cstring>

#include <benchmark/benchmark.h>

namespace planemap {

// Runs the registered benchmarks, then summary() if the report goes to the console: the table
// goes to stdout after the console report only (not into JSON or CSV output).
inline int RunBenchmarksThenSummary(int argc, char** argv, void (*summary)()) {
  bool console = true;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--benchmark_format=", 19) == 0 && std::strcmp(argv[i] + 19, "console") != 0) console = false;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  if (console) summary();
  benchmark::Shutdown();
  return 0;
}

}  // namespace planemap
