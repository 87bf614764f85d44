// planemap map: the frontend and tracking over a TUM-layout sequence; the trajectory, a per-frame
// tracking log, and the plane/object map.
#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>

#include "app_report.h"
#include "planemap/apps/app_config.h"
#include "planemap/apps/commands.h"
#include "planemap/core/error.h"
#include "planemap/core/statistics.h"
#include "planemap/io/frame_model_io.h"
#include "planemap/io/tum_sequence.h"
#include "planemap/pipeline/mapper.h"

namespace fs = std::filesystem;

namespace planemap {
namespace {

// "std: dimensions 1.6 1.6 0.9 mm, centre ... mm, axes ... deg, grasp axis ... deg" (a dimension
// only bounded from below: "bound").
std::string UncertaintyText(const MapObject::Uncertainty& u) {
  char text[256];
  std::string dims;
  for (int k = 0; k < 3; ++k) {
    std::snprintf(text, sizeof(text), "%s%.1f", k ? " " : "", 1000 * u.dimension_std[k]);
    dims += u.dimension_std[k] < 0.0 ? std::string(k ? " bound" : "bound") : std::string(text);
  }
  const Eigen::Vector3d centre = u.center_covariance.diagonal().cwiseMax(0.0).cwiseSqrt() * 1000;
  std::snprintf(text, sizeof(text), "std: dimensions %s mm, centre %.1f %.1f %.1f mm, axes %.2f %.2f %.2f deg, grasp axis ", dims.c_str(),
                centre.x(), centre.y(), centre.z(), u.axes_std_deg.x(), u.axes_std_deg.y(), u.axes_std_deg.z());
  std::string out = text;
  if (u.grasp_axis_std_deg < 0.0) return out + "none";
  std::snprintf(text, sizeof(text), "%.2f deg", u.grasp_axis_std_deg);
  return out + text;
}

}  // namespace

int RunMap(const MapOptions& options) {
  if (options.stride < 1) throw InputError("--stride must be 1 or more");
  if (options.anchor != "auto" && options.anchor != "groundtruth" && options.anchor != "first") {
    throw InputError("--anchor must be auto, groundtruth or first, not '" + options.anchor + "'");
  }
  ReportAssets report_assets;
  if (!options.report.empty()) report_assets = PrepareReport(options.report);
  CameraIntrinsics camera;
  if (!options.camera.empty()) {
    camera = LoadCameraIntrinsics(ResolveConfigPath(options.camera));
  } else if (const auto stored = TumSequence::StoredCamera(options.sequence)) {
    camera = *stored;
  } else {
    camera = LoadCameraIntrinsics(ResolveConfigPath("configs/cameras/tum_openni_default.yaml"));
  }
  const AppConfig config = LoadConfigFile<AppConfig>(ResolveConfigPath(options.config));
  const TumSequence sequence = TumSequence::Open(options.sequence, camera, config.dataset);

  // The world: the first frame's ground-truth pose when there is one (so the map and the
  // trajectory are in the ground truth's frame), else the first camera frame.
  Pose3 T_world_first = Pose3::Identity();
  const auto first_truth = sequence.size() > 0 ? sequence.entry(0).T_world_camera : std::nullopt;
  if (options.anchor == "groundtruth" && !first_truth) {
    ThrowInputError(options.sequence, 0, "--anchor groundtruth: the first frame has no ground-truth pose");
  }
  const bool anchored = options.anchor != "first" && first_truth.has_value();
  if (anchored) T_world_first = *first_truth;
  Mapper mapper(camera, config.mapper(), LoadPatterns(ResolveConfigPath(options.patterns)), T_world_first);

  std::error_code ec;
  fs::create_directories(options.out, ec);
  if (ec) ThrowInputError(options.out, 0, "cannot create folder: " + ec.message());
  const fs::path out(options.out);
  // Written frame by frame and flushed, so an interrupted run keeps what it did.
  std::ofstream trajectory(out / "trajectory.txt"), smoothed(out / "trajectory_smoothed.txt"), log(out / "tracking.csv");
  if (!trajectory || !smoothed || !log) ThrowInputError(options.out, 0, "cannot write trajectory.txt / trajectory_smoothed.txt / tracking.csv");
  const std::string world = anchored ? "ground truth (first pose)" : "first camera frame";
  trajectory << "# planemap map " << options.sequence << ": T_world_camera (tracking), world = " << world
             << "\n# timestamp tx ty tz qx qy qz qw\n";
  smoothed << "# planemap map " << options.sequence << ": T_world_camera (sliding window of " << config.backend.window_size
           << " frames, as given live), world = " << world << "\n# timestamp tx ty tz qx qy qz qw\n";
  log << "frame,stamp,status,planes,matched,inliers,added,refined,frontend_ms,tracking_ms,window_ms,reason\n";

  const size_t frames = options.max_frames < 0 ? sequence.size() : std::min(sequence.size(), static_cast<size_t>(options.max_frames));
  int unreadable = 0;
  double cloud_points = 0.0;  // valid pixels of every frame used
  std::vector<double> frontend_ms, tracking_ms, window_ms;
  Trajectory tracked, truth;  // for the report; the truth when the map is in its world
  using Clock = std::chrono::steady_clock;
  // The mapper's two stages on two threads: while frame k is tracked (and smoothed), frame k + 1
  // is read and perceived, which depends on no pose. Tracking takes the frames in order, so the
  // outputs are those of one thread, frame for frame.
  struct Perceived {
    RgbdFrame frame;
    Perception perception;
    std::string unreadable;  // why the frame could not be read; empty when it was
  };
  const auto perceive = [&](size_t i) {
    Perceived p;
    try {
      p.frame = sequence.LoadFrame(i);
    } catch (const InputError& e) {
      p.unreadable = e.what();
      return p;
    }
    p.perception = mapper.Perceive(p.frame);
    return p;
  };
  const auto start = Clock::now();
  std::future<Perceived> next;
  if (frames > 0) next = std::async(std::launch::async, perceive, size_t{0});
  for (size_t i = 0; i < frames; i += options.stride) {
    Perceived perceived = next.get();
    if (i + options.stride < frames) next = std::async(std::launch::async, perceive, i + options.stride);
    if (!perceived.unreadable.empty()) {  // documented fallback: report, skip, go on
      std::fprintf(stderr, "\nplanemap map: frame %zu skipped: %s\n", i, perceived.unreadable.c_str());
      ++unreadable;
      continue;
    }
    const RgbdFrame& frame = perceived.frame;
    for (const auto& p : *perceived.perception.cloud) cloud_points += IsValidPoint(p);
    const MapperStep step = mapper.Track(perceived.perception, frame.stamp);
    const TrackResult& r = step.track;
    frontend_ms.push_back(perceived.perception.frontend_ms);
    tracking_ms.push_back(step.tracking_ms);
    window_ms.push_back(step.window_ms);
    trajectory << FormatTumPose({frame.stamp, r.T_world_camera}) << "\n" << std::flush;
    tracked.push_back({frame.stamp, r.T_world_camera});
    if (anchored && sequence.entry(i).T_world_camera) truth.push_back({frame.stamp, *sequence.entry(i).T_world_camera});
    smoothed << FormatTumPose({frame.stamp, step.T_world_camera_smoothed}) << "\n" << std::flush;
    std::string reason = r.reason;
    std::replace(reason.begin(), reason.end(), ',', ';');
    log << i << ',' << FormatStamp(frame.stamp) << ',' << ToString(r.status) << ',' << r.planes << ',' << r.matched << ','
        << r.inliers << ',' << r.added << ',' << r.refined << ',' << frontend_ms.back() << ',' << tracking_ms.back() << ','
        << window_ms.back() << ',' << reason << "\n" << std::flush;
    std::fprintf(stderr, "\rframe %zu/%zu: %s, %d planes, %d matched, map %zu planes %zu objects   ", i + 1, frames,
                 ToString(r.status), r.planes, r.matched, mapper.map().landmarks.size(), mapper.map().objects.size());
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::fprintf(stderr, "\n");
  const int counts[3] = {mapper.frames(TrackStatus::kTracked), mapper.frames(TrackStatus::kDegraded), mapper.frames(TrackStatus::kLost)};
  if (counts[0] + counts[1] + counts[2] == 0) {
    ThrowInputError(options.sequence, 0, "none of its " + std::to_string(unreadable) + " frames could be read (each is named above): no map");
  }

  // Result lines go to stdout and into the report's summary.
  std::vector<std::string> summary;
  const auto say = [&summary](std::string line) {
    std::printf("%s\n", line.c_str());
    summary.push_back(std::move(line));
  };
  // The batch back end over every frame tracking kept (when asked), then duplicates fused.
  const FinalMap final_map = mapper.Finish(options.refine);
  const PlaneMap& map = final_map.map;
  Trajectory refined_poses;
  if (options.refine) {
    const SolveReport& s = final_map.refine;
    say(Printf("refine: %d poses, %d planes, %d boxes, %d residual blocks (%d plane observations, %d dropped as outliers)", s.poses,
               s.landmarks, s.cuboids, s.residual_blocks, s.observations, s.outliers));
    say(Printf("refine: %s, %d iterations, %.3f s (%.2f ms per iteration), cost %.4g -> %.4g, %s; covariances %.3f s",
               s.linear_solver.c_str(), s.iterations, s.seconds, 1000 * s.seconds_per_iteration, s.initial_cost, s.final_cost,
               s.termination.c_str(), s.covariance_seconds));
    std::ofstream(out / "refine_report.txt") << s.full;
    if (!s.usable) {
      std::fprintf(stderr, "planemap map: the back end failed (%s): map.json and the trajectory keep tracking's estimate\n",
                   s.termination.c_str());
    } else {
      if (!final_map.covariance_error.empty()) std::fprintf(stderr, "planemap map: no uncertainty: %s\n", final_map.covariance_error.c_str());
      std::ofstream refined(out / "trajectory_refined.txt");
      refined << "# planemap map --refine " << options.sequence << ": T_world_camera (batch back end), world = " << world
              << "\n# timestamp tx ty tz qx qy qz qw\n";
      const std::vector<FrameObservations>& frames_seen = mapper.observations();
      for (size_t k = 0; k < frames_seen.size(); ++k) refined_poses.push_back({frames_seen[k].stamp, final_map.refined_poses[k]});
      for (const StampedPose& pose : refined_poses) refined << FormatTumPose(pose) << "\n";
      if (!refined) ThrowInputError(options.out, 0, "cannot write trajectory_refined.txt");
    }
  }
  const int fused = final_map.fused_planes, fused_objects = final_map.fused_objects;
  {
    std::ofstream json(out / "map.json");
    json << PlaneMapJson(map) << "\n";
    if (!json) ThrowInputError((out / "map.json").string(), 0, "write failed");
  }
  WritePlaneMapPly((out / "map.ply").string(), map);

  // The map's size next to a point cloud of the same run (every valid pixel of every frame, as
  // xyz floats): the paper's argument for planes.
  const int tracked_frames = counts[0] + counts[1] + counts[2];
  say(Printf("frames %d: tracked %d, degraded %d, lost %d, unreadable %d", tracked_frames, counts[0], counts[1], counts[2], unreadable));
  say(Printf("map: %zu planes (%d duplicates fused), %zu edges, %zu objects (%d duplicates fused), %zu keyframes, %.1f kB (a point cloud of the same frames: %.1f MB)",
             map.landmarks.size(), fused, map.edges.size(), map.objects.size(), fused_objects, map.keyframes.size(), map.MemoryBytes() / 1024.0,
             cloud_points * 3 * sizeof(float) / (1024.0 * 1024.0)));
  for (const MapObject& o : map.objects) {
    say(Printf("  object %d: %s, %.3f x %.3f x %.3f m%s, centre (%.3f, %.3f, %.3f), seen %d times", o.id, o.label.c_str(),
               o.dimensions.x(), o.dimensions.y(), o.dimensions.z(),
               (o.dimension_complete[0] && o.dimension_complete[1] && o.dimension_complete[2]) ? "" : " (some lower bounds)",
               o.center.x(), o.center.y(), o.center.z(), o.observations));
    if (o.uncertainty.known) say("    " + UncertaintyText(o.uncertainty));
  }
  say(Printf("speed: frontend %.1f ms median (95%% %.1f), tracking %.1f ms median (95%% %.1f), sliding window %.1f ms median "
             "(95%% %.1f), %.1f frames/s overall",
             Percentile(frontend_ms, 0.5), Percentile(frontend_ms, 0.95), Percentile(tracking_ms, 0.5),
             Percentile(tracking_ms, 0.95), Percentile(window_ms, 0.5), Percentile(window_ms, 0.95), tracked_frames / std::max(seconds, 1e-9)));
  std::fprintf(stderr, "  wrote %s/trajectory.txt, trajectory_smoothed.txt, tracking.csv, map.json, map.ply%s\n", options.out.c_str(),
               options.refine ? ", trajectory_refined.txt, refine_report.txt" : "");
  if (!options.report.empty()) {
    ReportData report;
    report.title = "planemap map: " + options.sequence;
    report.summary = summary;
    AddMapToReport(map, config.frontend.graph, &report);
    report.trajectories = {{"tracked camera", "#ff8c00", tracked}};
    if (!refined_poses.empty()) report.trajectories.push_back({"refined camera (batch back end)", "#2ca02c", refined_poses});
    if (!truth.empty()) report.trajectories.push_back({"true camera (ground truth)", "#1f5fbf", truth});
    WriteHtmlReport(options.report, report, report_assets);
    std::fprintf(stderr, "  wrote %s\n", options.report.c_str());
  }
  return 0;
}

}  // namespace planemap
