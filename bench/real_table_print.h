#pragma once
// The real-data table as text: fixed-width for the console, Markdown for the README and docs/real_data.md, CSV with
// every figure, and the summary against the best OpenCV peer.
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "real_table.h"

namespace planemap {

// One method on one sequence at one stride.
struct MethodRow {
  std::string method;    // "planemap tracking", "OpenCV RgbdOdometry", ...
  bool is_peer = false;  // an OpenCV method (the summary's best peer is one of these)
  std::string failure;   // non-empty: no figures; this is shown instead
  TrajectoryFigures figures;
  int lost = 0;                 // planemap: tracking.csv's lost frames; OpenCV: compute() failures
  std::optional<int> degraded;  // planemap's degraded frames; OpenCV has none
  double ms_per_frame = 0.0;    // median [ms]
  int frames = 0;               // frames used
};

// One sequence at one stride.
struct TableGroup {
  std::string sequence;            // its name under the data folder
  std::string camera;              // the camera file used, as printed
  int stride = 1;                  // 0: the sequence could not be opened (`skipped` says why)
  size_t sequence_frames = 0;      // associated colour/depth pairs in the sequence
  size_t strided_frames = 0;       // of them at this stride
  GroundTruthPairing groundtruth;  // how many strided frames have a ground-truth pose, and how
  double step = 0.0;               // median time between strided frames [s]
  RpeChoice rpe;
  std::string skipped;  // non-empty: not run, and why
  std::vector<MethodRow> rows;

  bool HasAte() const { return groundtruth.frames >= 3; }
  bool HasPair() const { return groundtruth.frames == 2; }
};

// The lines that say how every figure is defined.
std::vector<std::string> TableHeaderLines(const std::string& data_dir, double max_time_gap);

void PrintTextTable(const std::vector<TableGroup>& groups, std::FILE* out);
void PrintMarkdownTable(const std::vector<TableGroup>& groups, std::FILE* out);
// Per sequence and stride: the best OpenCV peer's error, planemap tracking's, their ratio, and
// refine against tracking [mm].
void PrintSummary(const std::vector<TableGroup>& groups, bool markdown, std::FILE* out);
// One line per figure: sequence,stride,method,metric,value,unit. Throws InputError naming `file`
// when it cannot be written.
void WriteTableCsv(const std::vector<TableGroup>& groups, const std::string& file);

}  // namespace planemap
