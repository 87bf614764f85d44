// Step 1 of the frontend: depth to an organized, coloured cloud.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "planemap/frontend/organized_cloud.h"
#include "sim_views.h"
#include "test_support.h"

namespace planemap {
namespace {

using testing::XtionCamera;

TEST(OrganizedCloud, PointsLieOnTheirLabelledPlanes) {
  const testing::SimFrame sim = testing::RenderDefaultScene(testing::BoxViewpoints()[4], 1, /*noise=*/false);
  const Cloud::Ptr cloud = MakeOrganizedCloud(sim.frame, XtionCamera(), CloudConfig{});
  ASSERT_EQ(cloud->width, 640u);
  ASSERT_EQ(cloud->height, 480u);
  EXPECT_FALSE(cloud->is_dense);
  double max_distance = 0.0;
  size_t valid = 0;
  for (size_t i = 0; i < cloud->size(); ++i) {
    const auto& p = (*cloud)[i];
    if (!IsValidPoint(p)) continue;
    ++valid;
    const Plane& plane = sim.planes_camera.at(sim.labels.pixels()[i]);
    max_distance = std::max(max_distance, std::abs(plane.SignedDistance(Eigen::Vector3d(p.x, p.y, p.z))));
  }
  EXPECT_GT(valid, cloud->size() / 2);
  EXPECT_LT(max_distance, 1e-5) << "m (float coordinates)";
  // Colour comes along: pixel (320, 240) has the rendered colour.
  const auto& centre = (*cloud)(320, 240);
  const Rgb8& colour = sim.frame.color.at(320, 240);
  EXPECT_EQ(centre.r, colour[0]);
  EXPECT_EQ(centre.g, colour[1]);
  EXPECT_EQ(centre.b, colour[2]);
}

TEST(OrganizedCloud, InvalidDepthStaysInvalidAndNeverBecomesTheOrigin) {
  RgbdFrame frame;
  frame.depth = DepthImage(640, 480, 2.0f);
  frame.depth.at(0, 0) = 0.0f;
  frame.depth.at(1, 0) = std::numeric_limits<float>::quiet_NaN();
  frame.depth.at(2, 0) = std::numeric_limits<float>::infinity();
  frame.depth.at(3, 0) = -1.0f;
  frame.depth.at(4, 0) = 0.1f;   // nearer than min_depth
  frame.depth.at(5, 0) = 50.0f;  // farther than max_depth
  const Cloud::Ptr cloud = MakeOrganizedCloud(frame, XtionCamera(), CloudConfig{});
  for (int u = 0; u < 6; ++u) {
    const auto& p = (*cloud)(u, 0);
    EXPECT_FALSE(IsValidPoint(p)) << u;
    EXPECT_TRUE(std::isnan(p.x) && std::isnan(p.y) && std::isnan(p.z)) << u;
  }
  int at_origin = 0;
  for (const auto& p : cloud->points) at_origin += IsValidPoint(p) && p.x == 0 && p.y == 0 && p.z == 0;
  EXPECT_EQ(at_origin, 0);
  // A valid pixel back-projects through the pinhole: (u - cx) z / fx.
  const auto& p = (*cloud)(600, 400);
  EXPECT_NEAR(p.x, (600 - XtionCamera().cx) * 2.0 / XtionCamera().fx, 1e-6);
  EXPECT_NEAR(p.y, (400 - XtionCamera().cy) * 2.0 / XtionCamera().fy, 1e-6);
  EXPECT_NEAR(p.z, 2.0, 1e-7);
}

TEST(OrganizedCloud, SizeMismatchIsAnError) {
  RgbdFrame frame;
  frame.index = 7;
  frame.depth = DepthImage(320, 240, 1.0f);
  EXPECT_TRUE(testing::ThrowsWith([&] { MakeOrganizedCloud(frame, XtionCamera(), CloudConfig{}); },
                                  {"frame 7", "320x240", "640x480"}));
}

// The cloud built with AVX2 is the scalar one bit for bit: coordinates, the fourth float, colour,
// and the invalid pixels' NaN; on a frame whose width is not a multiple of four, with and without
// colour, with every kind of invalid depth and depths exactly at the limits.
TEST(OrganizedCloud, WithAvx2IsTheScalarCloud) {
  if (!OrganizedCloudHasAvx2()) GTEST_SKIP() << "this processor has no AVX2";
  CameraIntrinsics camera;
  camera.width = 67, camera.height = 23, camera.fx = 81.3, camera.fy = 79.9, camera.cx = 33.2, camera.cy = 11.7;
  const CloudConfig config;
  RgbdFrame frame;
  frame.depth = DepthImage(camera.width, camera.height, 0.0f);
  frame.color = ColorImage(camera.width, camera.height, Rgb8{0, 0, 0});
  std::mt19937 random(3);
  std::uniform_real_distribution<float> depth(0.0f, 7.0f);
  const float specials[] = {0.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                            -1.0f, static_cast<float>(config.min_depth), static_cast<float>(config.max_depth)};
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const int k = static_cast<int>(random() % 10);
      frame.depth.at(u, v) = k < 6 ? specials[k] : depth(random);
      frame.color.at(u, v) = Rgb8{static_cast<std::uint8_t>(random()), static_cast<std::uint8_t>(random()),
                                  static_cast<std::uint8_t>(random())};
    }
  }
  for (const bool with_color : {true, false}) {
    if (!with_color) frame.color = ColorImage();
    const Cloud::Ptr scalar = MakeOrganizedCloud(frame, camera, config, false);
    const Cloud::Ptr avx2 = MakeOrganizedCloud(frame, camera, config, true);
    ASSERT_EQ(scalar->size(), avx2->size());
    int valid = 0;
    for (size_t i = 0; i < scalar->size(); ++i) {
      const pcl::PointXYZRGB &a = (*scalar)[i], &b = (*avx2)[i];
      ASSERT_EQ(std::memcmp(a.data, b.data, sizeof(a.data)), 0) << "pixel " << i << ": " << a << " vs " << b;
      ASSERT_EQ(a.rgba, b.rgba) << "pixel " << i;
      valid += IsValidPoint(a);
    }
    EXPECT_GT(valid, 0);
    EXPECT_LT(valid, static_cast<int>(scalar->size()));
  }
}

}  // namespace
}  // namespace planemap
