// bench_plane_consistency: how well a sequence's planes agree with its ground truth, which bounds
// what any tracker built on them (planemap's, or one fed ideal correspondences) can reach.
//
//   ./build/bench/bench_plane_consistency [--data ../shared/data] [--sequences a,b] [--gaps 1,10,30] [--min-inliers 8000]
//                                       [--registration-min-inliers 1000]
//
// Per sequence (every TUM-layout folder with ground truth, as bench_real finds them):
//   1. agreement: each frame's large planes (--min-inliers) moved into the world by the ground truth,
//      against those of the frame `gap` frames later: the median angle between the normals of
//      planes that are one surface (within 8 deg and 8 cm) and the median offset between them.
//      A rigid, undistorted sensor with exact ground truth gives the fit's noise (0.1-0.3 deg for
//      such planes); a depth that bends with the position in the image gives more, growing as the
//      view changes.
//   2. the best frame-to-frame plane registration (planes of --registration-min-inliers or more):
//      consecutive frames' planes paired by the ground truth's motion (within 3 deg and 3 cm),
//      each frame's inliers aligned to the previous frame's planes (AlignPointsToPlanes, as the
//      tracker refines), the motions chained: ATE [cm] and the median rotation error per frame
//      [deg]. No association error, no RANSAC: what planes alone give when every pairing is right.
//      A step whose paired normals do not span 3-D keeps the truth's motion and is counted.
#include <CLI/CLI.hpp>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "planemap/core/error.h"
#include "planemap/core/statistics.h"
#include "planemap/core/trajectory_eval.h"
#include "planemap/frontend/frontend.h"
#include "planemap/frontend/plane_registration.h"
#include "planemap/io/tum_sequence.h"
#include "real_table.h"

namespace planemap {
namespace {

constexpr double kDegPerRad = 180.0 / M_PI;

struct FramePlanes {
  double stamp = 0.0;
  Pose3 T_world_camera = Pose3::Identity();  // ground truth
  std::vector<DetectedPlane> planes;         // camera frame, the smaller minimum or more
  std::vector<PointMoments> moments;         // their inliers, weighted as the tracker weighs them
};

std::vector<FramePlanes> LoadFrames(const TumSequence& sequence, const CameraIntrinsics& camera, const Frontend& frontend, int min_inliers) {
  std::vector<FramePlanes> frames;
  for (size_t i = 0; i < sequence.size(); ++i) {
    if (!sequence.entry(i).T_world_camera) continue;
    const RgbdFrame frame = sequence.LoadFrame(i);
    const Cloud::Ptr cloud = MakeOrganizedCloud(frame, camera, CloudConfig{});
    FramePlanes f;
    f.stamp = frame.stamp;
    f.T_world_camera = *sequence.entry(i).T_world_camera;
    for (DetectedPlane& p : frontend.Process(*cloud).planes) {
      if (p.strip || static_cast<int>(p.inliers.size()) < min_inliers) continue;
      PointMoments m;
      for (int k : p.inliers) {
        const Eigen::Vector3d x = (*cloud)[k].getVector3fMap().cast<double>();
        m.Add(x, DepthNoiseWeight(x.z()));
      }
      f.planes.push_back(std::move(p));
      f.moments.push_back(m);
    }
    frames.push_back(std::move(f));
  }
  return frames;
}

// The plane of `b` nearest to plane `p` of `a` once both are in a's camera frame (ground truth's
// relative motion), within max_angle [rad] and max_distance [m] (the centroid to the plane): its
// index, angle [rad] and distance [m]; -1 when none.
struct Match {
  int index = -1;
  double angle = 0.0, distance = 0.0;
};
Match Nearest(const FramePlanes& a, int p, const FramePlanes& b, double max_angle, double max_distance, int min_inliers) {
  const Pose3 T_a_b = a.T_world_camera.inverse() * b.T_world_camera;
  Match best;
  double best_score = 2.0;
  for (size_t q = 0; q < b.planes.size(); ++q) {
    if (static_cast<int>(b.planes[q].inliers.size()) < min_inliers) continue;
    const Plane in_a = TransformPlane(T_a_b, b.planes[q].plane);
    const double angle = NormalAngle(in_a, a.planes[p].plane);
    const double distance = std::abs(in_a.SignedDistance(a.planes[p].centroid));
    const double score = angle / max_angle + distance / max_distance;
    if (angle <= max_angle && distance <= max_distance && score < best_score) best = {static_cast<int>(q), angle, distance}, best_score = score;
  }
  return best;
}

void PrintAgreement(const std::vector<FramePlanes>& frames, int gap, int min_inliers) {
  std::vector<double> angles, distances;
  for (size_t i = 0; i + gap < frames.size(); ++i) {
    for (size_t p = 0; p < frames[i].planes.size(); ++p) {
      if (static_cast<int>(frames[i].planes[p].inliers.size()) < min_inliers) continue;
      const Match m = Nearest(frames[i], static_cast<int>(p), frames[i + gap], 8.0 / kDegPerRad, 0.08, min_inliers);
      if (m.index < 0) continue;
      angles.push_back(m.angle * kDegPerRad);
      distances.push_back(100 * m.distance);
    }
  }
  if (angles.empty()) {
    std::printf("  %3d frames apart: no surface seen in both\n", gap);
    return;
  }
  std::printf("  %3d frames apart: %5zu plane pairs, normals %.2f deg apart (median, 90%% %.2f), offsets %.2f cm\n", gap, angles.size(),
              Percentile(angles, 0.5), Percentile(angles, 0.9), Percentile(distances, 0.5));
}

void PrintBestRegistration(const std::vector<FramePlanes>& frames, int min_inliers) {
  Trajectory truth, chained;
  std::vector<double> rotation_errors;
  int unfixed = 0;
  Pose3 T = frames.front().T_world_camera;
  truth.push_back({frames.front().stamp, frames.front().T_world_camera});
  chained.push_back({frames.front().stamp, T});
  for (size_t k = 1; k < frames.size(); ++k) {
    const FramePlanes &a = frames[k - 1], &b = frames[k];
    const Pose3 T_a_b = a.T_world_camera.inverse() * b.T_world_camera;
    std::vector<PointsOnPlane> groups;
    for (size_t q = 0; q < b.planes.size(); ++q) {
      if (static_cast<int>(b.planes[q].inliers.size()) < min_inliers) continue;
      // b's plane q against a's planes: the reverse of Nearest (q in a's frame).
      const Plane in_a = TransformPlane(T_a_b, b.planes[q].plane);
      const Eigen::Vector3d centroid = T_a_b * b.planes[q].centroid;
      int best = -1;
      double best_score = 2.0;
      for (size_t p = 0; p < a.planes.size(); ++p) {
        if (static_cast<int>(a.planes[p].inliers.size()) < min_inliers) continue;
        const double angle = NormalAngle(in_a, a.planes[p].plane), distance = std::abs(a.planes[p].plane.SignedDistance(centroid));
        const double score = angle / (3.0 / kDegPerRad) + distance / 0.03;
        if (angle <= 3.0 / kDegPerRad && distance <= 0.03 && score < best_score) best = static_cast<int>(p), best_score = score;
      }
      if (best >= 0) groups.push_back({b.moments[q], a.planes[best].plane, 1.0});
    }
    // Without normals spanning 3-D (smallest eigenvalue of sum n n^T below 0.05: three planes
    // within about 13 deg of a common line) the pose is not fixed and the truth's motion stands.
    Eigen::Matrix3d normals = Eigen::Matrix3d::Zero();
    for (const PointsOnPlane& g : groups) normals += g.target.normal * g.target.normal.transpose();
    Pose3 step = T_a_b;
    if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(normals).eigenvalues()(0) >= 0.05) {
      step = AlignPointsToPlanes(groups, T_a_b, T_a_b, 1e-6, 10, 0.01).T_target_source;
    } else {
      ++unfixed;
    }
    rotation_errors.push_back(RotationAngle(T_a_b.linear().transpose() * step.linear()) * kDegPerRad);
    T = T * step;
    truth.push_back({b.stamp, b.T_world_camera});
    chained.push_back({b.stamp, T});
  }
  const AteResult ate = ComputeAte(AssociatePoses(truth, chained, 1e-6));
  std::printf("  best frame-to-frame plane registration: ATE %.2f cm, rotation error per frame %.2f deg (median); %d of %zu steps unfixed\n",
              100 * ate.translation.rmse, Percentile(rotation_errors, 0.5), unfixed, frames.size() - 1);
}

int Run(int argc, char** argv) {
  std::string data = PLANEMAP_SOURCE_DIR "/../shared/data";
  std::vector<std::string> wanted;
  std::vector<int> gaps = {1, 10, 30};
  int min_inliers = 8000;               // the agreement: large planes only [px]
  int registration_min_inliers = 1000;  // the registration: planes as small as the tracker uses [px]
  CLI::App app{"How well each real sequence's planes agree with its ground truth (a bound on plane-based tracking)"};
  app.add_option("--data", data, "A folder of TUM-layout sequences, or one sequence");
  app.add_option("--sequences", wanted, "Only these sequences, comma-separated")->delimiter(',');
  app.add_option("--gaps", gaps, "Frame gaps for the agreement, comma-separated")->delimiter(',')->check(CLI::PositiveNumber);
  app.add_option("--min-inliers", min_inliers, "Planes with at least this many pixels [px]")->check(CLI::PositiveNumber);
  app.add_option("--registration-min-inliers", registration_min_inliers, "The registration's planes: at least this many pixels [px]")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<RealSequence> sequences = FindRealSequences(data);
    if (!wanted.empty()) sequences = SelectSequences(sequences, wanted);
    const PatternsConfig patterns = LoadPatterns(PLANEMAP_SOURCE_DIR "/configs/patterns.yaml");
    std::printf("Each sequence's planes under its ground truth: agreement of planes of %d px or more, registration with planes of %d px or more\n",
                min_inliers, registration_min_inliers);
    for (const RealSequence& s : sequences) {
      const std::optional<std::string> camera_file = CameraFileByName(s.name);
      if (!camera_file) {
        std::printf("%s: skipped (no camera by its name)\n", s.name.c_str());
        continue;
      }
      const CameraIntrinsics camera = LoadCameraIntrinsics(std::string(PLANEMAP_SOURCE_DIR "/") + *camera_file);
      const TumSequence sequence = TumSequence::Open(s.dir, camera, DatasetConfig{});
      const Frontend frontend(camera, FrontendConfig{}, patterns);
      const std::vector<FramePlanes> frames = LoadFrames(sequence, camera, frontend, std::min(min_inliers, registration_min_inliers));
      std::printf("%s (%zu frames with ground truth, %s)\n", s.name.c_str(), frames.size(), camera_file->c_str());
      if (frames.size() < 3) continue;
      for (int gap : gaps) {
        if (gap < static_cast<int>(frames.size())) PrintAgreement(frames, gap, min_inliers);
      }
      PrintBestRegistration(frames, registration_min_inliers);
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "bench_plane_consistency: error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace
}  // namespace planemap

int main(int argc, char** argv) { return planemap::Run(argc, argv); }
