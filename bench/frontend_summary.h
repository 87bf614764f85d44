#pragma once
// bench_frontend's summary: one table after Google Benchmark's console report, a row per method
// or stage, a column per frame set. Benchmarks are named "Method/set".
#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

namespace planemap {

// What the table's notes say about a frame set.
struct FrameSetNote {
  std::string name;
  std::string what;  // where its frames come from and how recall is had
};

class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  explicit SummaryReporter(std::vector<FrameSetNote> sets) : sets_(std::move(sets)) {}

  // Keeps each benchmark's time and counters: with --benchmark_repetitions, its median.
  void ReportRuns(const std::vector<Run>& runs) override;

  // The table of what ran (--benchmark_filter may leave methods or sets out), then its notes.
  void PrintSummary() const;

 private:
  struct Figures {
    double ms = 0.0;
    std::map<std::string, double> counters;
  };
  const Figures* Find(const std::string& method, const std::string& set) const;
  std::string Cell(const std::string& method, const std::string& set, const std::string& counter) const;

  std::vector<FrameSetNote> sets_;
  std::map<std::string, std::map<std::string, Figures>> figures_;  // by method, then set
};

}  // namespace planemap
