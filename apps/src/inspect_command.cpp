// planemap inspect: reads a TUM-layout sequence the way every other command will, and reports it.
#include <algorithm>
#include <cstdio>

#include "planemap/apps/app_config.h"
#include "planemap/apps/commands.h"
#include "planemap/apps/depth_summary.h"
#include "planemap/io/tum_sequence.h"

namespace planemap {

int RunInspect(const InspectOptions& options) {
  const std::optional<CameraIntrinsics> stored = TumSequence::StoredCamera(options.sequence);
  const CameraIntrinsics camera =
      !options.camera.empty() ? LoadCameraIntrinsics(ResolveConfigPath(options.camera))
      : stored               ? *stored
                             : LoadCameraIntrinsics(ResolveConfigPath("configs/cameras/tum_openni_default.yaml"));
  const AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(options.config));
  const TumSequence sequence = TumSequence::Open(options.sequence, camera, config.dataset);
  const size_t n = options.max_frames >= 0 ? std::min<size_t>(options.max_frames, sequence.size()) : sequence.size();

  size_t with_groundtruth = 0;
  DepthSummary depth;
  for (size_t i = 0; i < n; ++i) {
    const RgbdFrame frame = sequence.LoadFrame(i);  // throws naming the image on bad input
    if (frame.T_world_camera) ++with_groundtruth;
    depth.Add(frame.depth);
  }
  const double span = sequence.entry(sequence.size() - 1).depth.stamp - sequence.entry(0).depth.stamp;
  std::printf("planemap inspect: %s\n", options.sequence.c_str());
  std::printf("  %zu associated frames over %.2f s (%.1f Hz), %zu read\n", sequence.size(), span,
              span > 0 ? (sequence.size() - 1) / span : 0.0, n);
  std::printf("  ground truth: %s, %zu of %zu read frames have a pose within %.3f s\n",
              sequence.has_groundtruth() ? "yes" : "no", with_groundtruth, n, config.dataset.max_groundtruth_gap);
  std::printf("  camera: fx %.1f fy %.1f cx %.1f cy %.1f, %dx%d, %.0f depth units per metre\n", camera.fx, camera.fy,
              camera.cx, camera.cy, camera.width, camera.height, camera.depth_scale);
  std::printf("  labels: %s\n", sequence.has_labels() ? "yes" : "no");
  if (n > 0 && depth.z_max == 0.0) {
    std::printf("  depth: no valid pixel\n");
  } else if (n > 0) {
    std::printf("  depth: %.1f%% of pixels valid on average, %.2f-%.2f m\n", depth.MeanValidPercent(), depth.z_min,
                depth.z_max);
  }
  return 0;
}

}  // namespace planemap
