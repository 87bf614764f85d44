// Step 4 of the frontend: plane graph, trihedral angles, floor, objects aggregated angle by angle.
#include <algorithm>
#include <cstdio>
#include <set>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "planemap/frontend/intersections.h"
#include "planemap/frontend/plane_evaluation.h"
#include "planemap/frontend/plane_graph.h"
#include "planemap/frontend/plane_segmenter.h"
#include "sim_views.h"
#include "test_support.h"

namespace planemap {
namespace {

using testing::DefaultScene;
using testing::Median;
using testing::XtionCamera;

struct Analysed {
  testing::SimFrame sim;
  FrameModel model;
  std::map<int, std::uint16_t> label_of_plane;  // matched detected plane -> true surface label
};

Analysed Analyse(const Pose3& pose, std::uint64_t seed) {
  Analysed a;
  a.sim = testing::RenderDefaultScene(pose, seed);
  const Cloud::Ptr cloud = MakeOrganizedCloud(a.sim.frame, XtionCamera(), CloudConfig{});
  a.model.planes = MakePlaneSegmenter(SegmenterConfig{})->Segment(*cloud).planes;
  a.model.edges = FindIntersections(a.model.planes, *cloud, XtionCamera(), IntersectionConfig{});
  BuildPlaneGraph(*cloud, PlaneGraphConfig{}, &a.model);
  std::vector<bool> valid(cloud->size());
  for (size_t i = 0; i < cloud->size(); ++i) valid[i] = IsValidPoint((*cloud)[i]);
  // Each plane's owner: the surface most of its inliers see.
  for (const DetectedPlane& p : a.model.planes) {
    std::map<std::uint16_t, int> votes;
    for (int i : p.inliers) ++votes[a.sim.labels.pixels()[i]];
    const auto best = std::max_element(votes.begin(), votes.end(),
                                       [](const auto& x, const auto& y) { return x.second < y.second; });
    if (best != votes.end() && best->first != 0) a.label_of_plane[p.id] = best->first;
  }
  return a;
}

std::string Owner(const Analysed& a, int plane) {
  const auto it = a.label_of_plane.find(plane);
  return it == a.label_of_plane.end() ? "?" : DefaultScene().surface(it->second).object;
}

TEST(PlaneGraph, FloorBoxObjectAndCornersFromViewsShowingThreeFaces) {
  int floors = 0, box_objects = 0, views = 0;
  std::vector<double> corner_error;
  const std::vector<Pose3> poses = testing::BoxViewpoints();
  for (size_t k = 0; k < poses.size(); ++k) {
    const Analysed a = Analyse(poses[k], 500 + k);
    ++views;
    if (a.model.floor >= 0 && Owner(a, a.model.floor) == "floor") ++floors;
    // Exactly one object holds the box's faces, and only box faces.
    int objects_with_box = 0;
    for (const FrameObject& o : a.model.objects) {
      std::set<std::string> owners;
      for (int p : o.planes) owners.insert(Owner(a, p));
      if (!owners.count("box")) continue;
      ++objects_with_box;
      if (owners.size() != 1u) {
        std::string all;
        for (const auto& s : owners) all += s + " ";
        ADD_FAILURE() << "view " << k << ": the box's object also holds " << all;
      }
      EXPECT_GE(o.planes.size(), 2u);
      // Its corners against the corner of the three true planes.
      for (int i : o.angles) {
        const TrihedralAngle& angle = a.model.angles[i];
        Eigen::Matrix3d N;
        Eigen::Vector3d d;
        bool known = true;
        for (int r = 0; r < 3; ++r) {
          const auto it = a.label_of_plane.find(angle.planes[r]);
          if (it == a.label_of_plane.end()) { known = false; break; }
          const Plane& truth = a.sim.planes_camera.at(it->second);
          N.row(r) = truth.normal.transpose();
          d[r] = -truth.offset;
        }
        if (known) corner_error.push_back((N.partialPivLu().solve(d) - angle.corner).norm());
      }
    }
    box_objects += objects_with_box == 1;
    if (objects_with_box != 1) std::printf("view %zu: %d objects hold the box\n", k, objects_with_box);
  }
  std::printf("%d views: floor found in %d, the box is one object in %d; %zu box corners, error median %.1f mm\n",
              views, floors, box_objects, corner_error.size(), 1000 * Median(corner_error));
  EXPECT_GE(views, 30);
  EXPECT_EQ(floors, views);
  EXPECT_GE(box_objects, 0.95 * views);
  ASSERT_GE(corner_error.size(), 30u);
  EXPECT_LE(Median(corner_error), 0.015) << "m";
}

TEST(PlaneGraph, OpenLockerIsTwoAnglesSharingTheFloorBackEdge) {
  // Fig. 2: locker 1, open at the front, shows floor-back-left and floor-back-right. From the
  // start pose (3.2 m) its inner sides are too narrow and oblique for the segmenter; 2 m in
  // front of it, on its axis, at the Nao's head height, they are found.
  const sim::SceneObject& locker = DefaultScene().object("locker1");
  const Eigen::Vector3d front = locker.T_world_object.linear().col(0);
  const Eigen::Vector3d base = locker.T_world_object.translation() - Eigen::Vector3d(0, 0, 0.6);
  const Pose3 pose = testing::LookAt(base + 2.0 * front + Eigen::Vector3d(0, 0, 0.52), base + Eigen::Vector3d(0, 0, 0.3));
  const Analysed a = Analyse(pose, 7);
  bool found = false;
  for (const FrameObject& o : a.model.objects) {
    std::set<std::string> owners;
    for (int p : o.planes) owners.insert(Owner(a, p));
    if (!owners.count("locker1")) continue;
    found = true;
    EXPECT_EQ(owners.size(), 1u);
    EXPECT_EQ(o.angles.size(), 2u);
    EXPECT_EQ(o.planes.size(), 3u) << "back, left and right inner faces";
    if (o.angles.size() == 2) {
      // The shared edge joins the floor and the back panel.
      const auto& p0 = a.model.angles[o.angles[0]].planes;
      const auto& p1 = a.model.angles[o.angles[1]].planes;
      std::vector<int> shared;
      std::set_intersection(p0.begin(), p0.end(), p1.begin(), p1.end(), std::back_inserter(shared));
      ASSERT_EQ(shared.size(), 2u);
      EXPECT_TRUE(std::count(shared.begin(), shared.end(), a.model.floor) == 1);
    }
  }
  EXPECT_TRUE(found) << "locker1 is an object";

}

TEST(PlaneGraph, SingleWallOrFloorGivesNoAngleAndNoObject) {
  // Looking straight at a bare stretch of the east wall, and straight down at the floor.
  for (const Pose3& pose : {testing::LookAt({3.5, -2.0, 1.2}, {4.5, -2.0, 1.2}), testing::LookAt({0.5, -2.0, 1.5}, {0.52, -2.0, 0.0})}) {
    const Analysed a = Analyse(pose, 3);
    EXPECT_GE(a.model.planes.size(), 1u);
    EXPECT_TRUE(a.model.angles.empty());
    EXPECT_TRUE(a.model.objects.empty());
  }
}

// Faces in pieces (FindFaces) on hand-made planes: a front (z = 1 m) and, above it, two ledges
// of a top 25 cm apart along the front's top edge, 4 deg apart, and a third top plane whose edge
// with the front runs right beside the first ledge's (a rounded corner, across from it).
struct Pieces {
  Cloud cloud;
  FrameModel model;
  // A plane through points at z = 1 + slope * (y - 0.1) above y = 0.1 over x in [x0, x1] (a ledge
  // going back from the front's top edge), with its edge with the front (plane 0).
  void AddLedge(double x0, double x1, double slope, bool convex) {
    DetectedPlane p;
    p.id = static_cast<int>(model.planes.size());
    for (double x = x0; x <= x1 + 1e-9; x += 0.005) {
      for (double depth = 0.0; depth <= 0.03; depth += 0.005) {
        pcl::PointXYZRGB q;
        q.x = static_cast<float>(x), q.y = static_cast<float>(0.1 - slope * depth), q.z = static_cast<float>(1.0 + depth);
        p.inliers.push_back(static_cast<int>(cloud.size()));
        cloud.push_back(q);
      }
    }
    p = FitDetectedPlane(cloud, p.inliers);
    p.id = static_cast<int>(model.planes.size());
    model.planes.push_back(p);
    PlaneEdge e;
    e.plane_a = 0, e.plane_b = p.id;
    e.start = Eigen::Vector3d(x0, 0.1, 1.0), e.end = Eigen::Vector3d(x1, 0.1, 1.0);
    e.direction = Eigen::Vector3d::UnitX(), e.length = x1 - x0, e.convex = convex;
    model.edges.push_back(e);
    model.structure.push_back(false);
  }
  Pieces() {
    DetectedPlane front;  // z = 1 m, facing the camera
    for (double x = -0.2; x <= 0.2; x += 0.01) {
      for (double y = 0.1; y <= 0.3; y += 0.01) {
        pcl::PointXYZRGB q;
        q.x = static_cast<float>(x), q.y = static_cast<float>(y), q.z = 1.0f;
        front.inliers.push_back(static_cast<int>(cloud.size()));
        cloud.push_back(q);
      }
    }
    front = FitDetectedPlane(cloud, front.inliers);
    front.id = 0;
    model.planes.push_back(front);
    model.structure.push_back(false);
  }
};

TEST(PlaneGraph, NearParallelPlanesMeetingAThirdSideBySideArePiecesOfOneFace) {
  Pieces side_by_side;
  side_by_side.AddLedge(-0.15, -0.10, std::tan(2.0 * M_PI / 180.0), true);
  side_by_side.AddLedge(0.10, 0.15, std::tan(-2.0 * M_PI / 180.0), true);
  FindFaces(side_by_side.cloud, PlaneGraphConfig{}, &side_by_side.model);
  EXPECT_EQ(side_by_side.model.FaceOf(2), 1);
  EXPECT_EQ(side_by_side.model.FaceOf(0), 0);
  // The face's plane, fitted to both, lies between the two: 2 deg from each.
  const Plane& face = side_by_side.model.FacePlane(1);
  EXPECT_NEAR(NormalAngle(face, side_by_side.model.planes[1].plane) * 180 / M_PI, 2.0, 0.3) << "deg";
  EXPECT_NEAR(NormalAngle(face, side_by_side.model.planes[2].plane) * 180 / M_PI, 2.0, 0.3) << "deg";

  // Off, and planes more than face_piece_max_angle_deg apart (12 deg), stay apart.
  PlaneGraphConfig off;
  off.face_piece_max_angle_deg = 0.0;
  FindFaces(side_by_side.cloud, off, &side_by_side.model);
  EXPECT_EQ(side_by_side.model.FaceOf(2), 2);
  Pieces steep;
  steep.AddLedge(-0.15, -0.10, std::tan(6.0 * M_PI / 180.0), true);
  steep.AddLedge(0.10, 0.15, std::tan(-6.0 * M_PI / 180.0), true);
  FindFaces(steep.cloud, PlaneGraphConfig{}, &steep.model);
  EXPECT_EQ(steep.model.FaceOf(2), 2);

  // Across: the second meets the front along the same stretch as the first (a rounded corner
  // beside a face's own edge), so it is no piece of it.
  Pieces across;
  across.AddLedge(-0.15, -0.05, std::tan(2.0 * M_PI / 180.0), true);
  across.AddLedge(-0.14, -0.06, std::tan(-2.0 * M_PI / 180.0), true);
  FindFaces(across.cloud, PlaneGraphConfig{}, &across.model);
  EXPECT_EQ(across.model.FaceOf(2), 2);

  // Concave edges (two objects standing on the third plane) make one face only side by side with
  // at most face_piece_max_gap between them.
  Pieces apart, touching;
  apart.AddLedge(-0.15, -0.10, 0.0, false);
  apart.AddLedge(0.10, 0.15, 0.0, false);
  touching.AddLedge(-0.15, -0.01, 0.0, false);
  touching.AddLedge(0.0, 0.15, 0.0, false);
  FindFaces(apart.cloud, PlaneGraphConfig{}, &apart.model);
  FindFaces(touching.cloud, PlaneGraphConfig{}, &touching.model);
  EXPECT_EQ(apart.model.FaceOf(2), 2);
  EXPECT_EQ(touching.model.FaceOf(2), 1);
}

}  // namespace
}  // namespace planemap
