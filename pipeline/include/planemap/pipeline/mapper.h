#pragma once
// The live pipeline as one library call (DESIGN.md, pipeline/): an RGB-D frame in; its model, the
// tracked pose, the sliding window's smoothed pose, the tracking status and the growing map out.
// `planemap map`, `approach`, `study` and `nees`, the Python module and a robot's own loop all
// run frames through it:
//
//   Mapper mapper(camera, LoadMapperConfig("configs/default.yaml"), LoadPatterns("configs/patterns.yaml"));
//   for (const RgbdFrame& frame : frames) {
//     const MapperStep step = mapper.Add(frame);   // step.track.status, step.T_world_camera_smoothed
//   }
//   const FinalMap result = mapper.Finish(/*refine=*/true);   // result.map, result.refined_poses
//
// A frame's two stages can run on two threads: Perceive (cloud and frontend) depends on no pose and
// is const, so frame k + 1 may be perceived while frame k is tracked; Track takes frames in order.
#include <optional>
#include <string>
#include <vector>

#include "planemap/backend/backend.h"
#include "planemap/backend/backend_config.h"
#include "planemap/core/frame_model.h"
#include "planemap/core/intrinsics.h"
#include "planemap/core/plane_map.h"
#include "planemap/core/pose.h"
#include "planemap/frontend/frontend.h"
#include "planemap/frontend/map_merge.h"
#include "planemap/frontend/objects.h"
#include "planemap/frontend/organized_cloud.h"
#include "planemap/frontend/tracker.h"

namespace planemap {

// The settings of the pipeline's stages, under the same keys as in configs/default.yaml.
struct MapperConfig {
  FrontendConfig frontend;  // cloud, segmentation, edges, objects
  TrackingConfig tracking;  // association, pose, map update
  BackendConfig backend;    // sliding window and batch refinement
  MapMergeConfig merge;     // duplicate surfaces and objects fused in the final map

  template <class V>
  void VisitFields(V&& v) {
    v("frontend", frontend);
    v("tracking", tracking);
    v("backend", backend);
    v("merge", merge);
  }
};

// Reads the pipeline's sections (frontend, tracking, backend, merge) of a planemap config file;
// its other sections (render, humanoid, ...) belong to other tools and are left alone. Keys left
// out keep their defaults. Throws InputError naming the file, line and key of a bad setting.
MapperConfig LoadMapperConfig(const std::string& file);

// Stage 1 of a frame: what the camera saw, before any pose.
struct Perception {
  Cloud::Ptr cloud;          // the organized cloud (the model's planes index into it)
  FrameModel model;          // planes, edges, corners, objects in the camera frame
  double frontend_ms = 0.0;  // cloud and frontend [ms]
};

// Stage 2 of a frame: where the camera was.
struct MapperStep {
  TrackResult track;                // status, tracked T_world_camera, counts, reason
  Pose3 T_world_camera_smoothed;    // the sliding window's estimate (tracking's without smoothing)
  double tracking_ms = 0.0;         // [ms]
  double window_ms = 0.0;           // [ms]; 0 without smoothing
};

// The map a user keeps at the end of a run.
struct FinalMap {
  PlaneMap map;                      // refined when asked and the solve was usable; duplicates fused
  bool refine_asked = false;
  SolveReport refine;                // the batch back end's report, when asked
  std::vector<Pose3> refined_poses;  // per frame of Mapper::observations(), when refined and usable
  std::string covariance_error;      // why the uncertainties are missing; empty when computed
  int fused_planes = 0;              // surfaces the tracker added twice, folded into one
  int fused_objects = 0;             // objects mapped twice, folded into one
};

class Mapper {
 public:
  // `T_world_first` is the first frame's camera pose (the identity: the first camera frame is the
  // world; a ground-truth or known start pose puts the map in that world). `smoothing` runs the
  // sliding window after each frame (off: T_world_camera_smoothed is tracking's pose). Throws
  // std::invalid_argument for out-of-range settings, as Frontend does.
  Mapper(const CameraIntrinsics& camera, const MapperConfig& config, PatternsConfig patterns,
         const Pose3& T_world_first = Pose3::Identity(), bool smoothing = true);

  // Stage 1: the cloud and the frontend. Const and thread-safe; never throws for what a frame
  // holds (an empty model says why in its `reason`).
  Perception Perceive(const RgbdFrame& frame) const;
  // Stage 2, in frame order: tracking (frame to map), then the sliding window. With odometry,
  // `T_odometry_camera` is the camera pose in the odometry's own frame (Tracker::Track).
  MapperStep Track(const Perception& perception, double stamp, const std::optional<Pose3>& T_odometry_camera = std::nullopt);
  // Both stages on this thread.
  MapperStep Add(const RgbdFrame& frame, const std::optional<Pose3>& T_odometry_camera = std::nullopt);

  // The live map and, per frame tracked so far, its pose and observations.
  const PlaneMap& map() const { return tracker_.map(); }
  const std::vector<FrameObservations>& observations() const { return tracker_.observations(); }
  // Frames tracked so far with each status (TrackStatus order: tracked, degraded, lost).
  int frames(TrackStatus status) const { return counts_[static_cast<int>(status)]; }

  // The batch back end over every frame so far (BatchResult::report.usable says if it may be used).
  BatchResult Refine() const;
  // The map to keep: refined by the batch back end when `refine` (tracking's map when the solve is
  // unusable; the report says why), then duplicate surfaces and objects fused.
  FinalMap Finish(bool refine) const;

  const CameraIntrinsics& camera() const { return camera_; }
  const MapperConfig& config() const { return config_; }
  const Frontend& frontend() const { return frontend_; }

 private:
  CameraIntrinsics camera_;
  MapperConfig config_;
  Frontend frontend_;
  Tracker tracker_;
  std::optional<SlidingWindow> window_;
  int counts_[3] = {0, 0, 0};
};

}  // namespace planemap
