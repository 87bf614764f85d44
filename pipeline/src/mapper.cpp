#include "planemap/pipeline/mapper.h"

#include <chrono>

#include "planemap/core/config.h"

namespace planemap {
namespace {

using Clock = std::chrono::steady_clock;

double Ms(Clock::time_point from, Clock::time_point to) { return std::chrono::duration<double, std::milli>(to - from).count(); }

}  // namespace

MapperConfig LoadMapperConfig(const std::string& file) {
  const YAML::Node root = LoadYamlFile(file);
  MapperConfig config;
  if (!root || root.IsNull()) return config;
  if (!root.IsMap()) ThrowInputError(file, config_detail::LineOf(root), "expects a map of settings");
  ConfigReader reader(root, file);
  config.VisitFields(reader);  // other top-level keys are other tools' sections
  return config;
}

Mapper::Mapper(const CameraIntrinsics& camera, const MapperConfig& config, PatternsConfig patterns, const Pose3& T_world_first,
               bool smoothing)
    : camera_(camera),
      config_(config),
      frontend_(camera, config.frontend, std::move(patterns)),
      tracker_(config.tracking, T_world_first, camera_) {
  if (smoothing) window_.emplace(config.backend);
}

Perception Mapper::Perceive(const RgbdFrame& frame) const {
  Perception p;
  const auto t0 = Clock::now();
  p.cloud = MakeOrganizedCloud(frame, camera_, config_.frontend.cloud);
  p.model = frontend_.Process(*p.cloud);
  p.frontend_ms = Ms(t0, Clock::now());
  return p;
}

MapperStep Mapper::Track(const Perception& perception, double stamp, const std::optional<Pose3>& T_odometry_camera) {
  MapperStep step;
  const auto t0 = Clock::now();
  step.track = tracker_.Track(perception.model, *perception.cloud, stamp, T_odometry_camera);
  const auto t1 = Clock::now();
  ++counts_[static_cast<int>(step.track.status)];
  step.tracking_ms = Ms(t0, t1);
  if (window_) {
    step.T_world_camera_smoothed = window_->Update(tracker_.map(), tracker_.observations().back());
    step.window_ms = Ms(t1, Clock::now());
  } else {
    step.T_world_camera_smoothed = step.track.T_world_camera;
  }
  return step;
}

MapperStep Mapper::Add(const RgbdFrame& frame, const std::optional<Pose3>& T_odometry_camera) {
  return Track(Perceive(frame), frame.stamp, T_odometry_camera);
}

BatchResult Mapper::Refine() const { return RefineBatch(tracker_.map(), tracker_.observations(), config_.backend); }

FinalMap Mapper::Finish(bool refine) const {
  FinalMap result;
  result.refine_asked = refine;
  if (refine) {
    // Before landmarks are fused or renumbered: the observations name the tracker's landmarks.
    BatchResult batch = Refine();
    result.refine = batch.report;
    if (batch.report.usable) {
      result.map = std::move(batch.map);
      result.refined_poses = std::move(batch.poses);
      result.covariance_error = batch.covariance_error;
    }
  }
  if (!refine || !result.refine.usable) result.map = tracker_.map();  // tracking's map
  result.fused_planes = FuseDuplicateLandmarks(config_.merge, &result.map);
  result.fused_objects = FuseDuplicateObjects(config_.merge, &result.map);
  return result;
}

}  // namespace planemap
