#pragma once
// The peers of the real-data table: OpenCV's four RGB-D odometry methods (contrib rgbd module),
// each with its default parameters, run frame to frame over the frames planemap map uses.
#include <string>
#include <vector>

#include "planemap/core/pose.h"
#include "planemap/core/tum_format.h"
#include "planemap/io/tum_sequence.h"

namespace planemap {

// cv::rgbd class names: "ICPOdometry", "RgbdOdometry", "RgbdICPOdometry", "FastICPOdometry".
const std::vector<std::string>& OpenCvOdometryMethods();

struct OdometryRun {
  Trajectory trajectory;        // T_world_camera of every frame read, starting at T_world_first
  int frames = 0;               // frames read
  int failures = 0;             // compute() returned false: the previous pose was kept
  int unreadable = 0;           // frames the sequence could not load (named on stderr)
  std::vector<double> step_ms;  // prepareFrameCache + compute, per frame after the first [ms]
  std::string error;            // non-empty: OpenCV threw; the run stopped there
};

// Runs `method` over `frames` of `sequence` (indices), frame to frame: gray image and depth in
// metres as TumSequence::LoadFrame reads them, the sequence's camera. The first frame read gets
// T_world_first. A frame that fails to load is skipped like planemap map skips it.
OdometryRun RunOpenCvOdometry(const std::string& method, const TumSequence& sequence,
                              const std::vector<size_t>& frames, const Pose3& T_world_first);

}  // namespace planemap
