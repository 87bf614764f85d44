// Back-end time and accuracy on a synthetic run: 1000 keyframes along a smooth figure-eight walk
// (two laps, head height) through an 8 x 6 x 2.6 m room of 50 plane landmarks: walls, floor,
// ceiling, two free boxes, eight boxes against the walls (the faces the walk can see), a shelf
// board, two leaning panels, a chamfered corner, a ramp and a tilted picture. Each keyframe
// observes the planes it can see (in the depth camera's field of view, 0.4-5 m, at most 75 deg off
// the normal, no slivers; occlusion ignored), the 12 with the largest visible area at most: 1-11 a
// frame, about 7 on average. An observation is what the frontend would measure: FitPlane of 500
// points sampled on the visible part of the patch with depth noise of 1.5 mm z^2, weighted as the
// tracker weighs them (its plane, centroid and (n, d) covariance; their errors match it, chi-square
// about 3 for 3 degrees of freedom). Tracking's poses are the true ones with a drifting error (a
// random walk of 0.15 mm and 0.006 deg a frame per axis, plus 0.5 mm and 0.03 deg of jitter; the
// first pose exact, as the gauge prior anchors it). The map is what the tracker would hold: each
// landmark the plane through all its observations' points, placed by tracking's poses (the batch
// starts from the map at the end of the run; the window gets the map as it stood at each frame).
// No objects.
// Side by side, one thread:
//   - RefineBatch over the whole run with each configured linear solver (sparse_schur,
//     sparse_normal_cholesky), covariances off; goal: <= 1 s. Each runs 3 times, the median kept.
//   - SlidingWindow (10 keyframes, landmarks held) fed the first 300 frames one by one, each
//     Update timed; goal: median <= 5 ms.
// ATE here is the RMS of the position error against the true poses, without alignment (the
// gauge is the true first pose). Fixed seeds: the problem is the same on every run.
// Run: ./build/bench/bench_backend [--benchmark_format=json]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <benchmark/benchmark.h>

#include "planemap/backend/backend.h"
#include "planemap/core/detected_plane.h"
#include "planemap/core/observations.h"
#include "planemap/core/plane_map.h"
#include "planemap/core/statistics.h"
#include "bench_main.h"

namespace planemap {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kFrames = 1000;
constexpr int kWindowFrames = 300;
constexpr int kWindowSize = 10;
constexpr int kBatchRuns = 3;
constexpr double kBatchGoalSeconds = 1.0;
constexpr double kWindowGoalMs = 5.0;

// The depth camera (Kinect / Xtion-like) and what the frontend would detect with it.
constexpr double kTanHalfFovX = 0.5543, kTanHalfFovY = 0.4142;  // tan(29 deg), tan(22.5 deg)
constexpr double kMinDepth = 0.4, kMaxDepth = 5.0;               // [m]
constexpr double kMinCosIncidence = 0.25;  // planes seen more than ~75 deg off their normal are missed
constexpr double kMinVisibleArea = 0.05;   // [m^2]
constexpr double kMinVisibleWidth = 0.2;   // no slivers [m]
constexpr int kGrid = 12;                  // visibility test points per side of a patch
constexpr int kPointsPerPlane = 500;
constexpr double kDepthNoise = 0.0015;  // depth noise sigma / z^2 (structured light, as DepthNoiseWeight assumes) [1/m]
constexpr int kMaxPlanesPerFrame = 12;
constexpr double kYawSwing = 35 * kDeg, kElevationSwing = 15 * kDeg;  // the camera's look around
// Tracking's error: a random walk per frame plus white jitter, per axis.
constexpr double kDriftStep = 0.00015, kDriftStepRad = 0.006 * kDeg;  // [m], [rad]
constexpr double kJitter = 0.0005, kJitterRad = 0.03 * kDeg;         // [m], [rad]

// A landmark's true surface: a rectangle on its plane (world).
struct Patch {
  Plane plane;  // normal toward the room
  Eigen::Vector3d center, u, v;  // centre [m], unit in-plane axes
  double half_u = 0.0, half_v = 0.0;  // [m]
  Eigen::Vector3d At(double a, double b) const { return center + a * half_u * u + b * half_v * v; }  // a, b in [-1, 1]
  double Area() const { return 4.0 * half_u * half_v; }
};

Patch MakePatch(const Eigen::Vector3d& center, const Eigen::Vector3d& normal, const Eigen::Vector3d& along, double half_u,
                double half_v) {
  Patch p;
  const Eigen::Vector3d n = normal.normalized();
  p.plane = Plane::FromPointNormal(center, n);
  p.center = center;
  p.u = (along - along.dot(n) * n).normalized();
  p.v = n.cross(p.u);
  p.half_u = half_u;
  p.half_v = half_v;
  return p;
}

// A box standing on the floor, turned by yaw about z; `faces` the ones the walk sees (a box
// against a wall never shows its back, nor a side unless the walk passes a metre beyond it).
enum Face { kTop = 1, kFront = 2, kBack = 4, kLeft = 8, kRight = 16, kAllFaces = 31 };
void AddBox(double x, double y, double yaw_deg, const Eigen::Vector3d& size, int faces, std::vector<Patch>* out) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ(), c(x, y, size.z() / 2), h = size / 2;
  if (faces & kTop) out->push_back(MakePatch(c + h.z() * z, z, R.col(0), h.x(), h.y()));
  const int sides[4][3] = {{kFront, 0, 1}, {kBack, 0, -1}, {kLeft, 1, 1}, {kRight, 1, -1}};  // face, axis, sign
  for (const auto& [face, k, sign] : sides) {
    if (faces & face) out->push_back(MakePatch(c + sign * h[k] * R.col(k), sign * R.col(k), z, h.z(), h[1 - k]));
  }
}

// The 50 landmarks. Boxes against a wall face the room with their front (local +x).
std::vector<Patch> MakeRoom() {
  using V = Eigen::Vector3d;
  const V X = V::UnitX(), Y = V::UnitY(), Z = V::UnitZ();
  std::vector<Patch> room = {
      MakePatch({0, 3, 1.3}, X, Y, 3.0, 1.3),    MakePatch({8, 3, 1.3}, -X, Y, 3.0, 1.3),  // walls
      MakePatch({4, 0, 1.3}, Y, X, 4.0, 1.3),    MakePatch({4, 6, 1.3}, -Y, X, 4.0, 1.3),
      MakePatch({4, 3, 0.0}, Z, X, 4.0, 3.0),    MakePatch({4, 3, 2.6}, -Z, X, 4.0, 3.0),  // floor, ceiling
  };
  AddBox(2.4, 3.0, 0, {0.9, 1.1, 0.75}, kAllFaces, &room);  // free: a lobe of the walk circles each
  AddBox(5.6, 3.0, -25, {1.0, 0.7, 1.0}, kAllFaces, &room);
  const int both_sides = kTop | kFront | kLeft | kRight;
  AddBox(2.4, 0.38, 84, {0.5, 1.2, 0.75}, both_sides, &room);  // against y = 0
  AddBox(4.9, 0.42, 98, {0.55, 1.0, 0.85}, both_sides, &room);
  AddBox(3.0, 5.65, -86, {0.5, 1.0, 0.5}, both_sides, &room);  // against y = 6
  AddBox(4.6, 5.70, -93, {0.45, 1.0, 0.7}, both_sides, &room);
  AddBox(0.35, 1.1, 3, {0.5, 1.0, 0.9}, kTop | kFront | kLeft, &room);  // against x = 0
  AddBox(0.33, 5.0, -4, {0.45, 1.1, 1.0}, kTop | kFront | kRight, &room);
  AddBox(7.70, 4.6, 178, {0.4, 1.4, 0.95}, kTop | kFront | kLeft, &room);  // against x = 8
  AddBox(7.72, 1.5, 182, {0.45, 0.8, 0.6}, kTop | kFront | kRight, &room);
  room.push_back(MakePatch({0.15, 3.0, 0.9}, Z, Y, 0.8, 0.15));                // shelf board on x = 0
  room.push_back(MakePatch({6.7, 5.75, 0.9}, {0, -1.8, 0.4}, X, 0.5, 0.92));   // panel leaning on y = 6
  room.push_back(MakePatch({3.6, 0.325, 0.75}, {0, 1.5, 0.55}, X, 0.3, 0.8));  // panel leaning on y = 0
  room.push_back(MakePatch({7.7, 0.3, 1.3}, {-1, 1, 0}, Z, 1.3, 0.42));        // chamfered corner
  room.push_back(MakePatch({4.0, 4.9, 0.05}, {0, -std::sin(10 * kDeg), std::cos(10 * kDeg)}, X, 0.3, 0.25));  // ramp
  room.push_back(MakePatch({7.93, 3.2, 1.6}, {-std::cos(15 * kDeg), 0, -std::sin(15 * kDeg)}, Y, 0.4, 0.3));  // tilted picture
  return room;
}

// The walk: two laps of a figure eight around the free boxes at head height, the camera looking
// across the room at a point that circles it once a lap, swinging left, right, up and down.
Pose3 TruePose(int k) {
  const double s = 4.0 * M_PI * k / kFrames;
  const Eigen::Vector3d p(4.0 + 2.8 * std::sin(s), 3.0 + 1.5 * std::sin(2 * s), 1.5 + 0.08 * std::sin(0.9 * s));
  const double phi = 1.37 * s + 2.0;  // the point looked at, on the walls' ellipse, its own pace
  const Eigen::Vector3d look = Eigen::Vector3d(4.0 + 3.9 * std::cos(phi), 3.0 + 2.9 * std::sin(phi), 0.4) - p;
  const double yaw = std::atan2(look.y(), look.x()) + kYawSwing * std::sin(2.3 * s + 0.5);
  const double elevation = std::atan2(look.z(), look.head<2>().norm()) + kElevationSwing * std::sin(1.7 * s + 1.0);
  Pose3 T = MakePoseRpy(3 * kDeg * std::sin(2.9 * s), -elevation, yaw, p);  // positive pitch looks down
  T.linear() = T.linear() * RotationBodyFromOptical();
  return T;
}

bool Visible(const Eigen::Vector3d& p_C, const Eigen::Vector3d& n_C) {
  if (p_C.z() < kMinDepth || p_C.z() > kMaxDepth) return false;
  if (std::abs(p_C.x()) > kTanHalfFovX * p_C.z() || std::abs(p_C.y()) > kTanHalfFovY * p_C.z()) return false;
  return -n_C.dot(p_C.normalized()) > kMinCosIncidence;
}

// The area of a patch the camera sees [m^2], from a grid over it (occlusion ignored); 0 when what
// it sees is a sliver (a frontend would not take it for a plane).
double VisibleArea(const Patch& patch, const Pose3& T_camera_world) {
  const Eigen::Vector3d n_C = T_camera_world.linear() * patch.plane.normal;
  PointMoments seen;  // in the patch's (u, v) [m]
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const double a = (2.0 * i + 1.0) / kGrid - 1.0, b = (2.0 * j + 1.0) / kGrid - 1.0;
      if (Visible(T_camera_world * patch.At(a, b), n_C)) seen.Add({a * patch.half_u, b * patch.half_v, 0.0});
    }
  }
  if (seen.n < 3) return 0.0;
  // The narrower spread of the visible part; a uniform strip of width w has w / sqrt(12).
  const double narrow = std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(seen.Covariance().topLeftCorner<2, 2>()).eigenvalues()(0)));
  if (narrow * std::sqrt(12.0) < kMinVisibleWidth) return 0.0;
  return patch.Area() * seen.n / (kGrid * kGrid);
}

// What the frontend measures of a patch: a plane fit to noisy depth points on its visible part;
// `points` gets their moments (camera frame).
PlaneObservation Observe(int landmark, const Patch& patch, const Pose3& T_camera_world, std::mt19937_64* rng, PointMoments* points) {
  const Eigen::Vector3d n_C = T_camera_world.linear() * patch.plane.normal;
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  PointMoments& moments = *points = PointMoments();
  for (int tries = 0; moments.n < kPointsPerPlane && tries < 1000 * kPointsPerPlane; ++tries) {
    const double a = uniform(*rng), b = uniform(*rng);  // in this order
    const Eigen::Vector3d p = T_camera_world * patch.At(a, b);
    if (!Visible(p, n_C)) continue;
    // The depth error's component along the normal: the part a plane fit sees. (Moved along the
    // ray instead, the in-plane part tilts PCA fits of far oblique patches by degrees, a bias
    // their covariance does not hold.)
    const double sigma = kDepthNoise * p.z() * p.z() * std::abs(n_C.dot(p.normalized()));
    const Eigen::Vector3d q = p + sigma * normal(*rng) * n_C;
    moments.Add(q, DepthNoiseWeight(q.z()));
  }
  const PlaneFit fit = FitPlane(moments);
  PlaneObservation o;
  o.landmark = landmark;
  o.plane = fit.plane;
  o.covariance = fit.covariance;
  o.centroid = fit.centroid;
  o.inliers = static_cast<int>(moments.n);
  return o;
}

Eigen::Matrix3d Exp(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  return angle > 0.0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

// The run: true poses, tracking's frames and the map tracking built.
struct Problem {
  std::vector<Pose3> truth;
  std::vector<FrameObservations> frames;
  PlaneMap map;                   // at the end of the run
  std::vector<PlaneMap> live_maps;  // as it was after each of the window's frames
  int observations = 0, min_per_frame = 1 << 30, max_per_frame = 0, min_per_landmark = 1 << 30;
};

// Tracking's pose of frame k: the truth with a drifting error (`drift` the random walk so far).
Pose3 TrackingPose(const Pose3& T_world_camera, Eigen::Matrix<double, 6, 1>* drift, std::mt19937_64* rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  auto gaussian = [&](double sigma) -> Eigen::Vector3d {  // drawn in a fixed order
    Eigen::Vector3d g;
    for (int i = 0; i < 3; ++i) g[i] = sigma * normal(*rng);
    return g;
  };
  drift->head<3>() += gaussian(kDriftStep);
  drift->tail<3>() += gaussian(kDriftStepRad);
  Pose3 T = T_world_camera;
  T.linear() = Exp(drift->tail<3>() + gaussian(kJitterRad)) * T_world_camera.linear();
  T.translation() += drift->head<3>() + gaussian(kJitter);
  return T;
}

// A landmark as the tracker holds it: the plane through every inlier it merged, placed in the
// world by tracking's poses, its normal toward the cameras.
void Merge(const PointMoments& points_camera, const PlaneObservation& o, const Pose3& T_world_camera, PlaneLandmark* landmark) {
  landmark->moments += TransformMoments(T_world_camera, points_camera);
  landmark->plane = FitPlane(landmark->moments).plane;
  if (landmark->plane.normal.dot(T_world_camera.linear() * o.plane.normal) < 0.0) landmark->plane = landmark->plane.Flipped();
}

Problem MakeProblem() {
  const std::vector<Patch> room = MakeRoom();
  std::mt19937_64 rng(20240611);
  Problem problem;
  problem.map.landmarks.resize(room.size());
  for (size_t l = 0; l < room.size(); ++l) {
    PlaneLandmark& landmark = problem.map.landmarks[l];
    landmark.id = static_cast<int>(l);
    landmark.plane = room[l].plane;  // replaced at its first observation
    for (const double a : {-1.0, 1.0}) {
      for (const double b : {-1.0, 1.0}) {
        landmark.low = landmark.low.cwiseMin(room[l].At(a, b));
        landmark.high = landmark.high.cwiseMax(room[l].At(a, b));
      }
    }
  }
  Eigen::Matrix<double, 6, 1> drift = Eigen::Matrix<double, 6, 1>::Zero();
  for (int k = 0; k < kFrames; ++k) {
    const Pose3 T_world_camera = TruePose(k);
    problem.truth.push_back(T_world_camera);
    FrameObservations f;
    f.frame = k;
    f.stamp = k / 30.0;
    f.T_world_camera = k == 0 ? T_world_camera : TrackingPose(T_world_camera, &drift, &rng);  // the first exact: the gauge
    // The planes in view, the largest visible areas first.
    const Pose3 T_camera_world = T_world_camera.inverse();
    std::vector<std::pair<double, int>> seen;
    for (size_t l = 0; l < room.size(); ++l) {
      if (room[l].plane.SignedDistance(T_world_camera.translation()) < 0.1) continue;  // behind it
      const double area = VisibleArea(room[l], T_camera_world);
      if (area >= kMinVisibleArea) seen.emplace_back(-area, static_cast<int>(l));
    }
    std::sort(seen.begin(), seen.end());
    seen.resize(std::min<size_t>(seen.size(), kMaxPlanesPerFrame));
    for (const auto& [area, l] : seen) {
      PointMoments points;
      f.planes.push_back(Observe(l, room[l], T_camera_world, &rng, &points));
      PlaneLandmark& landmark = problem.map.landmarks[l];
      Merge(points, f.planes.back(), f.T_world_camera, &landmark);
      if (landmark.first_frame < 0) landmark.first_frame = k;
      ++landmark.observations;
      landmark.last_frame = k;
    }
    problem.observations += static_cast<int>(f.planes.size());
    problem.min_per_frame = std::min(problem.min_per_frame, static_cast<int>(f.planes.size()));
    problem.max_per_frame = std::max(problem.max_per_frame, static_cast<int>(f.planes.size()));
    problem.map.keyframes.push_back({k, f.stamp, f.T_world_camera});
    problem.frames.push_back(std::move(f));
    if (k < kWindowFrames) problem.live_maps.push_back(problem.map);
  }
  for (const PlaneLandmark& landmark : problem.map.landmarks) {
    problem.min_per_landmark = std::min(problem.min_per_landmark, landmark.observations);
  }
  return problem;
}

const Problem& Shared() {
  static const Problem problem = MakeProblem();
  return problem;
}

// RMS position error against the true poses [mm], frames [0, count).
double AteMm(const std::vector<Pose3>& estimate, size_t count) {
  const std::vector<Pose3>& truth = Shared().truth;
  double sum = 0.0;
  for (size_t k = 0; k < count; ++k) sum += (estimate[k].translation() - truth[k].translation()).squaredNorm();
  return 1000.0 * std::sqrt(sum / static_cast<double>(count));
}

std::vector<Pose3> TrackingPoses() {
  std::vector<Pose3> poses;
  for (const FrameObservations& f : Shared().frames) poses.push_back(f.T_world_camera);
  return poses;
}

// Each method's figures, for the table printed after the run.
struct MethodResult {
  double total_ms = 0.0, p95_ms = 0.0;  // batch: the whole RefineBatch call; window: median Update, p95
  double solve_ms = 0.0;                // batch: Ceres's time (report.seconds)
  double iterations = 0.0, ms_per_iteration = 0.0;
  double ate_before_mm = 0.0, ate_after_mm = 0.0;
  int outliers = 0;
  std::string linear_solver, termination;
};
std::map<std::string, MethodResult>& Results() {
  static std::map<std::string, MethodResult> results;
  return results;
}

BackendConfig Config(const std::string& linear_solver) {
  BackendConfig config;
  config.linear_solver = linear_solver;
  config.threads = 1;
  config.covariance = false;  // timing the solve; no objects to take covariances of anyway
  config.window_size = kWindowSize;
  return config;
}

void RunBatch(benchmark::State& state, const std::string& linear_solver) {
  using Clock = std::chrono::steady_clock;
  const Problem& p = Shared();
  const BackendConfig config = Config(linear_solver);
  std::vector<double> wall, solve;
  BatchResult result;
  for (auto _ : state) {
    const Clock::time_point start = Clock::now();
    result = RefineBatch(p.map, p.frames, config);
    wall.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    solve.push_back(result.report.seconds);
    state.SetIterationTime(wall.back());
  }
  MethodResult r;
  r.total_ms = 1000.0 * Percentile(wall, 0.5);
  r.solve_ms = 1000.0 * Percentile(solve, 0.5);
  r.iterations = result.report.iterations;
  r.ms_per_iteration = 1000.0 * result.report.seconds_per_iteration;
  r.ate_before_mm = AteMm(TrackingPoses(), p.truth.size());
  r.ate_after_mm = AteMm(result.poses, p.truth.size());
  r.outliers = result.report.outliers;
  r.linear_solver = result.report.linear_solver;
  r.termination = result.report.termination;
  state.counters["wall_s"] = r.total_ms / 1000.0;
  state.counters["solve_s"] = r.solve_ms / 1000.0;
  state.counters["goal_s"] = kBatchGoalSeconds;
  state.counters["solver_iterations"] = r.iterations;
  state.counters["s_per_iteration"] = r.ms_per_iteration / 1000.0;
  state.counters["ate_before_mm"] = r.ate_before_mm;
  state.counters["ate_after_mm"] = r.ate_after_mm;
  state.counters["observations"] = result.report.observations;
  state.counters["outliers"] = r.outliers;
  state.counters["landmarks"] = result.report.landmarks;
  state.counters["poses"] = result.report.poses;
  if (const auto schur = Results().find("sparse_schur"); schur != Results().end()) {
    state.counters["x_sparse_schur"] = r.total_ms / schur->second.total_ms;
  }
  state.SetLabel(r.linear_solver + "; " + r.termination.substr(0, r.termination.find(':')));
  Results()[linear_solver] = r;
}

void RunWindow(benchmark::State& state, const std::string& linear_solver) {
  using Clock = std::chrono::steady_clock;
  const Problem& p = Shared();
  const BackendConfig config = Config(linear_solver);
  std::vector<double> ms, iterations, ms_per_iteration;
  std::vector<Pose3> smoothed;
  std::string solver;
  for (auto _ : state) {
    SlidingWindow window(config);
    ms.clear(), iterations.clear(), ms_per_iteration.clear(), smoothed.clear();
    double seconds = 0.0;
    for (int k = 0; k < kWindowFrames; ++k) {
      const Clock::time_point start = Clock::now();
      smoothed.push_back(window.Update(p.live_maps[k], p.frames[k]));
      const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      seconds += elapsed;
      if (k == 0) continue;  // one frame: nothing to solve
      ms.push_back(1000.0 * elapsed);
      iterations.push_back(window.last_report().iterations);
      ms_per_iteration.push_back(1000.0 * window.last_report().seconds_per_iteration);
      solver = window.last_report().linear_solver;
    }
    state.SetIterationTime(seconds);
  }
  MethodResult r;
  r.total_ms = Percentile(ms, 0.5);
  r.p95_ms = Percentile(ms, 0.95);
  r.iterations = Percentile(iterations, 0.5);
  r.ms_per_iteration = Percentile(ms_per_iteration, 0.5);
  r.ate_before_mm = AteMm(TrackingPoses(), kWindowFrames);
  r.ate_after_mm = AteMm(smoothed, kWindowFrames);
  r.linear_solver = solver;
  state.counters["frames"] = kWindowFrames;
  state.counters["median_ms"] = r.total_ms;
  state.counters["p95_ms"] = r.p95_ms;
  state.counters["goal_median_ms"] = kWindowGoalMs;
  state.counters["iterations_median"] = r.iterations;
  state.counters["ms_per_iteration"] = r.ms_per_iteration;
  state.counters["ate_input_mm"] = r.ate_before_mm;
  state.counters["ate_window_mm"] = r.ate_after_mm;
  state.SetLabel(solver);
  Results()["window " + linear_solver] = r;
}

void BM_BatchSparseSchur(benchmark::State& state) { RunBatch(state, "sparse_schur"); }
void BM_BatchSparseNormalCholesky(benchmark::State& state) { RunBatch(state, "sparse_normal_cholesky"); }
void BM_SlidingWindow(benchmark::State& state) { RunWindow(state, "sparse_schur"); }

// The batch runs kBatchRuns times (the median kept); the window once (its updates are the samples).
BENCHMARK(BM_BatchSparseSchur)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(kBatchRuns);
BENCHMARK(BM_BatchSparseNormalCholesky)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(kBatchRuns);
BENCHMARK(BM_SlidingWindow)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);

// The methods side by side; times relative to the sparse_schur batch.
void PrintSummary() {
  const auto& results = Results();
  if (results.empty()) return;
  const auto schur = results.find("sparse_schur");
  // `value` relative to the sparse_schur batch's, when it ran.
  auto ratio = [&](double value, double MethodResult::*field) {
    char text[32] = "-";
    if (schur != results.end()) std::snprintf(text, sizeof(text), "%.3fx", value / (schur->second.*field));
    return std::string(text);
  };
  const Problem& p = Shared();
  std::printf("\nBack end on a synthetic room (8 x 6 x 2.6 m): %d keyframes, %zu plane landmarks (each seen by >= %d frames), "
              "%d plane observations (%d-%d a frame, mean %.1f), one thread.\n",
              kFrames, p.map.landmarks.size(), p.min_per_landmark, p.observations, p.min_per_frame, p.max_per_frame,
              static_cast<double>(p.observations) / kFrames);
  if (results.count("sparse_schur") || results.count("sparse_normal_cholesky")) {
    std::printf("Batch (RefineBatch, covariance off), median of %d runs; goal: <= %.0f s\n", kBatchRuns, kBatchGoalSeconds);
    std::printf("  %-24s %8s %8s %8s %6s %8s %13s %12s  %s\n", "linear_solver", "total s", "solve s", "x schur", "iters", "ms/iter",
                "ATE before mm", "ATE after mm", "Ceres ran");
    for (const char* name : {"sparse_schur", "sparse_normal_cholesky"}) {
      if (!results.count(name)) continue;
      const MethodResult& r = results.at(name);
      const std::string outliers = r.outliers > 0 ? ", " + std::to_string(r.outliers) + " outliers dropped" : "";
      std::printf("  %-24s %8.3f %8.3f %8s %6.0f %8.1f %13.2f %12.2f  %s%s\n", name, r.total_ms / 1000.0, r.solve_ms / 1000.0,
                  ratio(r.total_ms, &MethodResult::total_ms).c_str(), r.iterations, r.ms_per_iteration, r.ate_before_mm, r.ate_after_mm,
                  r.linear_solver.c_str(), outliers.c_str());
      if (r.termination.rfind("CONVERGENCE", 0) != 0) std::printf("  %-24s %s\n", "", r.termination.c_str());
    }
    std::printf("  (total: the RefineBatch call, building the problem included; solve: Ceres's time; iters and ms/iter: Ceres's\n"
                "   minimizer, the outlier rounds' solves included)\n");
  }
  const auto window = results.find("window sparse_schur");
  if (window == results.end()) return;
  const MethodResult& w = window->second;
  std::printf("Sliding window (%d keyframes, landmarks held), frames 0-%d one by one, per Update; goal: median <= %.0f ms\n",
              kWindowSize, kWindowFrames - 1, kWindowGoalMs);
  std::printf("  %-24s %9s %8s %6s %8s %13s %13s %13s  %s\n", "linear_solver", "median ms", "p95 ms", "iters", "ms/iter",
              "x schur/iter", "ATE input mm", "ATE window mm", "Ceres ran");
  std::printf("  %-24s %9.2f %8.2f %6.0f %8.2f %13s %13.2f %13.2f  %s\n", "sparse_schur", w.total_ms, w.p95_ms, w.iterations,
              w.ms_per_iteration, ratio(w.ms_per_iteration, &MethodResult::ms_per_iteration).c_str(), w.ate_before_mm, w.ate_after_mm,
              w.linear_solver.c_str());
  std::printf("  (medians over the updates that solve, frames 1-%d; ATE of each frame's pose as Update returned it)\n", kWindowFrames - 1);
}

}  // namespace
}  // namespace planemap

int main(int argc, char** argv) {
  return planemap::RunBenchmarksThenSummary(argc, argv, planemap::PrintSummary);
}
