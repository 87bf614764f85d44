#pragma once
// Rendered Nao-like walks tracked by the product, for tracking and map tests: the ground truth,
// the estimate, each frame's status and the map.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
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
  std::vector<bool> relocalized;  // per frame: its pose was found without the prediction
  PlaneMap map;
  std::vector<FrameObservations> observations;  // the tracker's, for the batch back end
};

// A Nao-like walk (10 cm/s, head sway, camera 52 cm up, 20 deg down) through `waypoints`, at
// 5 Hz as the paper's robot ran; frames rendered with noise (seed), then frontend and tracker,
// over the walk's frames [first, last); each frame also goes through the sliding window
// (`backend`'s settings). The tracker starts at T_run_world * (the true pose of
// frame `first`): its world is the scene's moved by T_run_world (identity: the scene's, as
// `planemap map` anchors a sequence with ground truth). PLANEMAP_TRACE=1 prints every frame.
// The walks of the tracking and back-end tests: each goes about 3.5 m past the scene's other
// furniture, turns, and approaches the box diagonally to about 0.65 m, so that two of its sides
// and its top are seen whole (from a 52 cm high camera a 25-30 cm box's top is seen only within
// about 1.3 m).
struct SceneWalk {
  const char* scene;
  std::vector<double> waypoints;  // x y pairs [m]
  const char* box;                // the object whose size and axis are checked
};
// default, storeroom, office.
const std::vector<SceneWalk>& SceneWalks();
// A test name from a walk: its scene file's stem ("default").
std::string SceneStem(const SceneWalk& walk);

// The true camera poses of such a walk through `waypoints` (5 Hz), as TrackWalk renders them.
Trajectory WalkTruth(std::vector<double> waypoints);

// Every `stride`-th frame from `first` on is tracked (1: all).
TrackedRun TrackWalk(const sim::Scene& scene, std::vector<double> waypoints, std::uint64_t seed, std::size_t first = 0,
                     std::size_t last = std::numeric_limits<std::size_t>::max(),
                     const Pose3& T_run_world = Pose3::Identity(), const BackendConfig& backend = BackendConfig{},
                     std::size_t stride = 1);


}  // namespace planemap::testing
