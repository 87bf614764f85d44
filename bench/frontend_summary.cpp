#include "frontend_summary.h"

#include <algorithm>
#include <cstdio>
#include <iterator>

namespace planemap {
namespace {

// A row: a method's time (with its recall where the set has labels), a counter of a method, or a
// heading (no method), printed when a row under it is.
struct Row {
  const char* label;
  const char* method;
  const char* counter;  // nullptr: the time
};

constexpr Row kRows[] = {
    {"whole frontend (depth to objects)", "Frontend", nullptr},
    {"  without occlusion inferences", "FrontendNoOcclusionInference", nullptr},
    {"  without thin strips", "FrontendNoStrips", nullptr},
    {"  without the planes' fringes", "FrontendNoFringes", nullptr},
    {"stages, each timed alone:", nullptr, nullptr},
    {"  depth to cloud", "Cloud", nullptr},
    {"  planes (ours, organized)", "Organized", nullptr},
    {"  floor/walls, intersections", "StageIntersections", nullptr},
    {"  graph, objects, sizes, classes", "StageObjects", nullptr},
    {"    of which faces in pieces", "StageFaces", nullptr},
    {"plane segmentation (recall):", nullptr, nullptr},
    {"  ours, organized", "Organized", "recall"},
    {"  ours without thin strips", "OrganizedNoStrips", "recall"},
    {"  PCL OrganizedMultiPlane", "PclOrganizedMultiPlane", "recall"},
    {"  OpenCV RgbdPlane", "OpenCvRgbdPlane", "recall"},
    {"  PCL SAC_MSAC", "PclSacMsac", "recall"},
    {"", nullptr, nullptr},  // the counts: a heading that prints nothing
    {"planes per frame, ours (median)", "Organized", "planes_per_frame"},
    {"objects per frame, frontend", "Frontend", "objects_per_frame"},
    {"labelled surfaces, all frames", "Organized", "surfaces"},
};
constexpr int kLabelWidth = 34;

// Wide enough for the set's name and "1234.56 (0.978)".
int ColumnWidth(const FrameSetNote& set) {
  return static_cast<int>(std::max<size_t>(set.name.size(), 15) + 2);
}

std::string Format(const char* format, double value) {
  char text[32];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

}  // namespace

void SummaryReporter::ReportRuns(const std::vector<Run>& runs) {
  ConsoleReporter::ReportRuns(runs);
  for (const Run& run : runs) {
    // With --benchmark_repetitions, the table shows each benchmark's median (the repetitions and
    // the other aggregates are in the report above).
    if (run.run_type == Run::RT_Aggregate && run.aggregate_name != "median") continue;
    if (run.run_type == Run::RT_Iteration && run.repetitions > 1) continue;
    const std::string& name = run.run_name.function_name;
    const size_t slash = name.find('/');
    if (slash == std::string::npos) continue;
    Figures& f = figures_[name.substr(0, slash)][name.substr(slash + 1)];
    f.ms = run.GetAdjustedRealTime();
    for (const auto& [counter, value] : run.counters) f.counters[counter] = value.value;
  }
}

const SummaryReporter::Figures* SummaryReporter::Find(const std::string& method,
                                                      const std::string& set) const {
  const auto by_method = figures_.find(method);
  if (by_method == figures_.end()) return nullptr;
  const auto by_set = by_method->second.find(set);
  return by_set == by_method->second.end() ? nullptr : &by_set->second;
}

// "ms", "ms (recall)" for a segmenter on a labelled set, a counter's value, or "-" (not run).
std::string SummaryReporter::Cell(const std::string& method, const std::string& set,
                                  const std::string& counter) const {
  const Figures* f = Find(method, set);
  if (f == nullptr) return "-";
  if (counter.empty()) return Format("%.2f", f->ms);
  if (counter == "recall") {
    const auto recall = f->counters.find("recall");
    return Format("%.2f", f->ms) + (recall == f->counters.end() ? "" : Format(" (%.3f)", recall->second));
  }
  const auto value = f->counters.find(counter);
  if (value == f->counters.end()) return "-";
  return Format(counter == "surfaces"           ? "%.0f"
                : counter == "planes_per_frame" ? "%.1f"
                                                : "%.2f",
                value->second);
}

void SummaryReporter::PrintSummary() const {
  std::vector<const FrameSetNote*> columns;  // the sets that ran
  for (const FrameSetNote& set : sets_) {
    const bool ran = std::any_of(figures_.begin(), figures_.end(),
                                 [&](const auto& m) { return m.second.count(set.name) > 0; });
    if (ran) columns.push_back(&set);
  }
  if (columns.empty()) return;
  std::printf("\nThe frontend and plane segmentation on 640x480 frames, one thread: ms/frame (recall)\n");
  std::printf("%-*s", kLabelWidth, "");
  for (const FrameSetNote* set : columns) std::printf("%*s", ColumnWidth(*set), set->name.c_str());
  std::printf("\n");
  for (const Row* row = std::begin(kRows); row != std::end(kRows); ++row) {
    if (row->method == nullptr) {  // a heading, when some row under it ran
      const Row* next = row + 1;
      while (next != std::end(kRows) && next->method != nullptr && !figures_.count(next->method)) ++next;
      if (next != std::end(kRows) && next->method != nullptr && *row->label != '\0')
        std::printf("%s\n", row->label);
      continue;
    }
    if (!figures_.count(row->method)) continue;
    std::printf("%-*s", kLabelWidth, row->label);
    for (const FrameSetNote* set : columns) {
      std::printf("%*s", ColumnWidth(*set),
                  Cell(row->method, set->name, row->counter ? row->counter : "").c_str());
    }
    std::printf("\n");
  }
  std::printf(
      "Recall: labelled surfaces (1000 valid px or more; the last row counts them) matched by a plane with\n"
      "IoU >= 0.5, where the set has labels. Cells \"-\": not run (PCL SAC_MSAC takes over a second a "
      "frame).\n");
  for (const FrameSetNote* set : columns) std::printf("  %s: %s\n", set->name.c_str(), set->what.c_str());
}

}  // namespace planemap
