// Maps a TUM-layout RGB-D sequence with the planemap library: each frame's tracked and smoothed
// camera pose as it comes, then the objects of the final map.
//
//   map_sequence SEQUENCE_DIR CAMERA_YAML [MAX_FRAMES]
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "planemap/core/intrinsics.h"
#include "planemap/core/tum_format.h"
#include "planemap/io/tum_sequence.h"
#include "planemap/pipeline/mapper.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s SEQUENCE_DIR CAMERA_YAML [MAX_FRAMES]\n", argv[0]);
    return 2;
  }
  try {
    const std::string configs = PLANEMAP_CONFIGS_DIR;
    const planemap::CameraIntrinsics camera = planemap::LoadCameraIntrinsics(argv[2]);
    const planemap::TumSequence sequence = planemap::TumSequence::Open(argv[1], camera);
    const size_t frames = argc > 3 ? std::min<size_t>(std::strtoul(argv[3], nullptr, 10), sequence.size()) : sequence.size();

    // The first camera frame is the world.
    planemap::Mapper mapper(camera, planemap::LoadMapperConfig(configs + "/default.yaml"),
                            planemap::LoadPatterns(configs + "/patterns.yaml"));
    std::printf("# frame status tracked(stamp tx ty tz qx qy qz qw) | smoothed(tx ty tz)\n");
    for (size_t i = 0; i < frames; ++i) {
      const planemap::RgbdFrame frame = sequence.LoadFrame(i);
      const planemap::MapperStep step = mapper.Add(frame);
      const Eigen::Vector3d smoothed = step.T_world_camera_smoothed.translation();
      std::printf("%zu %s %s | %.4f %.4f %.4f\n", i, planemap::ToString(step.track.status),
                  planemap::FormatTumPose({frame.stamp, step.track.T_world_camera}).c_str(), smoothed.x(), smoothed.y(), smoothed.z());
    }

    const planemap::FinalMap result = mapper.Finish(/*refine=*/false);
    std::printf("map: %zu planes, %zu objects\n", result.map.landmarks.size(), result.map.objects.size());
    for (const planemap::MapObject& o : result.map.objects) {
      std::printf("object %d: %s, %.3f x %.3f x %.3f m, centre (%.3f, %.3f, %.3f), seen %d times\n", o.id, o.label.c_str(),
                  o.dimensions.x(), o.dimensions.y(), o.dimensions.z(), o.center.x(), o.center.y(), o.center.z(), o.observations);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "map_sequence: %s\n", e.what());
    return 1;
  }
  return 0;
}
