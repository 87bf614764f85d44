// Back-end factors and parameter blocks: residuals vanish at the truth, Jacobians agree with
// numeric differentiation on the manifolds (ceres::GradientChecker), the manifolds satisfy
// Ceres's invariants, the whitened residual of a plane fit from noisy points is chi-square with 3
// degrees of freedom, and a pose solved from plane observations is the true one.
#include <cmath>
#include <random>

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

#include "planemap/core/detected_plane.h"
#include "planemap/factors/box_contact_factor.h"
#include "planemap/factors/box_face_factor.h"
#include "planemap/factors/edge_length_factor.h"
#include "planemap/factors/object_center_factor.h"
#include "planemap/factors/parameters.h"
#include "planemap/factors/plane_observation_factor.h"
#include "planemap/factors/relative_pose_factor.h"
#include "planemap/factors/structure_factor.h"
#include "test_support.h"

// Ceres's invariant matchers are written to be used inside its namespace.
namespace ceres {
void ExpectManifoldInvariants(const Manifold& manifold, const Vector& x, const Vector& delta, const Vector& y) {
  EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, 1e-9);
}
}  // namespace ceres

namespace planemap {
namespace {

constexpr double kMinStd = 1e-9;  // [rad, m]: no floor to speak of in these tests

Pose3 RandomPose(std::mt19937_64& rng, double max_translation) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
  return MakePose(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI * u(rng), axis)),
                  max_translation * Eigen::Vector3d(u(rng), u(rng), u(rng)));
}

Plane RandomPlane(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return Plane{Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized(), 3.0 * u(rng)};
}

// A 1 x 1 m patch of the plane `camera` (camera frame) around its point nearest the origin's
// projection, 400 points with depth-like noise of `sigma` [m] along the normal, fit by FitPlane.
PlaneFit NoisyFit(const Plane& camera, double sigma, std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, sigma);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  const Eigen::Vector3d centre = -camera.offset * camera.normal;
  const Eigen::Vector3d a = camera.normal.unitOrthogonal(), b = camera.normal.cross(a);
  PointMoments moments;
  for (int i = 0; i < 400; ++i) moments.Add(centre + u(rng) * a + u(rng) * b + noise(rng) * camera.normal);
  PlaneFit fit = FitPlane(moments);
  if (fit.plane.normal.dot(camera.normal) < 0.0) fit.plane = fit.plane.Flipped();
  return fit;
}

TEST(Manifolds, PoseAndPlaneManifoldsSatisfyCeresInvariants) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 0.3);
  const PoseManifold pose_manifold;
  const PlaneManifold plane_manifold;
  for (int trial = 0; trial < 10; ++trial) {
    const PoseBlock x = ToBlock(RandomPose(rng, 2.0)), y = ToBlock(RandomPose(rng, 2.0));
    const Eigen::Map<const Eigen::Matrix<double, 7, 1>> xv(x.data()), yv(y.data());
    const Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::NullaryExpr([&] { return n(rng); });
    ceres::ExpectManifoldInvariants(pose_manifold, xv, delta, yv);
    const PlaneBlock p = ToBlock(RandomPlane(rng)), q = ToBlock(RandomPlane(rng));
    const Eigen::Map<const Eigen::Vector4d> pv(p.data()), qv(q.data());
    const Eigen::Vector3d plane_delta = Eigen::Vector3d::NullaryExpr([&] { return n(rng); });
    ceres::ExpectManifoldInvariants(plane_manifold, pv, plane_delta, qv);
  }
}

TEST(PlaneObservationFactor, ResidualIsZeroAtTheTruth) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose3 T_W_C = RandomPose(rng, 3.0);
    const Plane world = RandomPlane(rng);
    const Plane camera = TransformPlane(T_W_C.inverse(), world);
    const PlaneFit fit = NoisyFit(camera, 0.005, rng);  // only its covariance is used here
    const PlaneObservationFactor factor(camera, fit.covariance, kMinStd);
    const PoseBlock pose = ToBlock(T_W_C);
    const PlaneBlock plane = ToBlock(world);
    Eigen::Vector3d residual;
    ASSERT_TRUE(factor(pose.data(), plane.data(), residual.data()));
    EXPECT_LT(residual.norm(), 1e-6) << "whitened (unit: standard deviations)";
  }
}

TEST(PlaneObservationFactor, JacobiansPassTheGradientCheckerOnTheManifolds) {
  std::mt19937_64 rng(7);
  const PoseManifold pose_manifold;
  const PlaneManifold plane_manifold;
  const std::vector<const ceres::Manifold*> manifolds{&pose_manifold, &plane_manifold};
  for (int trial = 0; trial < 10; ++trial) {
    const Pose3 T_W_C = RandomPose(rng, 3.0);
    const Plane observed = TransformPlane(T_W_C.inverse(), RandomPlane(rng));
    const PlaneFit fit = NoisyFit(observed, 0.01, rng);
    std::unique_ptr<ceres::CostFunction> cost(PlaneObservationFactor::Create(fit.plane, fit.covariance, 1e-4));
    // At a random point, not the truth: the checker compares away from the minimum too.
    const PoseBlock pose = ToBlock(RandomPose(rng, 3.0));
    const PlaneBlock plane = ToBlock(RandomPlane(rng));
    const double* parameters[] = {pose.data(), plane.data()};
    ceres::NumericDiffOptions options;
    ceres::GradientChecker checker(cost.get(), &manifolds, options);
    // No ProbeResults of our own: its Eigen members are allocated inside libceres, and freeing
    // them here breaks under AddressSanitizer (Eigen then assumes a different malloc alignment).
    EXPECT_TRUE(checker.Probe(parameters, 1e-6, nullptr)) << "trial " << trial;
  }
}

TEST(PlaneObservationFactor, WhitenedResidualOfNoisyFitsIsChiSquareWithThreeDegrees) {
  // Planes fit from 400 noisy points (2 cm noise) at the true pose: if the covariance the fit
  // reports is the fit's true scatter and the factor whitens with it, |r|^2 averages 3.
  std::mt19937_64 rng(11);
  double sum = 0.0;
  const int trials = 2000;
  for (int trial = 0; trial < trials; ++trial) {
    const Pose3 T_W_C = RandomPose(rng, 3.0);
    const Plane world = RandomPlane(rng);
    const PlaneFit fit = NoisyFit(TransformPlane(T_W_C.inverse(), world), 0.02, rng);
    const PlaneObservationFactor factor(fit.plane, fit.covariance, kMinStd);
    const PoseBlock pose = ToBlock(T_W_C);
    const PlaneBlock plane = ToBlock(world);
    Eigen::Vector3d residual;
    factor(pose.data(), plane.data(), residual.data());
    sum += residual.squaredNorm();
  }
  const double mean = sum / trials;
  std::printf("mean whitened squared residual over %d fits: %.3f (chi-square, 3 dof: 3)\n", trials, mean);
  // The mean of 2000 chi-square(3) draws has a standard deviation of sqrt(6 / 2000) = 0.055.
  EXPECT_NEAR(mean, 3.0, 0.25);
}

TEST(PlaneObservationFactor, FirstTwoWhitenedRowsAreTheTiltAloneTheThirdTheShiftAtTheCentroid) {
  // The back end reads a block's rows as tilt and shift (backend/src/noise_estimation.h): moving
  // the landmark along its normal leaves the first two rows as they are; tilting it about the
  // inliers' centroid leaves the third as it is, to first order (a fit's tilt and its offset at
  // the centroid are independent); and over noisy fits the first two rows' squares average 2,
  // the third's 1.
  std::mt19937_64 rng(17);
  double tilt_sum = 0.0, shift_sum = 0.0;
  const int trials = 2000;
  for (int trial = 0; trial < trials; ++trial) {
    const Pose3 T_W_C = RandomPose(rng, 3.0);
    const Plane world = RandomPlane(rng);
    const PlaneFit fit = NoisyFit(TransformPlane(T_W_C.inverse(), world), 0.02, rng);
    const PlaneObservationFactor factor(fit.plane, fit.covariance, kMinStd);
    EXPECT_NEAR(factor.sqrt_information()(0, 1), 0.0, 1e-12 * factor.sqrt_information().norm());
    EXPECT_NEAR(factor.sqrt_information()(0, 2), 0.0, 1e-12 * factor.sqrt_information().norm());
    EXPECT_NEAR(factor.sqrt_information()(1, 2), 0.0, 1e-12 * factor.sqrt_information().norm());
    const PoseBlock pose = ToBlock(T_W_C);
    Eigen::Vector3d residual, shifted;
    const PlaneBlock plane = ToBlock(world);
    factor(pose.data(), plane.data(), residual.data());
    const PlaneBlock moved = ToBlock(Plane{world.normal, world.offset + 0.01});
    factor(pose.data(), moved.data(), shifted.data());
    EXPECT_NEAR((shifted - residual).head<2>().norm(), 0.0, 1e-9);
    // From the observed plane itself (residual 0), tilted about the centroid by 0.1 mrad.
    const Plane seen = TransformPlane(T_W_C, fit.plane);
    const Eigen::Vector3d tilted = Eigen::AngleAxisd(1e-4, seen.normal.unitOrthogonal()) * seen.normal;
    const PlaneBlock turned = ToBlock(Plane{tilted, -tilted.dot(T_W_C * fit.centroid)});
    Eigen::Vector3d turned_residual;
    factor(pose.data(), turned.data(), turned_residual.data());
    EXPECT_LT(std::abs(turned_residual[2]), 0.01 * turned_residual.head<2>().norm());
    tilt_sum += residual.head<2>().squaredNorm();
    shift_sum += residual[2] * residual[2];
  }
  // Means of 2000 chi-square draws: standard deviations 0.045 (2 dof) and 0.032 (1 dof).
  EXPECT_NEAR(tilt_sum / trials, 2.0, 0.2);
  EXPECT_NEAR(shift_sum / trials, 1.0, 0.15);
}

TEST(PlaneObservationFactor, PoseFromPlaneObservationsIsTheTrueOne) {
  // Five landmarks fixed, a camera 2 m from them: its pose from their noisy observations with
  // Ceres, from a start 20 cm and 10 deg off.
  std::mt19937_64 rng(13);
  const Pose3 T_W_C = MakePoseRpy(-1.8, 0.1, -1.4, Eigen::Vector3d(0.2, -0.3, 0.5));
  const std::vector<Plane> world{{Eigen::Vector3d::UnitZ(), 0.0},
                                 {-Eigen::Vector3d::UnitX(), 3.0},
                                 {-Eigen::Vector3d::UnitY(), 2.0},
                                 {Eigen::Vector3d(-1.0, -1.0, 0.0).normalized(), 2.5},
                                 {-Eigen::Vector3d::UnitZ(), 2.4}};
  PoseBlock pose = ToBlock(T_W_C * MakePoseRpy(0.1, -0.08, 0.12, Eigen::Vector3d(0.12, -0.1, 0.12)));
  std::vector<PlaneBlock> planes;
  for (const Plane& p : world) planes.push_back(ToBlock(p));
  ceres::Problem problem;
  problem.AddParameterBlock(pose.data(), 7, new PoseManifold);
  for (size_t k = 0; k < world.size(); ++k) {
    const PlaneFit fit = NoisyFit(TransformPlane(T_W_C.inverse(), world[k]), 0.005, rng);
    problem.AddParameterBlock(planes[k].data(), 4, new PlaneManifold);
    problem.SetParameterBlockConstant(planes[k].data());  // the map fixes the pose's gauge here
    problem.AddResidualBlock(PlaneObservationFactor::Create(fit.plane, fit.covariance, 1e-6), nullptr, pose.data(),
                             planes[k].data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  const Pose3 estimate = PoseFromBlock(pose.data());
  std::printf("pose from 5 plane observations: %.2f mm, %.3f deg off (%d iterations)\n",
              1000 * testing::TranslationError(estimate, T_W_C), testing::RotationErrorDeg(estimate, T_W_C),
              static_cast<int>(summary.iterations.size()));
  EXPECT_LT(100 * testing::TranslationError(estimate, T_W_C), 0.5) << "cm";
  EXPECT_LT(testing::RotationErrorDeg(estimate, T_W_C), 0.2) << "deg";
}

TEST(RelativePoseFactor, ResidualIsZeroAtTheTruthWhicheverQuaternionSign) {
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose3 T_W_A = RandomPose(rng, 3.0), T_W_B = RandomPose(rng, 3.0);
    const RelativePoseFactor factor(T_W_A.inverse() * T_W_B, Eigen::Matrix<double, 6, 6>::Identity());
    PoseBlock a = ToBlock(T_W_A), b = ToBlock(T_W_B);
    Eigen::Matrix<double, 6, 1> residual;
    ASSERT_TRUE(factor(a.data(), b.data(), residual.data()));
    EXPECT_LT(residual.norm(), 1e-9);
    for (int k = 0; k < 4; ++k) b[k] = -b[k];  // the same pose
    ASSERT_TRUE(factor(a.data(), b.data(), residual.data()));
    EXPECT_LT(residual.norm(), 1e-9);
  }
}

TEST(RelativePoseFactor, JacobiansPassTheGradientCheckerOnTheManifolds) {
  std::mt19937_64 rng(19);
  const PoseManifold pose_manifold;
  const std::vector<const ceres::Manifold*> two{&pose_manifold, &pose_manifold}, one{&pose_manifold};
  Eigen::Matrix<double, 6, 6> sqrt_information = Eigen::Matrix<double, 6, 6>::Identity();
  sqrt_information.diagonal() << 100, 100, 100, 50, 50, 50;  // 1 cm, 0.02 rad
  for (int trial = 0; trial < 10; ++trial) {
    const Pose3 T_W_A = RandomPose(rng, 3.0), T_W_B = RandomPose(rng, 3.0);
    // Measured near (not at) the truth: the checker compares away from the minimum (but not near
    // a 180 deg error, where taking the short way round makes the residual jump).
    const Pose3 off = MakePoseRpy(0.1, -0.05, 0.2, Eigen::Vector3d(0.1, 0.0, -0.05));
    std::unique_ptr<ceres::CostFunction> relative(RelativePoseFactor::Create(T_W_A.inverse() * T_W_B * off, sqrt_information));
    std::unique_ptr<ceres::CostFunction> prior(PosePriorFactor::Create(T_W_B * off, sqrt_information));
    const PoseBlock a = ToBlock(T_W_A), b = ToBlock(T_W_B);
    const double* both[] = {a.data(), b.data()};
    const double* single[] = {b.data()};
    ceres::NumericDiffOptions options;
    EXPECT_TRUE(ceres::GradientChecker(relative.get(), &two, options).Probe(both, 1e-6, nullptr)) << "trial " << trial;
    EXPECT_TRUE(ceres::GradientChecker(prior.get(), &one, options).Probe(single, 1e-6, nullptr)) << "trial " << trial;
  }
}

TEST(RelativePoseFactor, AChainWithAPriorOnItsFirstPoseSolvesToTheTruth) {
  // Ten poses along a walk, exact relative measurements between neighbours, the first pose held
  // by a prior (the gauge); every pose starts 10 cm and 5 deg off. Solved: the true poses.
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Pose3> truth{MakePoseRpy(-M_PI / 2, 0.0, -M_PI / 2, Eigen::Vector3d(0.0, 0.0, 0.5))};
  for (int k = 1; k < 10; ++k) truth.push_back(truth.back() * MakePoseRpy(0.02 * u(rng), 0.05 * u(rng), 0.02 * u(rng), Eigen::Vector3d(0.02 * u(rng), 0.01 * u(rng), 0.1)));
  std::vector<PoseBlock> blocks;
  for (const Pose3& T : truth) blocks.push_back(ToBlock(T * MakePoseRpy(0.05 * u(rng), 0.05 * u(rng), 0.05 * u(rng), 0.1 * Eigen::Vector3d(u(rng), u(rng), u(rng)))));
  const Eigen::Matrix<double, 6, 6> sqrt_information = 100.0 * Eigen::Matrix<double, 6, 6>::Identity();
  ceres::Problem problem;
  for (PoseBlock& b : blocks) problem.AddParameterBlock(b.data(), 7, new PoseManifold);
  problem.AddResidualBlock(PosePriorFactor::Create(truth[0], sqrt_information), nullptr, blocks[0].data());
  for (size_t k = 1; k < truth.size(); ++k) {
    problem.AddResidualBlock(RelativePoseFactor::Create(truth[k - 1].inverse() * truth[k], sqrt_information), nullptr,
                             blocks[k - 1].data(), blocks[k].data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.function_tolerance = options.gradient_tolerance = options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  for (size_t k = 0; k < truth.size(); ++k) {
    const Pose3 estimate = PoseFromBlock(blocks[k].data());
    EXPECT_LT(1000 * testing::TranslationError(estimate, truth[k]), 0.01) << "mm, pose " << k;
    EXPECT_LT(testing::RotationErrorDeg(estimate, truth[k]), 1e-4) << "deg, pose " << k;
  }
}

// The world plane of a box's face (outward normal), from the box pose and dimensions.
Plane FacePlane(const Pose3& T_W_O, const Eigen::Vector3d& dimensions, int axis, int side) {
  const Eigen::Vector3d n = T_W_O.linear() * (side * Eigen::Vector3d::Unit(axis));
  return Plane{n, -n.dot(T_W_O.translation()) - 0.5 * dimensions[axis]};
}

TEST(BoxFaceFactor, ResidualIsZeroAtTheTruthForEveryFace) {
  std::mt19937_64 rng(29);
  const Eigen::Vector3d dimensions(0.3, 0.4, 0.25);
  for (int trial = 0; trial < 10; ++trial) {
    const Pose3 T_W_O = RandomPose(rng, 3.0), T_W_C = RandomPose(rng, 3.0);
    for (int axis = 0; axis < 3; ++axis) {
      for (int side : {-1, 1}) {
        const Plane observed = TransformPlane(T_W_C.inverse(), FacePlane(T_W_O, dimensions, axis, side));
        const BoxFaceFactor factor(axis, side, observed, NoisyFit(observed, 0.005, rng).covariance, kMinStd);
        const PoseBlock camera = ToBlock(T_W_C), box = ToBlock(T_W_O);
        Eigen::Vector3d residual;
        ASSERT_TRUE(factor(camera.data(), box.data(), dimensions.data(), residual.data()));
        EXPECT_LT(residual.norm(), 1e-6) << "axis " << axis << " side " << side;
      }
    }
  }
}

TEST(BoxFaceFactor, JacobiansPassTheGradientCheckerOnTheManifolds) {
  std::mt19937_64 rng(31);
  const PoseManifold pose_manifold;
  const std::vector<const ceres::Manifold*> manifolds{&pose_manifold, &pose_manifold, nullptr};
  for (int trial = 0; trial < 10; ++trial) {
    const Plane observed = RandomPlane(rng);
    std::unique_ptr<ceres::CostFunction> cost(
        BoxFaceFactor::Create(trial % 3, trial % 2 ? 1 : -1, observed, NoisyFit(observed, 0.01, rng).covariance, 1e-4));
    const PoseBlock camera = ToBlock(RandomPose(rng, 3.0)), box = ToBlock(RandomPose(rng, 3.0));
    const Eigen::Vector3d dimensions(0.2 + 0.1 * trial, 0.3, 0.5);
    const double* parameters[] = {camera.data(), box.data(), dimensions.data()};
    ceres::NumericDiffOptions options;
    EXPECT_TRUE(ceres::GradientChecker(cost.get(), &manifolds, options).Probe(parameters, 1e-6, nullptr)) << "trial " << trial;
  }
}

TEST(BoxFaceFactor, BoxPoseAndDimensionsFromTwoViewsOfItsFaces) {
  // A 30 x 40 x 25 cm box on the floor, turned 30 deg, seen from two opposite corners (its four
  // sides and top, each fit from noisy points), its bottom on the floor the first camera sees.
  // Cameras fixed; the box starts 5 cm and 6 deg off with every dimension 5 cm wrong.
  std::mt19937_64 rng(37);
  const Eigen::Vector3d dimensions(0.30, 0.40, 0.25);
  const Pose3 T_W_O = MakePoseRpy(0.0, 0.0, M_PI / 6, Eigen::Vector3d(2.0, 0.5, 0.125));
  const auto camera_at = [&](const Eigen::Vector3d& offset) {
    const Eigen::Vector3d eye = T_W_O * offset, z = (T_W_O.translation() - eye).normalized();
    const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
    Pose3 T = Pose3::Identity();
    T.linear() << x, z.cross(x), z;
    T.translation() = eye;
    return T;
  };
  const std::vector<Pose3> cameras{camera_at({1.2, 1.0, 0.4}), camera_at({-1.2, -1.0, 0.4})};
  struct Seen { int camera, axis, side; };
  const std::vector<Seen> faces{{0, 0, 1}, {0, 1, 1}, {0, 2, 1}, {1, 0, -1}, {1, 1, -1}, {1, 2, 1}, {0, 2, -1}};
  PoseBlock box = ToBlock(T_W_O * MakePoseRpy(0.02, -0.03, 0.1, Eigen::Vector3d(0.05, -0.04, 0.03)));
  Eigen::Vector3d estimate = dimensions + Eigen::Vector3d(0.05, -0.05, 0.05);
  std::vector<PoseBlock> camera_blocks;
  for (const Pose3& T : cameras) camera_blocks.push_back(ToBlock(T));
  ceres::Problem problem;
  problem.AddParameterBlock(box.data(), 7, new PoseManifold);
  for (PoseBlock& c : camera_blocks) {
    problem.AddParameterBlock(c.data(), 7, new PoseManifold);
    problem.SetParameterBlockConstant(c.data());
  }
  problem.AddParameterBlock(estimate.data(), 3);
  for (int k = 0; k < 3; ++k) problem.SetParameterLowerBound(estimate.data(), k, 0.01);
  for (const Seen& f : faces) {
    // The bottom face is observed as the floor: the same plane, its normal (toward the camera) up.
    const Plane face = FacePlane(T_W_O, dimensions, f.axis, f.side);
    const Plane seen = TransformPlane(cameras[f.camera].inverse(), f.side < 0 && f.axis == 2 ? face.Flipped() : face);
    const PlaneFit fit = NoisyFit(seen, 0.002, rng);
    const Plane observed = f.side < 0 && f.axis == 2 ? fit.plane.Flipped() : fit.plane;
    problem.AddResidualBlock(BoxFaceFactor::Create(f.axis, f.side, observed, fit.covariance, 1e-6), nullptr,
                             camera_blocks[f.camera].data(), box.data(), estimate.data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  const Pose3 solved = PoseFromBlock(box.data());
  std::printf("box from 7 face observations: dimensions %+.2f %+.2f %+.2f mm, centre %.2f mm, axes %.3f deg\n",
              1000 * (estimate.x() - dimensions.x()), 1000 * (estimate.y() - dimensions.y()),
              1000 * (estimate.z() - dimensions.z()), 1000 * testing::TranslationError(solved, T_W_O),
              testing::RotationErrorDeg(solved, T_W_O));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(100 * estimate[k], 100 * dimensions[k], 0.3) << "cm, axis " << k;
  EXPECT_LT(100 * testing::TranslationError(solved, T_W_O), 0.3) << "cm";
  EXPECT_LT(testing::RotationErrorDeg(solved, T_W_O), 0.2) << "deg";
}

TEST(EdgeLengthFactor, ACompleteEdgeMeasuresACutEdgeOnlyBoundsFromBelow) {
  const Eigen::Vector3d dimensions(0.30, 0.40, 0.25);
  double r = 1.0;
  EdgeLengthFactor(1, 0.40, 0.005, true)(dimensions.data(), &r);
  EXPECT_EQ(r, 0.0);  // at the truth
  EdgeLengthFactor(1, 0.41, 0.005, true)(dimensions.data(), &r);
  EXPECT_NEAR(r, 2.0, 1e-9);  // 1 cm long at 5 mm: two standard deviations
  EdgeLengthFactor(1, 0.39, 0.005, true)(dimensions.data(), &r);
  EXPECT_NEAR(r, -2.0, 1e-9);
  EdgeLengthFactor(1, 0.30, 0.005, false)(dimensions.data(), &r);
  EXPECT_EQ(r, 0.0);  // a cut edge 10 cm short says nothing against the dimension
  EdgeLengthFactor(1, 0.41, 0.005, false)(dimensions.data(), &r);
  EXPECT_NEAR(r, 2.0, 1e-9);  // ... but one longer than the dimension does

  // The Jacobian, far from the cut edge's kink (the checker's numeric steps reach centimetres).
  for (bool complete : {true, false}) {
    std::unique_ptr<ceres::CostFunction> cost(EdgeLengthFactor::Create(2, 0.50, 0.005, complete));
    const double* parameters[] = {dimensions.data()};
    ceres::NumericDiffOptions options;
    const std::vector<const ceres::Manifold*> euclidean{nullptr};
    EXPECT_TRUE(ceres::GradientChecker(cost.get(), &euclidean, options).Probe(parameters, 1e-6, nullptr));
  }
}

TEST(EdgeLengthWithBiasFactor, TheBiasAddsToTheDimensionAndJacobiansPassTheGradientChecker) {
  const Eigen::Vector3d dimensions(0.30, 0.40, 0.25), bias(0.002, -0.001, 0.0);
  double residual = 1.0;
  // A complete edge 2 mm longer than s_x is explained by a 2 mm bias: zero residual.
  EdgeLengthWithBiasFactor(0, 0.302, 0.005, true)(dimensions.data(), bias.data(), &residual);
  EXPECT_NEAR(residual, 0.0, 1e-12);
  // Along y the bias is -1 mm: a 0.4 m edge is 1 mm longer than s_y + b_y, 0.2 sigma.
  EdgeLengthWithBiasFactor(1, 0.40, 0.005, true)(dimensions.data(), bias.data(), &residual);
  EXPECT_NEAR(residual, 0.2, 1e-9);
  // A cut edge shorter than s + b bounds nothing.
  EdgeLengthWithBiasFactor(1, 0.35, 0.005, false)(dimensions.data(), bias.data(), &residual);
  EXPECT_EQ(residual, 0.0);
  const std::vector<const ceres::Manifold*> euclidean{nullptr, nullptr};
  for (int axis = 0; axis < 3; ++axis) {
    std::unique_ptr<ceres::CostFunction> cost(EdgeLengthWithBiasFactor::Create(axis, 0.33, 0.005, true));
    const double* parameters[] = {dimensions.data(), bias.data()};
    ceres::NumericDiffOptions options;
    EXPECT_TRUE(ceres::GradientChecker(cost.get(), &euclidean, options).Probe(parameters, 1e-6, nullptr)) << "axis " << axis;
  }
}

TEST(EdgeLengthFactor, DimensionsFromCompleteEdgesAndCutOnesThatBoundThem) {
  // x: 20 complete edges with 5 mm noise -> their mean, within 3 standard errors (3.4 mm);
  // y: only cut edges, the longest 0.38 m -> the dimension rests at that bound;
  // z: a complete edge and a longer cut one -> the cut one's bound wins over the measurement.
  std::mt19937_64 rng(41);
  std::normal_distribution<double> noise(0.0, 0.005);
  Eigen::Vector3d estimate(0.1, 0.1, 0.1);
  ceres::Problem problem;
  double mean_x = 0.0;
  for (int i = 0; i < 20; ++i) {
    const double l = 0.30 + noise(rng);
    mean_x += l / 20;
    problem.AddResidualBlock(EdgeLengthFactor::Create(0, l, 0.005, true), nullptr, estimate.data());
  }
  for (double l : {0.20, 0.35, 0.38}) problem.AddResidualBlock(EdgeLengthFactor::Create(1, l, 0.005, false), nullptr, estimate.data());
  problem.AddResidualBlock(EdgeLengthFactor::Create(2, 0.25, 0.005, true), nullptr, estimate.data());
  problem.AddResidualBlock(EdgeLengthFactor::Create(2, 0.26, 0.001, false), nullptr, estimate.data());
  ceres::Solver::Options options;
  options.function_tolerance = options.gradient_tolerance = options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  EXPECT_NEAR(1000 * estimate.x(), 1000 * mean_x, 1e-3) << "mm";
  EXPECT_NEAR(100 * estimate.x(), 30.0, 0.34) << "cm";
  EXPECT_NEAR(100 * estimate.y(), 38.0, 0.01) << "cm";
  // The two pull against each other weighted 1 : 25: 0.25 + 25 / 26 * 0.01 m.
  EXPECT_NEAR(100 * estimate.z(), 100 * (0.25 + 0.01 * 25.0 / 26.0), 0.01) << "cm";
}

TEST(StructureFactors, ZeroForExactStructureAndJacobiansPassTheGradientChecker) {
  const PlaneBlock floor = ToBlock(Plane{Eigen::Vector3d::UnitZ(), 0.0});
  const PlaneBlock wall = ToBlock(Plane{-Eigen::Vector3d::UnitX(), 3.0});
  const PlaneBlock opposite = ToBlock(Plane{Eigen::Vector3d::UnitX(), -1.0});
  double perpendicular = 1.0;
  Eigen::Vector3d parallel = Eigen::Vector3d::Ones();
  PerpendicularPlanesFactor(0.01)(floor.data(), wall.data(), &perpendicular);
  ParallelPlanesFactor(0.01)(wall.data(), opposite.data(), parallel.data());
  EXPECT_EQ(perpendicular, 0.0);
  EXPECT_LT(parallel.norm(), 1e-12);
  // 1 deg off at sigma 0.01 rad: sin(1 deg) / 0.01 = 1.745.
  const PlaneBlock tilted = ToBlock(Plane{Eigen::Vector3d(-std::cos(M_PI / 180), 0.0, std::sin(M_PI / 180)), 3.0});
  PerpendicularPlanesFactor(0.01)(floor.data(), tilted.data(), &perpendicular);
  EXPECT_NEAR(perpendicular, 1.745, 1e-3);
  ParallelPlanesFactor(0.01)(tilted.data(), opposite.data(), parallel.data());
  EXPECT_NEAR(parallel.norm(), 1.745, 1e-3);

  std::mt19937_64 rng(43);
  const PlaneManifold plane_manifold;
  const std::vector<const ceres::Manifold*> manifolds{&plane_manifold, &plane_manifold};
  for (int trial = 0; trial < 10; ++trial) {
    const PlaneBlock a = ToBlock(RandomPlane(rng)), b = ToBlock(RandomPlane(rng));
    const double* parameters[] = {a.data(), b.data()};
    std::unique_ptr<ceres::CostFunction> perpendicular_cost(PerpendicularPlanesFactor::Create(0.01));
    std::unique_ptr<ceres::CostFunction> parallel_cost(ParallelPlanesFactor::Create(0.01));
    ceres::NumericDiffOptions options;
    EXPECT_TRUE(ceres::GradientChecker(perpendicular_cost.get(), &manifolds, options).Probe(parameters, 1e-6, nullptr));
    EXPECT_TRUE(ceres::GradientChecker(parallel_cost.get(), &manifolds, options).Probe(parameters, 1e-6, nullptr));
  }
}

TEST(StructureFactors, APerpendicularPriorSquaresTwoTiltedFaces) {
  // A box's side and top seen from a fixed camera, each observed tilted by 0.75 deg the other way
  // about their common edge's direction (so 1.5 deg from perpendicular between them), with the
  // covariance of a fit of 400 points with 3 cm noise; with a tight prior (0.1 deg) they meet at
  // 90 deg, each moved toward the other.
  std::mt19937_64 rng(47);
  const Pose3 T_W_C = MakePoseRpy(-1.9, 0.0, -1.57, Eigen::Vector3d(0.0, 0.0, 0.5));
  const std::vector<Plane> truth{{-Eigen::Vector3d::UnitX(), 1.5}, {Eigen::Vector3d::UnitZ(), -0.3}};
  const Eigen::Vector3d edge_point(1.5, 0.0, 0.3);
  std::vector<PlaneBlock> planes;
  ceres::Problem problem;
  PoseBlock camera = ToBlock(T_W_C);
  problem.AddParameterBlock(camera.data(), 7, new PoseManifold);
  problem.SetParameterBlockConstant(camera.data());
  planes.reserve(truth.size());
  std::vector<Plane> observed_world;
  for (size_t k = 0; k < truth.size(); ++k) {
    // Tilted about the edge (the y axis through edge_point).
    Pose3 tilt = Pose3::Identity();
    tilt.linear() = Eigen::AngleAxisd((k == 0 ? 0.75 : -0.75) * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    tilt.translation() = edge_point - tilt.linear() * edge_point;
    observed_world.push_back(TransformPlane(tilt, truth[k]));
    const Plane observed = TransformPlane(T_W_C.inverse(), observed_world.back());
    const PlaneFit fit = NoisyFit(observed, 0.03, rng);  // its covariance only
    planes.push_back(ToBlock(observed_world.back()));
    problem.AddParameterBlock(planes.back().data(), 4, new PlaneManifold);
    problem.AddResidualBlock(PlaneObservationFactor::Create(observed, fit.covariance, 1e-6), nullptr, camera.data(),
                             planes.back().data());
  }
  const double before = std::abs(90.0 - NormalAngle(observed_world[0], observed_world[1]) * 180 / M_PI);
  problem.AddResidualBlock(PerpendicularPlanesFactor::Create(0.1 * M_PI / 180), nullptr, planes[0].data(), planes[1].data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  const Plane a = PlaneFromBlock(planes[0].data()), b = PlaneFromBlock(planes[1].data());
  const double after = std::abs(90.0 - NormalAngle(a, b) * 180 / M_PI);
  std::printf("faces %.3f deg from perpendicular as fit, %.3f deg with the prior\n", before, after);
  EXPECT_NEAR(before, 1.5, 1e-6) << "deg";
  EXPECT_LT(after, 0.1 * before) << "deg";
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT(NormalAngle(k == 0 ? a : b, observed_world[k]) * 180 / M_PI, before) << "deg, plane " << k;
  }
}

TEST(BoxContactFactor, ZeroForABoxOnTheFloorAndJacobiansPassTheGradientChecker) {
  // A 30 x 40 x 25 cm box turned 0.7 rad about z, its centre 12.5 cm above the floor z = 0.
  const Pose3 T_W_O = MakePoseRpy(0.0, 0.0, 0.7, Eigen::Vector3d(1.0, 0.5, 0.125));
  const PoseBlock box = ToBlock(T_W_O);
  const Eigen::Vector3d dimensions(0.3, 0.4, 0.25);
  const PlaneBlock floor = ToBlock(Plane{Eigen::Vector3d::UnitZ(), 0.0});
  const BoxContactFactor factor(0.002, 0.01);
  Eigen::Vector4d residual;
  ASSERT_TRUE(factor(box.data(), dimensions.data(), floor.data(), residual.data()));
  EXPECT_LT(residual.norm(), 1e-12);
  // Lifted 1 cm: 1 cm / 2 mm = 5 sigma on the distance row, nothing on the tilt rows.
  const PoseBlock lifted = ToBlock(MakePoseRpy(0.0, 0.0, 0.7, Eigen::Vector3d(1.0, 0.5, 0.135)));
  factor(lifted.data(), dimensions.data(), floor.data(), residual.data());
  EXPECT_NEAR(residual[3], 5.0, 1e-9);
  EXPECT_LT(residual.head<3>().norm(), 1e-12);
  // Tipped 1 deg: sin(1 deg) / 0.01 rad = 1.745 on the tilt rows.
  const PoseBlock tipped = ToBlock(MakePoseRpy(M_PI / 180, 0.0, 0.7, Eigen::Vector3d(1.0, 0.5, 0.125)));
  factor(tipped.data(), dimensions.data(), floor.data(), residual.data());
  EXPECT_NEAR(residual.head<3>().norm(), 1.745, 1e-3);

  std::mt19937_64 rng(53);
  const PoseManifold pose_manifold;
  const PlaneManifold plane_manifold;
  const std::vector<const ceres::Manifold*> manifolds{&pose_manifold, nullptr, &plane_manifold};
  for (int trial = 0; trial < 10; ++trial) {
    const PoseBlock b = ToBlock(RandomPose(rng, 3.0));
    const PlaneBlock p = ToBlock(RandomPlane(rng));
    const Eigen::Vector3d s(0.2 + 0.05 * trial, 0.3, 0.4);
    const double* parameters[] = {b.data(), s.data(), p.data()};
    std::unique_ptr<ceres::CostFunction> cost(BoxContactFactor::Create(0.002, 0.01));
    ceres::NumericDiffOptions options;
    EXPECT_TRUE(ceres::GradientChecker(cost.get(), &manifolds, options).Probe(parameters, 1e-6, nullptr)) << "trial " << trial;
  }
}

// A 3-row cost function's residual and Jacobians multiplied by a fixed invertible matrix M.
class MixedRows : public ceres::CostFunction {
 public:
  MixedRows(const ceres::CostFunction* inner, const Eigen::Matrix3d& M) : inner_(inner), M_(M) {
    set_num_residuals(3);
    *mutable_parameter_block_sizes() = inner->parameter_block_sizes();
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    if (!inner_->Evaluate(parameters, residuals, jacobians)) return false;
    Eigen::Map<Eigen::Vector3d> r(residuals);
    r = M_ * Eigen::Vector3d(r);
    for (size_t k = 0; jacobians && k < parameter_block_sizes().size(); ++k) {
      if (!jacobians[k]) continue;
      Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> J(jacobians[k], 3, parameter_block_sizes()[k]);
      J = M_ * Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>(J);
    }
    return true;
  }

 private:
  const ceres::CostFunction* inner_;
  const Eigen::Matrix3d M_;
};

TEST(ObjectCenterFactor, ZeroAtTheTruthAndJacobiansPassTheGradientChecker) {
  std::mt19937_64 rng(59);
  const PoseManifold pose_manifold;
  const std::vector<const ceres::Manifold*> manifolds{&pose_manifold, &pose_manifold};
  for (int trial = 0; trial < 10; ++trial) {
    const Pose3 T_W_C = RandomPose(rng, 3.0), T_W_O = RandomPose(rng, 3.0);
    const Eigen::Vector3d center_C = T_W_C.inverse() * T_W_O.translation();
    const PoseBlock camera = ToBlock(T_W_C), box = ToBlock(T_W_O);
    Eigen::Vector3d residual;
    ObjectCenterFactor(center_C, 0.01)(camera.data(), box.data(), residual.data());
    EXPECT_LT(residual.norm(), 1e-9);
    // 2 cm off along the camera's x axis: 2 sigma.
    ObjectCenterFactor(center_C + Eigen::Vector3d(0.02, 0.0, 0.0), 0.01)(camera.data(), box.data(), residual.data());
    EXPECT_NEAR(residual.norm(), 2.0, 1e-9);
    std::unique_ptr<ceres::CostFunction> cost(ObjectCenterFactor::Create(center_C, 0.01));
    // Its Jacobian has structural zeros (d(R c)/dtheta = -[R c]x has a zero diagonal), where the
    // checker's relative test compares two round-off values; mixing the rows by a fixed rotation
    // removes them without changing what is checked.
    MixedRows mixed(cost.get(), Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix());
    const double* parameters[] = {camera.data(), box.data()};
    ceres::NumericDiffOptions options;
    EXPECT_TRUE(ceres::GradientChecker(&mixed, &manifolds, options).Probe(parameters, 1e-6, nullptr)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace planemap
