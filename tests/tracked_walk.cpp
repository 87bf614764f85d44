#include "tracked_walk.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "planemap/pipeline/mapper.h"
#include "planemap/sim/virtual_camera.h"
#include "planemap/sim/walk.h"
#include "sim_views.h"
#include "test_support.h"

namespace planemap::testing {

const std::vector<SceneWalk>& SceneWalks() {
  static const std::vector<SceneWalk> walks{
      {"configs/scenes/default.yaml", {-0.7, -1.3, 1.95, -1.3, 2.03, -0.546}, "box"},
      {"configs/scenes/storeroom.yaml", {0.2, 1.3, 2.898, 1.645, 2.475, 0.739}, "crate"},
      // Long stretches see only planes along two directions (floor, east wall, the locker's
      // front, the shelf's bottom board): those frames are degraded.
      {"configs/scenes/office.yaml", {0.3, 0.6, 3.378, 0.449, 2.79, 0.175}, "box"}};
  return walks;
}

std::string SceneStem(const SceneWalk& walk) {
  std::string name = walk.scene;
  name = name.substr(name.rfind('/') + 1);
  return name.substr(0, name.find('.'));
}

Trajectory WalkTruth(std::vector<double> waypoints) {
  sim::WalkConfig walk;
  walk.waypoints = std::move(waypoints);
  walk.rate = 5.0;
  return sim::GenerateWalk(walk);
}

TrackedRun TrackWalk(const sim::Scene& scene, std::vector<double> waypoints, std::uint64_t seed, std::size_t first,
                     std::size_t last, const Pose3& T_run_world, const BackendConfig& backend, std::size_t stride) {
  sim::RenderConfig render;
  render.seed = seed;
  const sim::VirtualCamera camera(scene, XtionCamera(), render);
  TrackedRun run;
  const Trajectory truth = WalkTruth(std::move(waypoints));
  last = std::min(last, truth.size());
  if (first >= last) return run;
  for (size_t k = first; k < last; k += stride) run.truth.push_back(truth[k]);
  MapperConfig config;
  config.backend = backend;
  Mapper mapper(XtionCamera(), config, LoadPatterns(SourcePath("configs/patterns.yaml")), T_run_world * truth[first].T_world_camera);
  for (size_t k = first; k < last; k += stride) {
    sim::RenderedFrame rendered = camera.Render(truth[k].T_world_camera, camera.FrameSeed(static_cast<int>(k)));
    RgbdFrame frame;
    frame.depth = std::move(rendered.depth);
    frame.color = std::move(rendered.color);
    frame.stamp = truth[k].stamp;
    const MapperStep step = mapper.Add(frame);
    const TrackResult& r = step.track;
    run.estimate.push_back({frame.stamp, r.T_world_camera});
    run.smoothed.push_back({frame.stamp, step.T_world_camera_smoothed});
    if (std::getenv("PLANEMAP_TRACE")) {
      const Pose3 e = (T_run_world * truth[k].T_world_camera).inverse() * r.T_world_camera;
      const Pose3 p = (T_run_world * truth[k].T_world_camera).inverse() * r.T_predicted;  // the motion model's error
      std::printf("frame %zu %s planes %d matched %d inliers %d added %d icp %d err %.1f mm %.2f deg (predicted %.1f mm %.2f deg) %s\n",
                  k, ToString(r.status), r.planes, r.matched, r.inliers, r.added, r.refined, 1000 * e.translation().norm(),
                  RotationAngle(e.linear()) * 57.3, 1000 * p.translation().norm(), RotationAngle(p.linear()) * 57.3, r.reason.c_str());
    }
    run.status.push_back(r.status);
    run.relocalized.push_back(r.relocalized);
  }
  run.map = mapper.map();
  run.observations = mapper.observations();
  return run;
}



}  // namespace planemap::testing
