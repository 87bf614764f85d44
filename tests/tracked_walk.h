#pragma once
// Rendered Nao-like walks tracked by the product, for tracking and map tests: the ground truth,
// the estimate, each frame's status and the map.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "planemap/backend/backend.h"
#include "planemap/core/object_eval.h"
#include "planemap/core/plane_map.h"
#include "planemap/core/tum_format.h"
#include "planemap/frontend/tracker.h"
#include "planemap/sim/scene.h"

namespace planemap::testing {

struct TrackedRun {
  Trajectory truth, estimate;  // frames [first, last) of the walk; the estimate in the run's world
  Trajectory smoothed;         // the sliding window's pose of each frame, as it was given live
  std::vector<TrackStatus> status;
  PlaneMap map;
  std::vector<FrameObservations> observations;  // the tracker's, for the batch back end
};

// A Nao-like walk (10 cm/s, head sway, camera 52 cm up, 20 deg down) through `waypoints`, at
// 5 Hz as the paper's robot ran; frames rendered with noise (seed), then frontend and tracker,
// over the walk's frames [first, last); each frame also goes through the sliding window
// (`backend`'s settings). The tracker starts at T_run_world * (the true pose of
// frame `first`): its world is the scene's moved by T_run_world (identity: the scene's, as
// `planemap map` anchors a sequence with ground truth). PLANEMAP_TRACE=1 prints every frame.
TrackedRun TrackWalk(const sim::Scene& scene, std::vector<double> waypoints, std::uint64_t seed, std::size_t first = 0,
                     std::size_t last = std::numeric_limits<std::size_t>::max(),
                     const Pose3& T_run_world = Pose3::Identity(), const BackendConfig& backend = BackendConfig{});


}  // namespace planemap::testing
