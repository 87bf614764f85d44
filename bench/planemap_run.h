#pragma once
// `planemap map SEQ --camera CAM --stride N --refine --out DIR` run as a subprocess, exactly as a
// user runs it, and its outputs read back: the three trajectories, tracking.csv and the time of
// the batch back end.
#include <optional>
#include <string>
#include <vector>

#include "planemap/core/tum_format.h"

namespace planemap {

// One row of tracking.csv.
struct TrackingLogRow {
  std::string status;        // tracked, degraded or lost
  double frontend_ms = 0.0;  // [ms]
  double tracking_ms = 0.0;  // [ms]
  double window_ms = 0.0;    // the sliding window's update [ms]
};

// Reads tracking.csv; throws InputError naming the file and line when a column is missing or a
// figure does not parse.
std::vector<TrackingLogRow> ReadTrackingLog(const std::string& file);

// The batch's solve time from the `refine: ..., 12 iterations, 0.412 s (...` line `planemap map
// --refine` prints [s]; nothing when there is no such line.
std::optional<double> RefineSeconds(const std::string& stdout_text);

struct PlanemapRun {
  int exit_code = 0;  // of the subprocess; -1 when it could not start
  std::string error;  // a failed run: what its stderr says went wrong
  std::vector<TrackingLogRow> log;
  Trajectory tracking;                   // trajectory.txt
  Trajectory smoothed;                   // trajectory_smoothed.txt (the sliding window, live)
  Trajectory refined;                    // trajectory_refined.txt; empty when the back end failed ...
  std::string refine_failure;            // ... and then what the tool said about it
  std::optional<double> refine_seconds;  // [s]
};

// Runs `binary map sequence --camera camera --stride stride --refine --out out_dir`, its stdout and
// stderr going to out_dir/stdout.txt and stderr.txt, and reads its outputs.
PlanemapRun RunPlanemapMap(const std::string& binary, const std::string& sequence, const std::string& camera,
                           int stride, const std::string& out_dir);

}  // namespace planemap
