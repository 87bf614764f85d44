#include "planemap/backend/backend.h"

#include <algorithm>
#include <cmath>

#include "factor_graph.h"

namespace planemap {

using backend_detail::FactorGraph;
using backend_detail::GraphSpec;

BatchResult RefineBatch(const PlaneMap& map, const std::vector<FrameObservations>& frames, const BackendConfig& config) {
  BatchResult result;
  result.map = map;
  std::vector<const FrameObservations*> pointers;
  std::vector<Pose3> initial;
  for (const FrameObservations& f : frames) {
    pointers.push_back(&f);
    initial.push_back(f.T_world_camera);
  }
  GraphSpec spec;
  spec.max_iterations = config.max_iterations;
  spec.tracking_sigma = config.batch_tracking_sigma;
  spec.tracking_sigma_rad = config.batch_tracking_sigma_deg * M_PI / 180.0;
  spec.tracking_prior_weak_only = true;
  spec.estimate_noise = true;
  FactorGraph graph(map, pointers, initial, config, spec);
  result.report = graph.Solve();
  if (!result.report.usable) {  // documented fallback: tracking's estimate, and the reason
    result.poses = initial;
    return result;
  }
  for (size_t i = 0; i < frames.size(); ++i) result.poses.push_back(graph.pose(i));
  graph.Write(&result.map);
  for (Keyframe& k : result.map.keyframes) {
    const auto it = std::find_if(frames.begin(), frames.end(), [&](const FrameObservations& f) { return f.frame == k.frame; });
    if (it != frames.end()) k.T_world_camera = result.poses[it - frames.begin()];
  }
  if (config.covariance) graph.Covariances(&result.map, &result.covariance_error, &result.report.covariance_seconds);
  return result;
}

SlidingWindow::SlidingWindow(const BackendConfig& config) : config_(config) {}

Pose3 SlidingWindow::Update(const PlaneMap& map, const FrameObservations& frame) {
  window_.push_back(frame);
  smoothed_.push_back(frame.T_world_camera);
  while (static_cast<int>(window_.size()) > std::max(config_.window_size, 1)) {
    window_.pop_front();
    smoothed_.pop_front();
  }
  if (window_.size() < 2) return frame.T_world_camera;  // nothing to smooth against yet
  std::vector<const FrameObservations*> pointers;
  for (const FrameObservations& f : window_) pointers.push_back(&f);
  // The newest frame starts at tracking's pose; the others at their smoothed ones; the oldest
  // is held (older frames are summarised by it).
  std::vector<Pose3> initial(smoothed_.begin(), smoothed_.end());
  GraphSpec spec;
  spec.free_landmarks = false;
  spec.cuboids = false;
  spec.gauge_prior = false;
  // The landmarks are the map's, which took these observations only where they agreed with it.
  spec.drop_outliers = false;
  spec.tracking_sigma = config_.window_tracking_sigma;
  spec.tracking_sigma_rad = config_.window_tracking_sigma_deg * M_PI / 180.0;
  spec.max_iterations = config_.window_max_iterations;
  FactorGraph graph(map, pointers, initial, config_, spec);
  report_ = graph.Solve();
  if (!report_.usable) return frame.T_world_camera;  // documented fallback: tracking's pose
  for (size_t i = 0; i < window_.size(); ++i) smoothed_[i] = graph.pose(i);
  return smoothed_.back();
}

}  // namespace planemap
