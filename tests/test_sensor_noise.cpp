// The structured-light noise model, measured on rendered frames against its own parameters.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "planemap/core/intrinsics.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"
#include "planemap/sim/walk.h"
#include "test_support.h"

namespace planemap::sim {
namespace {

using planemap::testing::SourcePath;
using planemap::testing::TempDir;

constexpr double kRadToDeg = 180.0 / M_PI;

// A large wall at x = 5 facing -x, and the floor.
Scene WallScene(const TempDir& dir) {
  return LoadScene(dir.Write("wall.yaml",
                             "name: wall\n"
                             "floor: {center: [0, 0], size: [12, 12]}\n"
                             "walls:\n"
                             "  - {name: wall, from: [5, 6], to: [5, -6], height: 6}\n"));
}

// Camera at height 1.5 m looking along +x, square to the wall, `distance` metres from it.
Pose3 FacingWall(double distance) {
  Pose3 T = Pose3::Identity();
  T.linear() = RotationBodyFromOptical();
  T.translation() = Eigen::Vector3d(5.0 - distance, 0.0, 1.5);
  return T;
}

// The start of the default walk: box and lockers stand out against the floor and walls.
Pose3 StartPose() { return LoadTrajectory(SourcePath("configs/walks/default.yaml")).front().T_world_camera; }

CameraIntrinsics Camera() { return LoadCameraIntrinsics(SourcePath("configs/cameras/xtion_nao.yaml")); }

RenderConfig WithNoise(const SensorNoiseConfig& noise) {
  RenderConfig config;
  config.noise = noise;
  return config;
}

struct ErrorStats {
  double mean = 0.0, std = 0.0;
  size_t count = 0;
};

// Statistics of (noisy - exact) over pixels that keep a reading.
ErrorStats MeasureError(const RenderedFrame& noisy, const RenderedFrame& exact) {
  double sum = 0.0, sum2 = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < noisy.depth.size(); ++i) {
    const float z = noisy.depth.pixels()[i];
    if (!IsValidDepth(z) || !IsValidDepth(exact.depth.pixels()[i])) continue;
    const double e = static_cast<double>(z) - exact.depth.pixels()[i];
    sum += e;
    sum2 += e * e;
    ++n;
  }
  ErrorStats s;
  s.count = n;
  s.mean = sum / n;
  s.std = std::sqrt(sum2 / n - s.mean * s.mean);
  return s;
}

class NoiseAtDistance : public ::testing::TestWithParam<std::tuple<double, bool>> {};

TEST_P(NoiseAtDistance, MeasuredStandardDeviationMatchesTheModel) {
  const auto [distance, quantization] = GetParam();
  TempDir dir;
  SensorNoiseConfig noise = SensorNoiseConfig::None();
  noise.gaussian = true;
  noise.quantization = quantization;
  const VirtualCamera camera(WallScene(dir), Camera(), WithNoise(noise));
  const Pose3 pose = FacingWall(distance);
  const ErrorStats stats = MeasureError(camera.Render(pose, 42), camera.RenderExact(pose));
  const double expected = noise.ExpectedDepthStd(distance);
  std::printf("depth %.0f m, quantisation %s: measured std %.2f mm, model %.2f mm (%+.1f%%), bias %+.3f mm, %zu px\n",
              distance, quantization ? "on " : "off", stats.std * 1000, expected * 1000,
              100.0 * (stats.std / expected - 1.0), stats.mean * 1000, stats.count);
  EXPECT_GT(stats.count, 250000u);  // the wall fills the view
  EXPECT_NEAR(stats.std, expected, 0.10 * expected) << "depth " << distance << " m, std in m";
  EXPECT_LT(std::abs(stats.mean), 0.1 * expected) << "bias in m";
  // sigma grows with z^2: 1.425 mm at 1 m for the Kinect v1 coefficient, before quantisation.
  EXPECT_NEAR(noise.sigma_coefficient * distance * distance * 1000.0, 1.425 * distance * distance, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(OneTwoThreeMetres, NoiseAtDistance,
                         ::testing::Combine(::testing::Values(1.0, 2.0, 3.0), ::testing::Bool()));

TEST(SensorNoise, QuantizationStepIsThatOfTheKinectDisparity) {
  const SensorNoiseConfig noise;
  // z^2 * (1/8 px) / (580 px * 0.075 m): 2.9 mm at 1 m, 25.9 mm at 3 m.
  EXPECT_NEAR(noise.QuantizationStep(1.0) * 1000.0, 2.87, 0.01);
  EXPECT_NEAR(noise.QuantizationStep(3.0) * 1000.0, 25.86, 0.01);
}

TEST(SensorNoise, GrazingDropoutsFollowTheConfiguredRamp) {
  TempDir dir;
  SensorNoiseConfig noise = SensorNoiseConfig::None();
  noise.grazing_dropout = true;
  const CameraIntrinsics intrinsics = Camera();
  const VirtualCamera camera(WallScene(dir), intrinsics, WithNoise(noise));
  // Low above the floor, looking nearly level: the floor is seen at 60-89 degrees incidence.
  Pose3 pose = FacingWall(4.5);
  pose.translation().z() = 0.3;
  const RenderedFrame exact = camera.RenderExact(pose);
  const RenderedFrame noisy = camera.Render(pose, 7);
  // Bins of incidence angle [deg] -> pixels, dropped pixels.
  std::map<int, std::pair<int, int>> bins;
  for (int v = 0; v < intrinsics.height; ++v) {
    for (int u = 0; u < intrinsics.width; ++u) {
      if (exact.labels.at(u, v) != 1) continue;  // the floor
      const Eigen::Vector3d ray = pose.linear() * intrinsics.Ray(u, v);
      const double angle = std::acos(std::abs(ray.normalized().z())) * kRadToDeg;
      auto& bin = bins[static_cast<int>(std::floor(angle))];
      ++bin.first;
      if (!IsValidDepth(noisy.depth.at(u, v))) ++bin.second;
    }
  }
  for (const auto& [degree, counts] : bins) {
    if (counts.first < 2000) continue;
    const double expected = std::clamp((degree + 0.5 - 78.0) / 10.0, 0.0, 1.0);
    EXPECT_NEAR(static_cast<double>(counts.second) / counts.first, expected, 0.05) << degree << " deg";
  }
  EXPECT_EQ(bins[70].second, 0) << "no dropout well below the start angle";
}

TEST(SensorNoise, DropoutsAtDepthDiscontinuities) {
  SensorNoiseConfig noise = SensorNoiseConfig::None();
  noise.edge_dropout = true;
  const CameraIntrinsics intrinsics = Camera();
  const VirtualCamera camera(LoadScene(SourcePath("configs/scenes/default.yaml")), intrinsics, WithNoise(noise));
  const Pose3 pose = StartPose();
  const RenderedFrame exact = camera.RenderExact(pose);
  const RenderedFrame noisy = camera.Render(pose, 11);
  int at_edge = 0, dropped_at_edge = 0, away = 0, dropped_away = 0;
  for (int v = 3; v < intrinsics.height - 4; ++v) {
    for (int u = 3; u < intrinsics.width - 4; ++u) {
      const float z = exact.depth.at(u, v);
      if (!IsValidDepth(z)) continue;
      // Largest jump to a 4-neighbour, and whether any pixel within 3 px jumps at all.
      float jump = 0.0f;
      for (auto [du, dv] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        jump = std::max(jump, std::abs(exact.depth.at(u + du, v + dv) - z));
      }
      bool quiet = true;
      for (int dv = -3; dv <= 3 && quiet; ++dv) {
        for (int du = -3; du <= 3 && quiet; ++du) {
          const float here = exact.depth.at(u + du, v + dv);
          quiet = std::abs(here - exact.depth.at(u + du + 1, v + dv)) < 0.02 &&
                  std::abs(here - exact.depth.at(u + du, v + dv + 1)) < 0.02;
        }
      }
      const bool dropped = !IsValidDepth(noisy.depth.at(u, v));
      if (jump > 0.2f) { ++at_edge; dropped_at_edge += dropped; }
      if (quiet) { ++away; dropped_away += dropped; }
    }
  }
  ASSERT_GT(at_edge, 500);
  EXPECT_NEAR(static_cast<double>(dropped_at_edge) / at_edge, noise.edge_dropout_probability, 0.05);
  EXPECT_EQ(dropped_away, 0) << "of " << away << " pixels away from any discontinuity";
}

TEST(SensorNoise, RandomDropoutRateAndWorkingRange) {
  TempDir dir;
  SensorNoiseConfig noise = SensorNoiseConfig::None();
  noise.random_dropout_probability = 0.05;
  const VirtualCamera camera(WallScene(dir), Camera(), WithNoise(noise));
  const RenderedFrame frame = camera.Render(FacingWall(2.0), 3);
  size_t dropped = 0;
  for (float z : frame.depth.pixels()) dropped += !IsValidDepth(z);
  EXPECT_NEAR(static_cast<double>(dropped) / frame.depth.size(), 0.05, 0.005);
  // Closer than min_depth (0.4 m): nothing.
  const RenderedFrame close = camera.Render(FacingWall(0.3), 3);
  for (float z : close.depth.pixels()) ASSERT_EQ(z, 0.0f);
}

TEST(SensorNoise, SameSeedSameFrameOtherSeedOtherNoise) {
  const VirtualCamera camera(LoadScene(SourcePath("configs/scenes/default.yaml")), Camera(), RenderConfig{});
  const Pose3 pose = StartPose();
  const RenderedFrame a = camera.Render(pose, camera.FrameSeed(5));
  const RenderedFrame b = camera.Render(pose, camera.FrameSeed(5));
  const RenderedFrame c = camera.Render(pose, camera.FrameSeed(6));
  EXPECT_TRUE(a.depth == b.depth);
  EXPECT_FALSE(a.depth == c.depth);
  EXPECT_TRUE(a.labels == c.labels);  // labels are ground truth, untouched by noise
  EXPECT_NE(camera.FrameSeed(5), camera.FrameSeed(6));
}

TEST(SensorNoise, MotionBlurVoidsReadingsAcrossMovingEdgesAndBlendsColour) {
  SensorNoiseConfig noise = SensorNoiseConfig::None();
  noise.motion_blur = true;
  const CameraIntrinsics intrinsics = Camera();
  const VirtualCamera camera(LoadScene(SourcePath("configs/scenes/default.yaml")), intrinsics, WithNoise(noise));
  const Pose3 end = StartPose();
  // Turning at 90 deg/s during a 20 ms exposure: 1.8 deg, about 18 px of smear.
  const Pose3 start = end * Eigen::AngleAxisd(1.8 * M_PI / 180.0, Eigen::Vector3d::UnitY());
  const RenderedFrame sharp = camera.Render(end, 1);
  const RenderedFrame blurred = camera.Render(end, 1, start);
  size_t sharp_valid = 0, blurred_valid = 0, blended = 0;
  for (size_t i = 0; i < sharp.depth.size(); ++i) {
    sharp_valid += IsValidDepth(sharp.depth.pixels()[i]);
    blurred_valid += IsValidDepth(blurred.depth.pixels()[i]);
    blended += sharp.color.pixels()[i] != blurred.color.pixels()[i];
  }
  EXPECT_LT(blurred_valid, sharp_valid - 2000);
  EXPECT_GT(blended, 2000u);
  // Where depth survives, it is the depth at the frame's pose.
  for (size_t i = 0; i < sharp.depth.size(); ++i) {
    if (IsValidDepth(blurred.depth.pixels()[i])) {
      ASSERT_EQ(blurred.depth.pixels()[i], sharp.depth.pixels()[i]);
    }
  }
}

}  // namespace
}  // namespace planemap::sim
