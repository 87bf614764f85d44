// Pose from plane correspondences (paper sec. 4.2): closed form [13, 20], RANSAC, ICP on points
// rebuilt from plane inliers.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <pcl/common/transforms.h>

#include "planemap/frontend/plane_registration.h"
#include "planemap/frontend/plane_segmenter.h"
#include "sim_views.h"
#include "test_support.h"

namespace planemap {
namespace {

using testing::Median;
using testing::PosesNear;
using testing::RotationErrorDeg;
using testing::TranslationError;

constexpr double kRadPerDeg = M_PI / 180.0;

Pose3 RandomPose(std::mt19937_64& rng, double max_translation) {
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> uniform(-max_translation, max_translation);
  const Eigen::Quaterniond q(gauss(rng), gauss(rng), gauss(rng), gauss(rng));
  return MakePose(q, Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)));
}

// `count` planes with random normals that span 3-D well (smallest singular value of the unit
// normals' matrix >= 0.3) and offsets of 0.5-4 m.
std::vector<Plane> RandomPlanes(int count, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> offset(0.5, 4.0);
  while (true) {
    std::vector<Plane> planes;
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (int i = 0; i < count; ++i) {
      const Eigen::Vector3d n = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
      planes.push_back({n, offset(rng)});
      scatter += n * n.transpose();
    }
    if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues()[0] >= 0.3 * 0.3) return planes;
  }
}

// A pair with the other members at their defaults (weight 1, no source point, a group of its own).
PlaneCorrespondence Pair(const Plane& source, const Plane& target) {
  PlaneCorrespondence pair;
  pair.source = source;
  pair.target = target;
  return pair;
}

// Each target plane paired with itself seen from the source frame.
std::vector<PlaneCorrespondence> Correspond(const std::vector<Plane>& target, const Pose3& T_target_source) {
  std::vector<PlaneCorrespondence> pairs;
  for (const Plane& t : target) pairs.push_back(Pair(TransformPlane(T_target_source.inverse(), t), t));
  return pairs;
}

// The normal tilted by a Gaussian of `sigma_rad` along each of two tangent directions, the
// offset moved by a Gaussian of `sigma_offset` [m].
Plane Perturb(const Plane& plane, double sigma_rad, double sigma_offset, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss;
  const Eigen::Vector3d e1 = plane.normal.unitOrthogonal(), e2 = plane.normal.cross(e1);
  const Eigen::Vector3d n = plane.normal + sigma_rad * (gauss(rng) * e1 + gauss(rng) * e2);
  return {n.normalized(), plane.offset + sigma_offset * gauss(rng)};
}

// ---- Closed form ----

class NoiselessPlaneToPlane : public ::testing::TestWithParam<int> {};

TEST_P(NoiselessPlaneToPlane, RecoversTheExactPose) {
  std::mt19937_64 rng(1000 + GetParam());
  const int count = 3 + GetParam() % 6;  // 3..8 planes
  const Pose3 truth = RandomPose(rng, 2.0);
  std::string reason;
  const auto T = SolvePlaneToPlane(Correspond(RandomPlanes(count, rng), truth), 0.1, &reason);
  ASSERT_TRUE(T.has_value()) << count << " planes: " << reason;
  EXPECT_TRUE(PosesNear(*T, truth, 1e-9, 1e-9)) << count << " planes";
}

INSTANTIATE_TEST_SUITE_P(TwentyRandomPoses, NoiselessPlaneToPlane, ::testing::Range(0, 20));

// Six planes around the origin, two per axis facing each other (a room), Sigma n n^T = 2 I.
// Source and target are both perturbed: normals by sigma [rad] along each tangent axis, offsets by
// sigma_d. First-order error of the estimate, per axis (Maxwell median of a 3-D Gaussian: 1.54 s):
//  rotation (Kabsch): s_R^2 = var(n_t - R n_s) (sum (I - n n^T))^-1 = 2 sigma^2 / (6 - 2) -> median 1.09 sigma;
//  translation: equation residual var = 2 sigma_d^2 + sigma^2 |t_perp|^2, times (Sigma n n^T)^-1 = 1/2
//  per axis after the pairwise sums: s_t^2 <= sigma_d^2 + sigma^2 |t|^2 / 2, |t|^2 <= 0.75 m^2 here.
// Predicted medians: 1.09 sigma; 1.54 sqrt(sigma_d^2 + sigma^2 / 12) with E|t_perp|^2 = 2/3 E|t|^2 = 1/6 m^2
// for t uniform in a 1 m cube. Bounds: 2 sigma for rotation, 2 s_t(max |t|) for translation.
TEST(PlaneToPlane, ErrorGrowsWithNoiseWithinTheFirstOrderBound) {
  const double sigma_deg[] = {0.1, 0.5, 1.0, 2.0};
  const double sigma_mm[] = {1.0, 5.0, 10.0, 20.0};
  const int trials = 1000;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> offset(1.0, 3.0);
  double previous_rotation = 0.0, previous_translation = 0.0;
  std::printf("  sigma_n  sigma_d | median rot predicted  bound | median trans predicted  bound\n");
  std::printf("    [deg]     [mm] |      [deg]     [deg]  [deg] |         [mm]      [mm]   [mm]\n");
  for (int level = 0; level < 4; ++level) {
    const double sigma = sigma_deg[level] * kRadPerDeg, sigma_d = sigma_mm[level] / 1000.0;
    std::vector<double> rotation_deg, translation_mm;
    for (int trial = 0; trial < trials; ++trial) {
      std::vector<Plane> room;
      for (int axis = 0; axis < 3; ++axis) {
        room.push_back({Eigen::Vector3d::Unit(axis), offset(rng)});
        room.push_back({-Eigen::Vector3d::Unit(axis), offset(rng)});
      }
      const Pose3 truth = RandomPose(rng, 0.5);
      std::vector<PlaneCorrespondence> pairs = Correspond(room, truth);
      for (PlaneCorrespondence& p : pairs) {
        p.source = Perturb(p.source, sigma, sigma_d, rng);
        p.target = Perturb(p.target, sigma, sigma_d, rng);
      }
      std::string reason;
      const auto T = SolvePlaneToPlane(pairs, 0.1, &reason);
      ASSERT_TRUE(T.has_value()) << reason;
      rotation_deg.push_back(RotationErrorDeg(*T, truth));
      translation_mm.push_back(1000.0 * TranslationError(*T, truth));
    }
    const double rotation = Median(rotation_deg), translation = Median(translation_mm);
    const double sigma_mm_per_m = 1000.0 * sigma;  // normal noise times a lever of 1 m
    const double rotation_predicted = 1.54 * sigma_deg[level] / std::sqrt(2.0);
    const double rotation_bound = 2.0 * sigma_deg[level];
    const double translation_predicted = 1.54 * std::sqrt(std::pow(sigma_mm[level], 2) + std::pow(sigma_mm_per_m, 2) / 12.0);
    const double translation_bound = 2.0 * std::sqrt(std::pow(sigma_mm[level], 2) + 0.375 * std::pow(sigma_mm_per_m, 2));
    std::printf("  %7.1f  %7.0f | %10.3f %9.3f %6.3f | %12.2f %9.2f %6.2f\n", sigma_deg[level], sigma_mm[level],
                rotation, rotation_predicted, rotation_bound, translation, translation_predicted, translation_bound);
    EXPECT_LT(rotation, rotation_bound) << "median rotation error [deg] at sigma " << sigma_deg[level] << " deg";
    EXPECT_LT(translation, translation_bound) << "median translation error [mm] at sigma " << sigma_mm[level] << " mm";
    EXPECT_NEAR(rotation / rotation_predicted, 1.0, 0.2) << "median rotation error vs first order";
    EXPECT_NEAR(translation / translation_predicted, 1.0, 0.2) << "median translation error vs first order";
    EXPECT_GT(rotation, previous_rotation) << "rotation error [deg] must grow with the noise";
    EXPECT_GT(translation, previous_translation) << "translation error [mm] must grow with the noise";
    previous_rotation = rotation;
    previous_translation = translation;
  }
}

TEST(PlaneToPlane, DegenerateGeometryGivesNothingAndAReason) {
  const Pose3 truth = MakePoseRpy(0.1, -0.2, 0.3, Eigen::Vector3d(0.2, -0.1, 0.4));
  const Plane floor{Eigen::Vector3d::UnitZ(), 1.2};
  const Plane left{Eigen::Vector3d::UnitY(), 1.0}, right{-Eigen::Vector3d::UnitY(), 1.5};
  const Plane front{-Eigen::Vector3d::UnitX(), 3.0};
  std::string reason;

  EXPECT_FALSE(SolvePlaneToPlane(Correspond({floor, front}, truth), 0.1, &reason));
  EXPECT_NE(reason.find("at least 3"), std::string::npos) << reason;

  // A corridor: floor and two parallel walls constrain nothing along the corridor (x).
  EXPECT_FALSE(SolvePlaneToPlane(Correspond({floor, left, right}, truth), 0.1, &reason));
  EXPECT_NE(reason.find("coplanar"), std::string::npos) << reason;
  // ... also with a ceiling and normals perturbed by 1 deg per axis: far below a spread of 0.1,
  // which a normal 8 deg out of the others' plane would reach.
  std::mt19937_64 rng(3);
  std::vector<PlaneCorrespondence> corridor =
      Correspond({floor, left, right, Plane{-Eigen::Vector3d::UnitZ(), 1.3}}, truth);
  for (PlaneCorrespondence& p : corridor) p.target = Perturb(p.target, 1.0 * kRadPerDeg, 0.0, rng);
  EXPECT_FALSE(SolvePlaneToPlane(corridor, 0.1, &reason));
  EXPECT_NE(reason.find("coplanar"), std::string::npos) << reason;

  // Floor, table top, ceiling: parallel.
  const Plane table{Eigen::Vector3d::UnitZ(), 0.5}, ceiling{-Eigen::Vector3d::UnitZ(), 1.3};
  EXPECT_FALSE(SolvePlaneToPlane(Correspond({floor, table, ceiling}, truth), 0.1, &reason));
  EXPECT_NE(reason.find("parallel"), std::string::npos) << reason;

  std::vector<PlaneCorrespondence> bad_weight = Correspond({floor, left, front}, truth);
  bad_weight[1].weight = 0.0;
  EXPECT_FALSE(SolvePlaneToPlane(bad_weight, 0.1, &reason));
  EXPECT_NE(reason.find("correspondence 1"), std::string::npos) << reason;
}

TEST(PlaneToPlane, WeightsScaleFreely) {
  // The spread threshold does not depend on the weights' scale: a corridor stays degenerate with
  // weights of 1000, a corner stays solvable with weights of 0.001.
  const Pose3 truth = MakePoseRpy(0.0, 0.0, 0.5, Eigen::Vector3d(1.0, 0.0, 0.0));
  std::vector<PlaneCorrespondence> corridor = Correspond(
      {{Eigen::Vector3d::UnitZ(), 1.2}, {Eigen::Vector3d::UnitY(), 1.0}, {-Eigen::Vector3d::UnitY(), 1.0}}, truth);
  for (PlaneCorrespondence& p : corridor) p.weight = 1000.0;
  EXPECT_FALSE(SolvePlaneToPlane(corridor));
  std::vector<PlaneCorrespondence> corner = Correspond(
      {{Eigen::Vector3d::UnitZ(), 1.2}, {Eigen::Vector3d::UnitY(), 1.0}, {-Eigen::Vector3d::UnitX(), 2.0}}, truth);
  for (PlaneCorrespondence& p : corner) p.weight = 0.001;
  const auto T = SolvePlaneToPlane(corner);
  ASSERT_TRUE(T.has_value());
  EXPECT_TRUE(PosesNear(*T, truth, 1e-9, 1e-9));
}

// ---- RANSAC ----

TEST(PlaneRansac, PlantedWrongCorrespondencesAreNotInliersAndThePoseIsExact) {
  std::mt19937_64 rng(11);
  const Pose3 truth = RandomPose(rng, 1.0);
  const std::vector<Plane> planes = RandomPlanes(6, rng);
  std::vector<PlaneCorrespondence> pairs = Correspond(planes, truth);
  // Wrong pairs in the middle of the list: plane 0 seen from the source matched to plane 1's
  // target (swapped), and plane 2 matched to its target moved by 0.5 m.
  const PlaneCorrespondence swapped = Pair(pairs[0].source, pairs[1].target);
  const PlaneCorrespondence moved = Pair(pairs[2].source, Plane{pairs[2].target.normal, pairs[2].target.offset + 0.5});
  pairs.insert(pairs.begin() + 2, swapped);
  pairs.insert(pairs.begin() + 5, moved);  // indices 2 and 5 are wrong
  const std::vector<int> correct = {0, 1, 3, 4, 6, 7};

  const PlaneRansacConfig config;
  const PlaneRansacResult result = EstimatePoseRansac(pairs, config);
  ASSERT_TRUE(result.ok) << result.reason;
  EXPECT_EQ(result.inliers, correct);
  EXPECT_TRUE(PosesNear(result.T_target_source, truth, 1e-9, 1e-9));

  const PlaneRansacResult again = EstimatePoseRansac(pairs, config);
  EXPECT_EQ(again.inliers, result.inliers);
  EXPECT_TRUE(again.T_target_source.matrix() == result.T_target_source.matrix()) << "same seed, same pose";

  PlaneRansacConfig other_seed = config;
  other_seed.seed = 12345;
  const PlaneRansacResult other = EstimatePoseRansac(pairs, other_seed);
  EXPECT_EQ(other.inliers, correct);
  EXPECT_TRUE(PosesNear(other.T_target_source, truth, 1e-9, 1e-9));
}

TEST(PlaneRansac, NoisyPlanesKeepTheRightInliers) {
  std::mt19937_64 rng(21);
  const Pose3 truth = RandomPose(rng, 1.0);
  std::vector<PlaneCorrespondence> pairs = Correspond(RandomPlanes(6, rng), truth);
  for (PlaneCorrespondence& p : pairs) {
    p.source = Perturb(p.source, 0.3 * kRadPerDeg, 0.003, rng);
    p.target = Perturb(p.target, 0.3 * kRadPerDeg, 0.003, rng);
  }
  pairs.push_back(Pair(pairs[0].source, pairs[3].target));
  pairs.push_back(Pair(pairs[4].source, Plane{pairs[4].target.normal, pairs[4].target.offset - 0.5}));
  const PlaneRansacResult result = EstimatePoseRansac(pairs, PlaneRansacConfig{});
  ASSERT_TRUE(result.ok) << result.reason;
  EXPECT_EQ(result.inliers, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_TRUE(PosesNear(result.T_target_source, truth, 1.0, 0.02)) << "0.3 deg / 3 mm plane noise";
}

TEST(PlaneRansac, FourCorrespondencesTryEveryTriple) {
  std::mt19937_64 rng(31);
  const Pose3 truth = RandomPose(rng, 1.0);
  std::vector<PlaneCorrespondence> pairs = Correspond(RandomPlanes(3, rng), truth);
  // A wrong match first (the first plane's source with the second's target), so the first triple
  // tried holds it. (A copy of a true pair with its offset moved would not do: with it in place of
  // its twin, three pairs fit a wrong pose exactly, and the tie between the two poses would be
  // decided by rounding.)
  pairs.insert(pairs.begin(), Pair(pairs[0].source, pairs[1].target));
  PlaneRansacConfig config;
  config.max_iterations = 1;  // ignored: all 4 triples are tried
  const PlaneRansacResult result = EstimatePoseRansac(pairs, config);
  ASSERT_TRUE(result.ok) << result.reason;
  EXPECT_EQ(result.inliers, (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(PosesNear(result.T_target_source, truth, 1e-9, 1e-9));
}

TEST(PlaneRansac, TooFewOrDegenerateCorrespondencesAreNotOk) {
  const Pose3 truth = MakePoseRpy(0.0, 0.0, 0.2, Eigen::Vector3d(0.3, 0.0, 0.0));
  const Plane floor{Eigen::Vector3d::UnitZ(), 1.2};
  const Plane left{Eigen::Vector3d::UnitY(), 1.0}, right{-Eigen::Vector3d::UnitY(), 1.5};
  PlaneRansacResult result = EstimatePoseRansac(Correspond({floor, left}, truth), PlaneRansacConfig{});
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.reason.find("at least 3"), std::string::npos) << result.reason;
  result = EstimatePoseRansac(Correspond({floor, left, right, Plane{-Eigen::Vector3d::UnitZ(), 1.3}}, truth),
                              PlaneRansacConfig{});
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.reason.find("coplanar"), std::string::npos) << result.reason;
}

// ---- ICP on plane points ----

// Points on a square patch of a plane through `corner` spanned by u and v (side `size`, grid
// `step`, shifted by `shift` along both), with normal n.
void AddPatch(const Eigen::Vector3d& corner, const Eigen::Vector3d& u, const Eigen::Vector3d& v, double size,
              double step, double shift, const Pose3& T, pcl::PointCloud<pcl::PointNormal>* cloud) {
  const Eigen::Vector3d n = T.linear() * u.cross(v).normalized();
  for (double a = shift; a < size; a += step) {
    for (double b = shift; b < size; b += step) {
      pcl::PointNormal p;
      p.getVector3fMap() = (T * (corner + a * u + b * v)).cast<float>();
      p.getNormalVector3fMap() = n.cast<float>();
      cloud->push_back(p);
    }
  }
}

// A box corner on the floor: the floor (z = 0) and two perpendicular faces of a 1 m box at the
// origin, normals out of the box (toward a camera in the +x, +y, +z octant).
pcl::PointCloud<pcl::PointNormal> BoxCornerOnFloor(double step, double shift, const Pose3& T) {
  pcl::PointCloud<pcl::PointNormal> cloud;
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  AddPatch(Eigen::Vector3d(0.0, 0.0, 0.0), x, y, 1.5, step, shift, T, &cloud);   // floor beside the box
  AddPatch(Eigen::Vector3d(0.0, -1.0, 0.0), y, z, 1.0, step, shift, T, &cloud);  // face x = 0, normal +x
  AddPatch(Eigen::Vector3d(-1.0, 0.0, 0.0), z, x, 1.0, step, shift, T, &cloud);  // face y = 0, normal +y
  return cloud;
}

Pose3 Perturbation(double deg, double metres, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss;
  const Eigen::Vector3d axis = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
  const Eigen::Vector3d dir = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
  Pose3 T = Pose3::Identity();
  T.linear() = Eigen::AngleAxisd(deg * kRadPerDeg, axis).toRotationMatrix();
  T.translation() = metres * dir;
  return T;
}

TEST(Icp, BoxCornerOnTheFloorConvergesFromTwoDegreesAndThreeCentimetres) {
  std::mt19937_64 rng(41);
  for (int trial = 0; trial < 5; ++trial) {
    const Pose3 truth = testing::LookAt(Eigen::Vector3d(1.5, 1.2, 1.0), Eigen::Vector3d(0.0, 0.0, 0.2));
    const pcl::PointCloud<pcl::PointNormal> target = BoxCornerOnFloor(0.01, 0.0, Pose3::Identity());
    // The source samples the same surfaces on another grid, in the camera frame.
    const pcl::PointCloud<pcl::PointNormal> source = BoxCornerOnFloor(0.01, 0.005, truth.inverse());
    const Pose3 initial = truth * Perturbation(2.0, 0.03, rng);
    const IcpResult icp = RefineIcp(source, target, initial, IcpConfig{});
    const double rotation = RotationErrorDeg(icp.T_target_source, truth);
    const double translation = TranslationError(icp.T_target_source, truth);
    std::printf("  trial %d: initial %.2f deg %.1f mm -> %.2e deg %.2e mm, %d iterations, fitness %.2e m^2, %s\n",
                trial, RotationErrorDeg(initial, truth), 1000.0 * TranslationError(initial, truth), rotation,
                1000.0 * translation, icp.iterations, icp.fitness, icp.converged ? "converged" : icp.reason.c_str());
    EXPECT_TRUE(icp.converged) << icp.reason;
    EXPECT_LT(rotation, 0.2) << "rotation error [deg], trial " << trial;
    EXPECT_LT(translation, 0.005) << "translation error [m], trial " << trial;
  }
}

TEST(Icp, NoOverlapKeepsTheInitialPoseAndSaysWhy) {
  const pcl::PointCloud<pcl::PointNormal> target = BoxCornerOnFloor(0.02, 0.0, Pose3::Identity());
  const pcl::PointCloud<pcl::PointNormal> source = BoxCornerOnFloor(0.02, 0.0, Pose3::Identity());
  const Pose3 far_away = MakePoseRpy(0.0, 0.0, 0.0, Eigen::Vector3d(10.0, 0.0, 0.0));
  const IcpResult icp = RefineIcp(source, target, far_away, IcpConfig{});
  EXPECT_FALSE(icp.converged);
  EXPECT_FALSE(icp.reason.empty());
  EXPECT_TRUE(PosesNear(icp.T_target_source, far_away, 1e-12, 1e-12));

  const IcpResult empty = RefineIcp(pcl::PointCloud<pcl::PointNormal>(), target, far_away, IcpConfig{});
  EXPECT_FALSE(empty.converged);
  EXPECT_NE(empty.reason.find("too few points"), std::string::npos) << empty.reason;
}

// ---- Points rebuilt from plane inliers ----

TEST(PlanePoints, EveryStrideThValidInlierProjectedWithThePlaneNormal) {
  Cloud cloud;  // one row of 10 pixels
  DetectedPlane plane;
  plane.plane = Plane::FromPointNormal(Eigen::Vector3d(0.0, 0.0, 2.0), Eigen::Vector3d(0.0, 0.6, -0.8));
  for (int i = 0; i < 10; ++i) {
    pcl::PointXYZRGB p;
    // Off the plane by up to 1 cm; pixel 4 has no depth.
    const Eigen::Vector3d x = Eigen::Vector3d(0.1 * i, 0.0, 2.0) + 0.001 * i * plane.plane.normal;
    p.x = static_cast<float>(x.x()), p.y = static_cast<float>(x.y());
    p.z = i == 4 ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(x.z());
    cloud.push_back(p);
    plane.inliers.push_back(i);
  }
  const auto points = PlanePoints(plane, cloud, 2);  // inliers 0, 2, 4 (invalid), 6, 8
  ASSERT_EQ(points->size(), 4u);
  for (const pcl::PointNormal& p : *points) {
    EXPECT_LT(std::abs(plane.plane.SignedDistance(p.getVector3fMap().cast<double>())), 1e-6) << "distance [m]";
    EXPECT_LT((p.getNormalVector3fMap().cast<double>() - plane.plane.normal).norm(), 1e-6);
  }
  EXPECT_NEAR((*points)[3].x, 0.8, 1e-6) << "the 4th point is inlier 8 [m]";
  EXPECT_THROW(PlanePoints(plane, cloud, 0), std::invalid_argument);
}

// ---- On rendered frames: the paper's pipeline from plane inliers ----

TEST(Icp, RenderedViewsOfTheBoxAlignFromTwoDegreesAndThreeCentimetres) {
  // Two views of the box from near the start pose (2 m away, 1 m up), 10 deg apart in bearing
  // around the box (0.35 m): its sides and top, the floor, lockers and walls.
  const Eigen::Vector3d box = testing::DefaultScene().object("box").T_world_object.translation();
  const auto view = [&](double bearing_deg) {
    const double b = bearing_deg * kRadPerDeg;
    return testing::LookAt(box + Eigen::Vector3d(2.0 * std::cos(b), 2.0 * std::sin(b), 1.0 - box.z()), box);
  };
  const auto segmenter = MakePlaneSegmenter(SegmenterConfig{});
  // The plane points of a rendered frame in its camera frame.
  const auto plane_points = [&](const Pose3& T_world_camera, std::uint64_t seed) {
    const testing::SimFrame sim = testing::RenderDefaultScene(T_world_camera, seed);
    const Cloud::Ptr cloud = MakeOrganizedCloud(sim.frame, testing::XtionCamera(), CloudConfig{});
    pcl::PointCloud<pcl::PointNormal> points;
    for (const DetectedPlane& p : segmenter->Segment(*cloud).planes) points += *PlanePoints(p, *cloud, 4);
    return points;
  };
  std::mt19937_64 rng(51);
  const Pose3 T_world_a = view(175.0), T_world_b = view(185.0);
  pcl::PointCloud<pcl::PointNormal> target;
  pcl::transformPointCloudWithNormals(plane_points(T_world_a, 61), target, T_world_a.matrix().cast<float>());
  const pcl::PointCloud<pcl::PointNormal> source = plane_points(T_world_b, 62);
  const Pose3 initial = T_world_b * Perturbation(2.0, 0.03, rng);
  const IcpResult icp = RefineIcp(source, target, initial, IcpConfig{});
  const double rotation = RotationErrorDeg(icp.T_target_source, T_world_b);
  const double translation = TranslationError(icp.T_target_source, T_world_b);
  std::printf("  views %.2f m apart: initial %.2f deg %.1f mm -> %.3f deg %.2f mm, %d iterations, %s\n",
              TranslationError(T_world_a, T_world_b), RotationErrorDeg(initial, T_world_b),
              1000.0 * TranslationError(initial, T_world_b), rotation, 1000.0 * translation, icp.iterations,
              icp.converged ? "converged" : icp.reason.c_str());
  EXPECT_LT(rotation, 0.2) << "rotation error [deg]";
  EXPECT_LT(translation, 0.005) << "translation error [m]";
}

}  // namespace
}  // namespace planemap
