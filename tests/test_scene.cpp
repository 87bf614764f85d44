// Scene files: the default layout of the paper's Fig. 2 and every kind of bad input.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "planemap/core/error.h"
#include "planemap/sim/scene.h"
#include "test_support.h"

namespace planemap::sim {
namespace {

using planemap::testing::SourcePath;
using planemap::testing::TempDir;
using planemap::testing::ThrowsWith;

constexpr double kRadToDeg = 180.0 / M_PI;

TEST(Scene, DefaultSceneHasTheLayoutOfFig2) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/default.yaml"));
  EXPECT_EQ(scene.name, "fig2");
  ASSERT_EQ(scene.objects.size(), 3u);
  const SceneObject& box = scene.object("box");
  EXPECT_EQ(box.type, "box");
  EXPECT_NEAR(box.dimensions.x(), 0.25, 1e-12);
  EXPECT_NEAR(box.dimensions.y(), 0.35, 1e-12);
  EXPECT_NEAR(box.dimensions.z(), 0.25, 1e-12);
  // The box stands on the floor: its bottom face lies in the floor plane z = 0.
  EXPECT_NEAR(box.T_world_object.translation().z() - box.dimensions.z() / 2, 0.0, 1e-12);
  EXPECT_EQ(scene.object("locker1").type, "open_locker");
  EXPECT_EQ(scene.object("locker1").cuboids.size(), 4u);  // back, left, right, top panels
  EXPECT_EQ(scene.object("locker2").cuboids.size(), 1u);
  // Floor + 4 walls + 6 faces for each of 1 + 4 + 1 cuboids.
  EXPECT_EQ(scene.surfaces.size(), 5u + 6u * 6u);
  EXPECT_EQ(scene.markers.size(), 3u);
  for (size_t i = 0; i < scene.surfaces.size(); ++i) EXPECT_EQ(scene.surfaces[i].label, i + 1);
}

TEST(Scene, EveryShippedSceneLoadsWithABoxToGraspOnTheFloor) {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(SourcePath("configs/scenes"))) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const Scene scene = LoadScene(entry.path().string());
    ++scenes;
    EXPECT_FALSE(scene.surfaces.empty());
    int boxes = 0;
    for (const SceneObject& o : scene.objects) {
      if (o.type != "box") continue;
      ++boxes;
      EXPECT_NEAR(o.Center().z(), o.dimensions.z() / 2.0, 1e-9);  // standing on the floor
    }
    EXPECT_GE(boxes, 1);
    // A room the robot is sent into names the box it is sent for (the office is a mapping scene).
    if (entry.path().stem() != "office") {
      EXPECT_NE(scene.task_object, "");
    }
  }
  EXPECT_GE(scenes, 18);  // default, office, storeroom, lab, hall, workshop, corridor, garage, studio, loft, atelier,
                          // hideout, gallery, cellar, pantry, foyer, scullery, vestibule
}

TEST(Scene, SurfacesAreConsistentRectangles) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/default.yaml"));
  for (const Surface& s : scene.surfaces) {
    SCOPED_TRACE(s.object + " " + s.part + " " + s.face);
    EXPECT_NEAR(s.plane_world.normal.norm(), 1.0, 1e-12);
    EXPECT_NEAR(s.axis_u.dot(s.axis_v), 0.0, 1e-12);
    EXPECT_NEAR((s.axis_u.cross(s.axis_v) - s.plane_world.normal).norm(), 0.0, 1e-12);
    EXPECT_NEAR(s.plane_world.SignedDistance(s.center_world), 0.0, 1e-12);
    EXPECT_GT(s.half_u, 0.0);
    EXPECT_GT(s.half_v, 0.0);
  }
}

TEST(Scene, BoxFacesPointOutOfTheBoxAndMatchItsDimensions) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/default.yaml"));
  const SceneObject& box = scene.object("box");
  const Cuboid& cuboid = scene.cuboids[box.cuboids[0]];
  const Eigen::Vector3d center = cuboid.T_world_box.translation();
  for (int f = 0; f < 6; ++f) {
    const Surface& s = scene.surface(cuboid.face_labels[f]);
    EXPECT_EQ(s.face, kFaceNames[f]);
    // The centre is inside: at minus half the dimension along the face normal.
    EXPECT_NEAR(s.plane_world.SignedDistance(center), -cuboid.dimensions[f / 2] / 2, 1e-12);
  }
  // The top face is horizontal, at the box height.
  const Surface& top = scene.surface(cuboid.face_labels[4]);
  EXPECT_NEAR(top.plane_world.normal.z(), 1.0, 1e-12);
  EXPECT_NEAR(-top.plane_world.offset, 0.25, 1e-12);
}

TEST(Scene, WallNormalsFaceIntoTheRoomAndWallsAreVertical) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/default.yaml"));
  const Eigen::Vector3d room_center(1.75, 0.0, 1.0);
  int walls = 0;
  for (const Surface& s : scene.surfaces) {
    if (s.object.rfind("wall", 0) != 0) continue;
    ++walls;
    EXPECT_GT(s.plane_world.SignedDistance(room_center), 2.0) << s.object;
    EXPECT_NEAR(std::asin(std::abs(s.plane_world.normal.z())) * kRadToDeg, 0.0, 1e-9) << s.object;
  }
  EXPECT_EQ(walls, 4);
}

TEST(Scene, OpenLockerShowsItsInsideTowardTheFront) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/default.yaml"));
  const SceneObject& locker = scene.object("locker1");
  const Eigen::Vector3d front = locker.T_world_object.linear().col(0);
  // The back panel's inner face (+x) faces the opening; the side panels' inner faces face each other.
  const Surface* back_inner = nullptr;
  const Surface* left_inner = nullptr;
  const Surface* right_inner = nullptr;
  for (const Surface& s : scene.surfaces) {
    if (s.object != "locker1") continue;
    if (s.part == "back" && s.face == "+x") back_inner = &s;
    if (s.part == "left" && s.face == "-y") left_inner = &s;
    if (s.part == "right" && s.face == "+y") right_inner = &s;
  }
  ASSERT_TRUE(back_inner && left_inner && right_inner);
  EXPECT_NEAR(back_inner->plane_world.normal.dot(front), 1.0, 1e-12);
  EXPECT_NEAR(left_inner->plane_world.normal.dot(right_inner->plane_world.normal), -1.0, 1e-12);
  // Inner width = width - 2 x panel thickness = 0.76 m.
  EXPECT_NEAR(std::abs(left_inner->plane_world.SignedDistance(right_inner->center_world)), 0.76, 1e-12);
}

TEST(Scene, GroundTruthListsObjectsAndSurfaces) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/default.yaml"));
  const YAML::Node gt = SceneGroundTruth(scene);
  ASSERT_EQ(gt["objects"].size(), 3u);
  ASSERT_EQ(gt["surfaces"].size(), scene.surfaces.size());
  EXPECT_NEAR(gt["objects"][0]["dimensions"][1].as<double>(), 0.35, 1e-12);
  EXPECT_NEAR(gt["surfaces"][0]["normal"][2].as<double>(), 1.0, 1e-12);  // the floor
}

TEST(Scene, FurnitureIsBuiltFromItsPartsInItsOwnFrame) {
  const Scene scene = LoadScene(SourcePath("configs/scenes/office.yaml"));
  const SceneObject& shelf = scene.object("shelf");
  EXPECT_EQ(shelf.type, "furniture");
  ASSERT_EQ(shelf.cuboids.size(), 5u);
  // Bounding box of the parts: 0.35 deep, 0.80 wide (sides at +-0.39 +- 0.01), 1.0 high.
  EXPECT_NEAR(shelf.dimensions.x(), 0.35, 1e-12);
  EXPECT_NEAR(shelf.dimensions.y(), 0.80, 1e-12);
  EXPECT_NEAR(shelf.dimensions.z(), 1.00, 1e-12);
  // The middle board's top face is 0.51 m above the floor, horizontal, facing up.
  for (const Surface& s : scene.surfaces) {
    if (s.object == "shelf" && s.part == "middle" && s.face == "+z") {
      EXPECT_NEAR(s.plane_world.normal.z(), 1.0, 1e-12);
      EXPECT_NEAR(-s.plane_world.offset, 0.51, 1e-12);
    }
  }
  // The desk's legs stand on the floor; its top is 0.735 m high.
  const SceneObject& desk = scene.object("desk");
  EXPECT_NEAR(desk.dimensions.z(), 0.735, 1e-12);
  // Its centre is its bounding box's, half its height up, not its frame's origin on the floor.
  EXPECT_NEAR(desk.Center().z(), 0.735 / 2, 1e-12);
  EXPECT_NEAR((desk.Center() - desk.T_world_object.translation()).head<2>().norm(), 0.0, 1e-12);
  EXPECT_NEAR(scene.object("box").Center().z(), scene.object("box").T_world_object.translation().z(), 1e-12);
  for (size_t index : desk.cuboids) {
    const Cuboid& c = scene.cuboids[index];
    EXPECT_GE(c.T_world_box.translation().z() - c.dimensions.z() / 2, -1e-12);
  }
  // Per-face colours of the box.
  for (const Surface& s : scene.surfaces) {
    if (s.object == "box" && s.face == "+x") {
      EXPECT_EQ(s.color, (Rgb8{200, 60, 50}));
    }
    if (s.object == "box" && s.face == "-z") {
      EXPECT_EQ(s.color, (Rgb8{120, 120, 120}));
    }
  }
}

// A minimal valid scene, with `extra` appended to the object's map.
std::string SceneWithObject(const std::string& extra) {
  return "name: t\n"
         "floor: {center: [0, 0], size: [4, 4]}\n"
         "objects:\n"
         "  - name: b\n"
         "    position: [1, 0, 0.1]\n"
         "    dimensions: [0.2, 0.2, 0.2]\n" + extra;
}

TEST(Scene, BadInputNamesFileLineAndKey) {
  TempDir dir;
  EXPECT_NO_THROW(LoadScene(dir.Write("ok.yaml", SceneWithObject(""))));
  const std::string unknown_type = dir.Write("type.yaml", SceneWithObject("    type: sphere\n"));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(unknown_type); }, {unknown_type + ":4", "unknown object type 'sphere'"}));
  const std::string typo = dir.Write("typo.yaml", SceneWithObject("    colour: [1, 2, 3]\n"));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(typo); }, {typo + ":7", "unknown key 'objects[0].colour'"}));
  const std::string negative = dir.Write("neg.yaml", SceneWithObject("").replace(
      SceneWithObject("").find("[0.2, 0.2, 0.2]"), 15, "[0.2, -0.2, 0.2]"));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(negative); }, {negative + ":6", "dimensions", "must be > 0"}));
  const std::string two_dims = dir.Write("two.yaml", "name: t\nobjects:\n  - {name: b, position: [0, 0, 0], dimensions: [1, 2]}\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(two_dims); }, {two_dims + ":3", "dimensions needs 3 numbers"}));
  const std::string duplicate = dir.Write(
      "dup.yaml", SceneWithObject("  - {name: b, position: [2, 0, 0.1], dimensions: [0.2, 0.2, 0.2]}\n"));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(duplicate); }, {duplicate + ":7", "duplicate name 'b'"}));
  const std::string bad_marker = dir.Write(
      "marker.yaml", SceneWithObject("markers:\n  - {id: 3, on: nothing, face: '+z'}\n"));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(bad_marker); }, {bad_marker + ":8", "no surface 'nothing'"}));
  const std::string bad_dict = dir.Write(
      "dict.yaml", SceneWithObject("markers:\n  - {id: 3, dictionary: DICT_9X9, on: floor}\n"));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(bad_dict); }, {bad_dict + ":8", "unknown ArUco dictionary 'DICT_9X9'"}));
  const std::string bad_id = dir.Write(
      "id.yaml", SceneWithObject("markers:\n  - {id: 50, dictionary: DICT_4X4_50, on: floor}\n"));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(bad_id); }, {bad_id + ":8", "50 is not in DICT_4X4_50"}));
  const std::string thick = dir.Write("thick.yaml", SceneWithObject("    type: open_locker\n    panel_thickness: 0.15\n"));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(thick); }, {thick + ":4", "panel_thickness"}));
  const std::string no_parts = dir.Write("noparts.yaml", "objects:\n  - {name: f, type: furniture, position: [0, 0, 0]}\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(no_parts); }, {no_parts + ":2", "furniture needs 'parts'"}));
  const std::string bad_part = dir.Write(
      "badpart.yaml",
      "objects:\n  - name: f\n    type: furniture\n    position: [0, 0, 0]\n    parts:\n"
      "      - {name: a, dimensions: [1, 1]}\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(bad_part); }, {bad_part + ":2", "parts[0].dimensions needs 3 numbers"}));
  const std::string part_typo = dir.Write(
      "parttypo.yaml",
      "objects:\n  - name: f\n    type: furniture\n    position: [0, 0, 0]\n    parts:\n"
      "      - {name: a, dimension: [1, 1, 1]}\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(part_typo); }, {part_typo + ":6", "unknown key 'objects[0].parts[0].dimension'"}));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(dir.File("missing.yaml")); }, {dir.File("missing.yaml"), "cannot open"}));
  // The task names one of the scene's boxes.
  const std::string no_such = dir.Write("task.yaml", "task: {object: parcel}\n" + SceneWithObject(""));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(no_such); }, {no_such + ":1", "task.object: no object named 'parcel'"}));
  const std::string not_a_box =
      dir.Write("taskbox.yaml", "task: {object: b}\n" + SceneWithObject("    type: locker\n"));
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(not_a_box); }, {not_a_box + ":1", "'b' is a locker; the robot is sent for a box"}));
  EXPECT_EQ(LoadScene(dir.Write("taskok.yaml", "task: {object: b}\n" + SceneWithObject(""))).task_object, "b");
  const std::string syntax = dir.Write("syntax.yaml", "name: [unclosed\n");
  EXPECT_TRUE(ThrowsWith([&] { LoadScene(syntax); }, {syntax, "YAML syntax error"}));
}

}  // namespace
}  // namespace planemap::sim
