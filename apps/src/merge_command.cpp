// planemap merge: two maps of `planemap map` into one (paper Fig. 4): aligned by plane
// correspondences (closed form in RANSAC, then ICP), surfaces fused, edges the longest of each
// pair, objects re-aggregated from the merged graph and re-classified.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "planemap/apps/app_config.h"
#include "planemap/apps/commands.h"
#include "planemap/core/error.h"
#include "planemap/frontend/map_merge.h"
#include "planemap/io/frame_model_io.h"
#include "planemap/io/plane_map_io.h"

namespace fs = std::filesystem;

namespace planemap {

int RunMerge(const MergeOptions& options) {
  constexpr double kDegToRad = M_PI / 180.0;
  const AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(options.config));
  const PlaneMap target = ReadPlaneMapJson(options.target);
  const PlaneMap source = ReadPlaneMapJson(options.source);
  Pose3 guess = Pose3::Identity();
  if (!options.guess.empty()) {
    if (options.guess.size() != 6) throw InputError("--guess takes x y z [m] roll pitch yaw [deg]");
    const std::vector<double>& g = options.guess;
    guess = MakePoseRpy(g[3] * kDegToRad, g[4] * kDegToRad, g[5] * kDegToRad, Eigen::Vector3d(g[0], g[1], g[2]));
  }
  ObjectModel objects{config.frontend.graph, config.frontend.objects, LoadPatterns(ResolveConfigPath(options.patterns))};
  const MapMergeResult r = MergeMaps(target, source, guess, config.merge, objects);
  if (!r.ok) {
    throw InputError("cannot align " + options.source + " to " + options.target + ": " + r.reason +
                     " (a --guess of the source world's pose in the target's may help)");
  }

  std::error_code ec;
  fs::create_directories(options.out, ec);
  if (ec) ThrowInputError(options.out, 0, "cannot create folder: " + ec.message());
  const fs::path out(options.out);
  std::ofstream json(out / "map.json");
  json << PlaneMapJson(r.map) << "\n";
  if (!json) ThrowInputError((out / "map.json").string(), 0, "cannot write");
  WritePlaneMapPly((out / "map.ply").string(), r.map);

  const Eigen::Vector3d t = r.T_target_source.translation();
  const Eigen::Vector3d rpy = r.T_target_source.linear().eulerAngles(2, 1, 0).reverse() / kDegToRad;
  std::printf("source in target: translation (%.3f, %.3f, %.3f) m, rotation %.2f deg (rpy %.2f %.2f %.2f, may wrap)\n", t.x(),
              t.y(), t.z(), RotationAngle(r.T_target_source.linear()) / kDegToRad, rpy.x(), rpy.y(), rpy.z());
  std::printf("alignment: %d candidate plane pairs, %d RANSAC inliers, ICP %s\n", r.candidates, r.inliers,
              r.refined ? "accepted" : "refused or not converged (closed form kept)");
  std::printf("planes: %zu + %zu -> %zu (%d fused); edges %zu + %zu -> %zu; keyframes %zu; %.1f kB\n", target.landmarks.size(),
              source.landmarks.size(), r.map.landmarks.size(), r.fused, target.edges.size(), source.edges.size(),
              r.map.edges.size(), r.map.keyframes.size(), r.map.MemoryBytes() / 1024.0);
  std::printf("objects: %zu + %zu -> %zu, re-aggregated from the merged graph\n", target.objects.size(), source.objects.size(),
              r.map.objects.size());
  for (const MapObject& o : r.map.objects) {
    std::printf("  object %d: %s, %.3f x %.3f x %.3f m%s, centre (%.3f, %.3f, %.3f), %zu faces, seen %d times\n", o.id,
                o.label.c_str(), o.dimensions.x(), o.dimensions.y(), o.dimensions.z(),
                (o.dimension_complete[0] && o.dimension_complete[1] && o.dimension_complete[2]) ? "" : " (some lower bounds)",
                o.center.x(), o.center.y(), o.center.z(), o.landmarks.size(), o.observations);
  }
  std::fprintf(stderr, "  wrote %s/map.json, map.ply\n", options.out.c_str());
  return 0;
}

}  // namespace planemap
