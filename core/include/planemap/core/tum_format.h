#pragma once
// Text formats of the TUM RGB-D benchmark: file lists ("stamp path") and trajectories
// ("stamp tx ty tz qx qy qz qw"). Lines starting with '#' and blank lines are comments.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "planemap/core/pose.h"

namespace planemap {

struct StampedFile {
  double stamp = 0.0;  // [s]
  std::string path;    // relative to the sequence folder, e.g. "depth/1305031102.160407.png"
  int line = 0;        // line in the list file, for error messages
};

struct StampedPose {
  double stamp = 0.0;  // [s]
  Pose3 T_world_camera = Pose3::Identity();
};

using Trajectory = std::vector<StampedPose>;

// Reads rgb.txt / depth.txt. Throws InputError "<file>:<line>: ..." on a malformed line,
// a non-finite stamp or stamps that go backwards.
std::vector<StampedFile> ReadFileList(const std::string& file);
void WriteFileList(const std::string& file, const std::string& header,
                   const std::vector<StampedFile>& entries);

// Reads a TUM trajectory; the quaternion must have unit norm within 1e-3 (it is then normalised).
Trajectory ReadTumTrajectory(const std::string& file);
void WriteTumTrajectory(const std::string& file, const Trajectory& trajectory);

// One trajectory line "stamp tx ty tz qx qy qz qw" (stamp to the microsecond, pose to 1e-9).
std::string FormatTumPose(const StampedPose& pose);
// A stamp as TUM writes it in file names and lists: "%.6f".
std::string FormatStamp(double stamp);

// Pairs stamps of `a` and `b` like the TUM benchmark's associate.py: all pairs closer than
// `max_gap` [s], taken greedily by increasing gap, each stamp used at most once. Returns index pairs
// sorted by the index into `a`.
std::vector<std::pair<size_t, size_t>> AssociateStamps(const std::vector<double>& a,
                                                       const std::vector<double>& b, double max_gap);

// Pose at `stamp`, interpolated between the two poses around it (slerp), or the nearest pose when
// it is within `max_gap` [s]; nothing if the trajectory does not cover the stamp. `trajectory`
// must be sorted by stamp.
std::optional<Pose3> PoseAt(const Trajectory& trajectory, double stamp, double max_gap);

}  // namespace planemap
