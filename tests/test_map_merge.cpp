// Merging maps (paper Fig. 4): a known transform between two maps of one synthetic room is
// recovered, landmarks of one surface fused, each merged edge the longest of its pair, the box
// re-aggregated from the merged graph and re-classified; two halves of a rendered walk, tracked
// into maps with different worlds, merge into one map whose box matches the scene.
#include <cmath>
#include <cstdio>
#include <functional>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "planemap/frontend/map_merge.h"
#include "planemap/io/plane_map_io.h"
#include "planemap/sim/scene.h"
#include "test_support.h"
#include "tracked_walk.h"

namespace planemap {
namespace {

using testing::kBoxTop;
using testing::kBoxX;
using testing::kBoxY;
using testing::kFloor;
using testing::kWallX;
using testing::Rectangle;
using testing::RoomEdge;
using testing::SourcePath;
using testing::SyntheticRoom;

constexpr double kRadToDeg = 180.0 / M_PI;

// The frontend's default graph and object settings, the shipped patterns.
ObjectModel Objects() {
  ObjectModel model;
  model.patterns = LoadPatterns(SourcePath("configs/patterns.yaml"));
  return model;
}

double MergedLength(const PlaneMap& map, int a, int b) {
  const int k = map.EdgeBetween(a, b);
  return k < 0 ? -1.0 : map.edges[k].length;
}

TEST(MapMerge, RebuildsTheBoxFromTheGraph) {
  PlaneMap map = SyntheticRoom();
  RebuildObjects(Objects(), 0.25, &map);
  ASSERT_EQ(map.objects.size(), 1u);
  const MapObject& box = map.objects[0];
  EXPECT_EQ(box.label, "box");
  EXPECT_EQ(box.landmarks, (std::vector<int>{kBoxX, kBoxY, kBoxTop}));
  // The largest vertical face (-x, 0.4 x 0.3 m) gives the x axis: its dimensions, in cm.
  EXPECT_NEAR(100 * box.dimensions.x(), 30.0, 0.1);
  EXPECT_NEAR(100 * box.dimensions.y(), 40.0, 0.1);
  EXPECT_NEAR(100 * box.dimensions.z(), 30.0, 0.1);
  EXPECT_LT(100 * (box.center - Eigen::Vector3d(1.5, 0.3, 0.15)).norm(), 0.1) << "cm";
  EXPECT_LT(std::acos(std::abs(box.axes.col(2).z())) * kRadToDeg, 0.01) << "deg";
}

TEST(MapMerge, RecoversAKnownTransformFusesSurfacesAndKeepsTheLongestEdge) {
  const PlaneMap target = SyntheticRoom();
  // The source: the same room seen by a second run whose world is the target's moved by D, with
  // one edge seen longer there (the box's top edge) and one seen shorter (its vertical edge).
  const Pose3 D = MakePoseRpy(2.0 / kRadToDeg, -1.0 / kRadToDeg, 6.0 / kRadToDeg, Eigen::Vector3d(0.15, -0.10, 0.03));
  PlaneMap source = SyntheticRoom();
  source.edges[target.EdgeBetween(kBoxX, kBoxY)].end.z() = 0.25;
  source.edges[target.EdgeBetween(kBoxX, kBoxY)].length = 0.25;
  PlaneMap shorter = target;
  shorter.edges[target.EdgeBetween(kBoxX, kBoxTop)].end.y() -= 0.05;
  shorter.edges[target.EdgeBetween(kBoxX, kBoxTop)].length -= 0.05;
  TransformMap(D, &source);

  const MapMergeResult r = MergeMaps(shorter, source, Pose3::Identity(), MapMergeConfig{}, Objects());
  ASSERT_TRUE(r.ok) << r.reason;
  const Pose3 error = D * r.T_target_source;  // T_target_source should be D^-1
  std::printf("recovered transform: error %.3f mm, %.4f deg; %d candidates, %d inliers, icp %d, %d landmarks fused\n",
              1000 * error.translation().norm(), RotationAngle(error.linear()) * kRadToDeg, r.candidates, r.inliers,
              r.refined, r.fused);
  EXPECT_LT(1000 * error.translation().norm(), 1.0) << "mm";
  EXPECT_LT(RotationAngle(error.linear()) * kRadToDeg, 0.05) << "deg";
  // Every surface is in both maps: each pair is fused into one landmark, at its true plane.
  EXPECT_EQ(r.fused, 6);
  ASSERT_EQ(r.map.landmarks.size(), 6u);
  for (int k = 0; k < 6; ++k) {
    EXPECT_LT(NormalAngle(r.map.landmarks[k].plane, target.landmarks[k].plane) * kRadToDeg, 0.05) << k;
    EXPECT_NEAR(100 * r.map.landmarks[k].plane.offset, 100 * target.landmarks[k].plane.offset, 0.1) << "cm, " << k;
    EXPECT_EQ(r.map.landmarks[k].observations, 2);
  }
  // Each merged edge is the longest of its pair: 0.4 m from the source, 0.3 m from the target.
  EXPECT_EQ(r.map.edges.size(), target.edges.size());
  EXPECT_NEAR(100 * MergedLength(r.map, kBoxX, kBoxTop), 40.0, 0.1) << "cm";
  EXPECT_NEAR(100 * MergedLength(r.map, kBoxX, kBoxY), 30.0, 0.1) << "cm";
  // The objects re-aggregated from the merged graph and re-classified: one box, true size.
  ASSERT_EQ(r.map.objects.size(), 1u);
  EXPECT_EQ(r.map.objects[0].label, "box");
  EXPECT_NEAR(100 * r.map.objects[0].dimensions.y(), 40.0, 0.1) << "cm";
  EXPECT_LT(100 * (r.map.objects[0].center - Eigen::Vector3d(1.5, 0.3, 0.15)).norm(), 0.1) << "cm";
  EXPECT_EQ(r.map.keyframes.size(), 2u);
}

TEST(MapMerge, FusesASurfaceAddedTwiceAndRenumbersEdges) {
  // The far wall added a second time, 1 cm off and turned by 0.5 deg (a tracker that missed it).
  PlaneMap twice = SyntheticRoom();
  const double a = 0.5 / kRadToDeg;
  const PlaneLandmark again = Rectangle(static_cast<int>(twice.landmarks.size()), {3.01, 0.0, 1.2}, Eigen::Vector3d::UnitZ(), 1.2,
                                        {-std::sin(a), std::cos(a), 0.0}, 2.0);
  twice.landmarks.push_back(again);
  twice.edges.push_back(RoomEdge(kFloor, again.id, {3.0, -2.0, 0.0}, {3.0, 2.5, 0.0}, false, false));  // seen longer
  EXPECT_EQ(FuseDuplicateLandmarks(MapMergeConfig{}, &twice), 1);
  ASSERT_EQ(twice.landmarks.size(), 6u);
  EXPECT_EQ(twice.landmarks[kWallX].observations, 2);
  // The fused wall from all its points: between the two.
  EXPECT_NEAR(100 * twice.landmarks[kWallX].plane.offset, 300.5, 0.3) << "cm";
  EXPECT_NEAR(MergedLength(twice, kFloor, kWallX), 4.5, 1e-9);
  EXPECT_EQ(twice.edges.size(), SyntheticRoom().edges.size());
  // Surfaces apart stay apart: the box's faces, the floor and the walls are not fused.
  PlaneMap room = SyntheticRoom();
  EXPECT_EQ(FuseDuplicateLandmarks(MapMergeConfig{}, &room), 0);
}

TEST(MapMerge, MapsThatShareNoStructureAreNotMergedAndSayWhy) {
  const PlaneMap target = SyntheticRoom();
  PlaneMap source;
  source.landmarks.push_back(target.landmarks[kFloor]);  // only a floor: the pose is not fixed
  const MapMergeResult r = MergeMaps(target, source, Pose3::Identity(), MapMergeConfig{}, Objects());
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.reason.empty());
  std::printf("reason: %s\n", r.reason.c_str());
  EXPECT_EQ(r.map.landmarks.size(), target.landmarks.size());
  EXPECT_FALSE(MergeMaps(target, PlaneMap{}, Pose3::Identity(), MapMergeConfig{}, Objects()).ok);
}

TEST(MapMerge, AnObjectTheGraphDoesNotFormIsKeptOnceWithBothMapsEvidence) {
  // A far object whose faces neither map kept (no landmarks), seen twice in each map, its centre
  // 4 cm apart between them: after the merge it is one object seen 4 times, centred between.
  const auto with_far_object = [](const Eigen::Vector3d& centre) {
    PlaneMap map = SyntheticRoom();
    MapObject far;
    far.id = 0;
    far.label = "unknown";
    far.center = centre;
    far.dimensions = Eigen::Vector3d(0.0, 0.3, 0.0);
    far.observations = far.partial_center_count = 2;
    far.partial_center_sum = 2 * centre;
    map.objects.push_back(far);
    return map;
  };
  const MapMergeResult r = MergeMaps(with_far_object({2.5, -1.5, 0.2}), with_far_object({2.5, -1.46, 0.2}), Pose3::Identity(),
                                     MapMergeConfig{}, Objects());
  ASSERT_TRUE(r.ok) << r.reason;
  int far = 0;
  for (const MapObject& o : r.map.objects) {
    if (o.label != "unknown") continue;
    ++far;
    EXPECT_EQ(o.observations, 4);
    EXPECT_LT(100 * (o.center - Eigen::Vector3d(2.5, -1.48, 0.2)).norm(), 0.1) << "cm";
    EXPECT_NEAR(100 * o.dimensions.y(), 30.0, 0.1) << "cm";
  }
  EXPECT_EQ(far, 1);
  EXPECT_EQ(r.map.objects.size(), 2u);  // and the box rebuilt from the graph
}

// An upright box seen whole (centre, axes, dimensions), for the object tests below.
MapObject Box(int id, const Eigen::Vector3d& centre, const Eigen::Vector3d& dimensions, double yaw_deg, int views) {
  MapObject o;
  o.id = id;
  o.label = "box";
  o.axes = Eigen::AngleAxisd(yaw_deg / kRadToDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  o.dimensions = dimensions;
  o.dimension_complete = {true, true, true};
  o.complete_count = {views, views, views};
  o.complete_sum = views * dimensions;
  o.center = centre;
  o.center_count = o.partial_center_count = o.observations = views;
  o.center_sum = o.partial_center_sum = views * centre;
  o.label_votes = {{"box", views}};
  return o;
}

TEST(CuboidOverlap, AQuarterTurnAShiftAndNeighbours) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d quarter = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d box(0.4, 0.2, 0.3), c(1.0, 2.0, 0.15);
  // The same box, its axes a quarter turn apart (x and y swapped): all of it.
  EXPECT_NEAR(CuboidOverlap(c, I, box, c, quarter, Eigen::Vector3d(0.2, 0.4, 0.3)), 1.0, 1e-12);
  // Shifted by a quarter of its length: three quarters.
  EXPECT_NEAR(CuboidOverlap(c, I, box, c + Eigen::Vector3d(0.1, 0, 0), I, box), 0.75, 1e-12);
  // A partial view (half its length, lower bound) inside it: all of the smaller.
  EXPECT_NEAR(CuboidOverlap(c, I, box, c - Eigen::Vector3d(0.1, 0, 0), I, Eigen::Vector3d(0.2, 0.2, 0.3)), 1.0, 1e-12);
  // A neighbour standing against it: nothing.
  EXPECT_NEAR(CuboidOverlap(c, I, box, c + Eigen::Vector3d(0.4, 0, 0), I, box), 0.0, 1e-12);
}

TEST(MapMerge, ABoxMappedTwiceIsFoldedNeighboursAreNot) {
  PlaneMap map;
  map.objects = {Box(0, {1.0, 2.0, 0.15}, {0.4, 0.2, 0.3}, 0.0, 10),
                 Box(1, {1.03, 2.01, 0.15}, {0.2, 0.4, 0.3}, 90.5, 5),  // the same box, axes named the other way
                 Box(2, {1.45, 2.0, 0.15}, {0.4, 0.2, 0.3}, 0.0, 8)};    // its neighbour, 5 cm apart
  EXPECT_EQ(FuseDuplicateObjects(MapMergeConfig{}, &map), 1);
  ASSERT_EQ(map.objects.size(), 2u);
  const MapObject& box = map.objects[0];
  EXPECT_EQ(box.observations, 15);
  EXPECT_EQ(box.id, 0);
  EXPECT_EQ(map.objects[1].id, 1);
  // Centre: the mean of the 15 views; dimensions along its own axes.
  EXPECT_NEAR(100 * box.center.x(), 101.0, 0.01) << "cm";
  EXPECT_NEAR(100 * box.dimensions.x(), 40.0, 0.01) << "cm";
  EXPECT_NEAR(100 * box.dimensions.y(), 20.0, 0.01) << "cm";
  EXPECT_NEAR(100 * map.objects[1].center.x(), 145.0, 1e-9) << "cm";
}

TEST(MapMerge, AnObjectMarkedAsRoomStructureIsDroppedNotFoldedIntoTheBoxItOverlaps) {
  // A room corner's two walls, taken for a "locker" 1 m deep before the map knew them for walls
  // (MapObject::structure), and the box standing in that corner inside its cuboid.
  PlaneMap map;
  map.objects = {Box(0, {-1.9, -0.9, 0.3}, {0.9, 1.1, 0.6}, 0.0, 114), Box(1, {-1.5, -0.6, 0.13}, {0.17, 0.37, 0.25}, 15.0, 700)};
  map.objects[0].structure = true;
  EXPECT_EQ(FuseDuplicateObjects(MapMergeConfig{}, &map), 0);
  ASSERT_EQ(map.objects.size(), 1u);
  EXPECT_EQ(map.objects[0].id, 0);
  EXPECT_EQ(map.objects[0].observations, 700);
  EXPECT_NEAR(100 * map.objects[0].center.x(), -150.0, 1e-9) << "cm";
  EXPECT_NEAR(100 * map.objects[0].dimensions.y(), 37.0, 1e-9) << "cm";
}

TEST(MapJson, RoundTripKeepsWhatAMergeNeeds) {
  PlaneMap map = SyntheticRoom();
  RebuildObjects(Objects(), 0.25, &map);
  map.objects[0].label_votes = {{"box", 12}, {"locker", 1}};
  map.objects[0].complete_count = {3, 2, 1};
  map.objects[0].complete_sum = Eigen::Vector3d(0.9, 0.8, 0.3);
  map.objects[0].structure = true;
  testing::TempDir dir;
  const PlaneMap back = ReadPlaneMapJson(dir.Write("map.json", PlaneMapJson(map)));
  ASSERT_EQ(back.landmarks.size(), map.landmarks.size());
  for (size_t k = 0; k < map.landmarks.size(); ++k) {
    const PlaneLandmark &a = map.landmarks[k], &b = back.landmarks[k];
    EXPECT_LT(NormalAngle(a.plane, b.plane), 1e-9);
    EXPECT_NEAR(a.plane.offset, b.plane.offset, 1e-12);
    EXPECT_NEAR(a.moments.w, b.moments.w, 1e-9);
    EXPECT_LT((a.moments.sum_outer - b.moments.sum_outer).norm(), 1e-9);
    ASSERT_EQ(a.points.size(), b.points.size());
    for (size_t i = 0; i < a.points.size(); ++i) EXPECT_LT((a.points[i] - b.points[i]).norm(), 1e-4) << "m";
    EXPECT_EQ(a.floor_votes, b.floor_votes);
  }
  ASSERT_EQ(back.edges.size(), map.edges.size());
  for (size_t k = 0; k < map.edges.size(); ++k) {
    EXPECT_EQ(back.edges[k].landmark_a, map.edges[k].landmark_a);
    EXPECT_NEAR(back.edges[k].length, map.edges[k].length, 1e-12);
    EXPECT_EQ(back.edges[k].Convex(), map.edges[k].Convex());
  }
  ASSERT_EQ(back.objects.size(), 1u);
  EXPECT_EQ(back.objects[0].landmarks, map.objects[0].landmarks);
  EXPECT_EQ(back.objects[0].label_votes, map.objects[0].label_votes);
  EXPECT_EQ(back.objects[0].complete_count, map.objects[0].complete_count);
  EXPECT_EQ(back.objects[0].grasp_landmark, map.objects[0].grasp_landmark);
  EXPECT_TRUE(back.objects[0].structure);
  EXPECT_LT((back.objects[0].center - map.objects[0].center).norm(), 1e-12);
  ASSERT_EQ(back.keyframes.size(), 1u);
  EXPECT_LT(testing::TranslationError(back.keyframes[0].T_world_camera, map.keyframes[0].T_world_camera), 1e-12);
  EXPECT_LT(testing::RotationErrorDeg(back.keyframes[0].T_world_camera, map.keyframes[0].T_world_camera), 1e-6);
}

// Values that parse but are no map: each was read as given before (a zero axis, a negative size;
// an id past 2^32 read as 0, which named another plane).
TEST(MapJson, ImpossibleValuesAreErrorsNamingTheField) {
  PlaneMap map = SyntheticRoom();
  RebuildObjects(Objects(), 0.25, &map);
  const nlohmann::json good = nlohmann::json::parse(PlaneMapJson(map));
  testing::TempDir dir;
  const auto read_with = [&](const std::function<void(nlohmann::json&)>& change) {
    nlohmann::json j = good;
    change(j);
    const std::string file = dir.Write("bad.json", j.dump());
    return [file] { ReadPlaneMapJson(file); };
  };
  EXPECT_TRUE(testing::ThrowsWith(read_with([](nlohmann::json& j) { j["objects"][0]["axes"][1] = {0.0, 0.0, 0.0}; }),
                                  {"objects[0].axes[1]", "expected a unit vector"}));
  EXPECT_TRUE(testing::ThrowsWith(read_with([](nlohmann::json& j) { j["objects"][0]["axes"][1] = j["objects"][0]["axes"][0]; }),
                                  {"objects[0].axes", "three perpendicular unit vectors"}));
  EXPECT_TRUE(testing::ThrowsWith(read_with([](nlohmann::json& j) { j["objects"][0]["dimensions"][2] = -0.3; }),
                                  {"objects[0].dimensions", "sizes >= 0"}));
  EXPECT_TRUE(testing::ThrowsWith(read_with([](nlohmann::json& j) { j["objects"][0]["planes"][0] = 4294967296ULL; }),
                                  {"objects[0].planes[0]", "fits in 32 bits", "4294967296"}));
  EXPECT_NO_THROW(read_with([](nlohmann::json&) {})());
}

TEST(MapMerge, TwoHalvesOfARenderedWalkMergeIntoOneMap) {
  // The default walk's first 110 frames in the scene's world, its last 100 (from frame 90) in a
  // world moved by D, as a second run started elsewhere would be; merged with no guess.
  const sim::Scene scene = sim::LoadScene(SourcePath("configs/scenes/default.yaml"));
  const std::vector<double> waypoints{-0.7, -1.3, 1.95, -1.3, 2.03, -0.546};
  const Pose3 D = MakePoseRpy(1.0 / kRadToDeg, 0.5 / kRadToDeg, 5.0 / kRadToDeg, Eigen::Vector3d(0.12, -0.08, 0.02));
  const testing::TrackedRun first = testing::TrackWalk(scene, waypoints, 11, 0, 110);
  const testing::TrackedRun second = testing::TrackWalk(scene, waypoints, 11, 90, 190, D);
  ASSERT_FALSE(second.estimate.empty());

  const MapMergeResult r = MergeMaps(first.map, second.map, Pose3::Identity(), MapMergeConfig{}, Objects());
  ASSERT_TRUE(r.ok) << r.reason;
  const Pose3 error = D * r.T_target_source;
  std::printf("halves: maps of %zu and %zu planes -> %zu (%d fused); transform error %.1f mm, %.2f deg; %d candidates, "
              "%d inliers, icp %d; %zu objects\n",
              first.map.landmarks.size(), second.map.landmarks.size(), r.map.landmarks.size(), r.fused,
              1000 * error.translation().norm(), RotationAngle(error.linear()) * kRadToDeg, r.candidates, r.inliers,
              r.refined, r.map.objects.size());
  EXPECT_LT(100 * error.translation().norm(), 1.0) << "cm";
  EXPECT_LT(RotationAngle(error.linear()) * kRadToDeg, 0.5) << "deg";
  EXPECT_LT(r.map.landmarks.size(), first.map.landmarks.size() + second.map.landmarks.size());

  // The box, in the scene's world (the first map's): the class, size and axis against the scene.
  const std::vector<ObjectError> errors = EvaluateObjects(sim::ObjectTruths(scene), MapObjectEstimates(r.map), EvalConfig{});
  bool checked = false;
  for (const ObjectError& e : errors) {
    if (!e.found()) continue;
    const MapObject& o = r.map.objects[e.estimate];
    std::printf("  %s: merged map %s, centre %.1f mm, dimensions %+.1f %+.1f %+.1f mm, axis %.2f deg\n", e.name.c_str(),
                o.label.c_str(), 1000 * e.center_error, 1000 * e.dimension_error.x(), 1000 * e.dimension_error.y(),
                1000 * e.dimension_error.z(), e.axis_error_deg);
    if (e.name != "box") continue;
    checked = true;
    EXPECT_EQ(o.label, "box");
    for (int k = 0; k < 3; ++k) EXPECT_LE(100 * std::abs(e.dimension_error[k]), 1.0) << "cm, axis " << k;
    EXPECT_LE(100 * e.center_error, 1.5) << "cm";
    EXPECT_LE(e.axis_error_deg, 2.0) << "deg";
  }
  EXPECT_TRUE(checked) << "the box is in the merged map";
}

}  // namespace
}  // namespace planemap
