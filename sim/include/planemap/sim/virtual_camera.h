#pragma once
// A virtual RGB-D camera: exact ray casting of a plane-based scene, then the sensor noise model.
#include <cstdint>
#include <optional>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/image.h"
#include "planemap/core/intrinsics.h"
#include "planemap/core/pose.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/sensor_noise.h"

namespace planemap::sim {

struct RenderConfig {
  SensorNoiseConfig noise;
  bool add_noise = true;               // false renders exact depth
  std::vector<double> light_direction{0.3, 0.2, 1.0};  // towards the light, world frame
  double ambient = 0.35;               // share of a face's colour lit by ambient light [0, 1]
  int seed = 1;                        // base seed of the noise; frame k uses a seed derived from it

  template <class V>
  void VisitFields(V&& v) {
    v("noise", noise);
    v("add_noise", add_noise);
    v("light_direction", light_direction);
    v("ambient", ambient, Check::kProbability);
    v("seed", seed, Check::kNonNegative);
  }
};

struct RenderedFrame {
  DepthImage depth;    // [m], 0 = no reading
  ColorImage color;
  LabelImage labels;   // Surface label of the exact ray hit (also where the reading dropped out); 0 = none
};

class VirtualCamera {
 public:
  VirtualCamera(Scene scene, const CameraIntrinsics& camera, const RenderConfig& config);

  // Exact depth, colour and labels seen from T_world_camera (camera optical frame), no noise.
  RenderedFrame RenderExact(const Pose3& T_world_camera) const;

  // A sensor reading: exact render plus noise seeded by `seed`. With motion blur on, the camera
  // moves from `T_world_camera_exposure_start` to `T_world_camera` during the exposure.
  RenderedFrame Render(const Pose3& T_world_camera, std::uint64_t seed,
                       const std::optional<Pose3>& T_world_camera_exposure_start = {}) const;

  // The seed of frame `index` derived from the config's base seed.
  std::uint64_t FrameSeed(int index) const;

  const Scene& scene() const { return scene_; }
  const CameraIntrinsics& intrinsics() const { return camera_; }
  const RenderConfig& config() const { return config_; }

 private:
  struct RayCast;
  RayCast Cast(const Pose3& T_world_camera) const;
  ColorImage ShadeColor(const RayCast& cast, const Pose3& T_world_camera) const;

  Scene scene_;
  CameraIntrinsics camera_;
  RenderConfig config_;
  Eigen::Vector3d light_world_;
  // Per surface label: the markers printed on it (indices into scene_.markers), its light factor
  // and its shaded colour.
  std::vector<std::vector<size_t>> markers_on_;
  std::vector<double> light_;
  std::vector<Rgb8> shaded_;
};

}  // namespace planemap::sim
