// The whole frontend on simulated frames with the full noise model: objects, classes, dimensions,
// centres and grasp axes against the scene's ground truth; degenerate frames.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "planemap/core/error.h"
#include "planemap/frontend/frontend.h"
#include "planemap/frontend/objects.h"
#include "planemap/sim/walk.h"
#include <yaml-cpp/yaml.h>
#include "sim_views.h"
#include "test_support.h"

namespace planemap {
namespace {

using testing::DefaultScene;
using testing::SourcePath;
using testing::Median;
using testing::XtionCamera;

Frontend MakeFrontend(const std::string& patterns = SourcePath("configs/patterns.yaml")) {
  return Frontend(XtionCamera(), FrontendConfig{}, LoadPatterns(patterns));
}

// The scene object most of an object's face pixels belong to.
std::string OwnerOf(const FrameModel& model, const FrameObject& object, const LabelImage& labels) {
  std::map<std::string, int> votes;
  for (int p : object.planes) {
    for (int i : model.planes[p].inliers) {
      const std::uint16_t l = labels.pixels()[i];
      if (l != 0) ++votes[DefaultScene().surface(l).object];
    }
  }
  const auto best = std::max_element(votes.begin(), votes.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  return best == votes.end() ? "" : best->first;
}

std::uint16_t LabelOf(const DetectedPlane& plane, const LabelImage& labels) {
  std::map<std::uint16_t, int> votes;
  for (int i : plane.inliers) ++votes[labels.pixels()[i]];
  return std::max_element(votes.begin(), votes.end(), [](const auto& a, const auto& b) { return a.second < b.second; })->first;
}

// The default box as the frontend finds it in rendered views, against the scene's truth.
struct BoxViewFigures {
  int views = 0, found = 0, as_box = 0, locker_objects = 0, as_locker = 0;
  std::vector<double> dimension_error, centre_error, axis_error_deg;  // [m], [m], [deg]
  std::string Summary() const {
    char text[400];
    std::snprintf(text, sizeof(text),
                  "%d views: box found in %d, classified box in %d; lockers as objects %d, classified locker %d\n"
                  "  dimensions (complete): %zu, |error| median %.1f mm, worst %.1f mm; centre median %.1f mm; "
                  "grasp axis median %.2f deg (%zu)\n",
                  views, found, as_box, locker_objects, as_locker, dimension_error.size(), 1000 * Median(dimension_error),
                  dimension_error.empty() ? 0.0 : 1000 * *std::max_element(dimension_error.begin(), dimension_error.end()),
                  1000 * Median(centre_error), Median(axis_error_deg), axis_error_deg.size());
    return text;
  }
};

BoxViewFigures EvaluateBoxViews(const Frontend& frontend, const std::vector<Pose3>& poses, std::uint64_t seed) {
  const sim::SceneObject& box = DefaultScene().object("box");
  BoxViewFigures f;
  for (size_t k = 0; k < poses.size(); ++k) {
    const testing::SimFrame sim = testing::RenderDefaultScene(poses[k], seed + k);
    const FrameModel model = frontend.Process(sim.frame);
    ++f.views;
    const Pose3 T_camera_box = poses[k].inverse() * box.T_world_object;
    for (const FrameObject& o : model.objects) {
      const std::string owner = OwnerOf(model, o, sim.labels);
      if (owner.rfind("locker", 0) == 0) {
        ++f.locker_objects;
        f.as_locker += o.label == "locker";
        if (o.label != "locker") {
          std::printf("view %zu: %s as '%s', %zu planes, %zu angles, dims %.2f %.2f %.2f (%d%d%d)\n", k, owner.c_str(),
                      o.label.c_str(), o.planes.size(), o.angles.size(), o.dimensions[0], o.dimensions[1],
                      o.dimensions[2], o.dimension_complete[0], o.dimension_complete[1], o.dimension_complete[2]);
        }
      }
      if (owner != "box") continue;
      ++f.found;
      if (o.label != "box") continue;
      ++f.as_box;
      for (int a = 0; a < 3; ++a) {
        if (!o.dimension_complete[a]) continue;
        // The box axis this object axis runs along, and its true dimension.
        int best = 0;
        for (int b = 1; b < 3; ++b) {
          if (std::abs(o.axes.col(a).dot(T_camera_box.linear().col(b))) >
              std::abs(o.axes.col(a).dot(T_camera_box.linear().col(best)))) {
            best = b;
          }
        }
        f.dimension_error.push_back(std::abs(o.dimensions[a] - box.dimensions[best]));
      }
      f.centre_error.push_back((o.center - T_camera_box.translation()).norm());
      if (o.grasp_side >= 0) {
        const Plane& truth = sim.planes_camera.at(LabelOf(model.planes[o.grasp_side], sim.labels));
        f.axis_error_deg.push_back(std::acos(std::min(1.0, std::abs(truth.normal.dot(o.grasp_axis)))) * 180.0 / M_PI);
      }
    }
  }
  return f;
}

TEST(Frontend, BoxClassDimensionsCentreAndGraspAxisFromViewsShowingThreeFaces) {
  const BoxViewFigures f = EvaluateBoxViews(MakeFrontend(), testing::BoxViewpoints(), 700);
  std::printf("%s", f.Summary().c_str());
  EXPECT_GE(f.as_box, 0.95 * f.views);
  EXPECT_GE(f.as_locker, 0.95 * f.locker_objects);
  ASSERT_GE(f.dimension_error.size(), 30u);
  EXPECT_LE(Median(f.dimension_error), 0.01) << "m";
  EXPECT_LE(Median(f.centre_error), 0.015) << "m";
  ASSERT_GE(f.axis_error_deg.size(), 30u);
  EXPECT_LE(Median(f.axis_error_deg), 2.0) << "deg";
}

// Issue 56: with objects of two faces on (graph.two_face_min_angle_deg 60, the default), the
// box showing only two faces, its top and a side or two sides (its third face turned away),
// standing on the floor, is a box object, its complete dimensions within 1 cm at
// the median, its grasp axis within 2 deg. The issue asks for 95% of the views; 89% hold (121
// of 136): every view of its top and a side, and 27 of the 42 of two sides. In the other 15 the
// floor meets both sides in seen edges, so the box is a trihedral object (floor and two sides)
// whose vertical edge, its top end against a background, is cut: its height is only a lower
// bound, and the first pattern it may match is the locker's (8 views); in 7 more the sides do not
// meet (a side seen at a glancing angle from 2-3 m).
TEST(Frontend, BoxFromViewsShowingTwoFacesOnTheFloor) {
  const std::vector<Pose3> poses = testing::BoxTwoFaceViewpoints();
  ASSERT_GE(poses.size(), 40u);
  // Two sides show only from below the box's top: the camera 12-18 cm above the floor, under the
  // default floor_min_distance (20 cm: a camera on a robot's head); configured for it.
  FrontendConfig low_camera;
  low_camera.graph.floor_min_distance = 0.1;
  low_camera.graph.two_face_min_angle_deg = 60.0;
  const BoxViewFigures f =
      EvaluateBoxViews(Frontend(XtionCamera(), low_camera, LoadPatterns(SourcePath("configs/patterns.yaml"))), poses, 900);
  std::printf("%s", f.Summary().c_str());
  EXPECT_GE(f.as_box, 0.95 * f.views);
  ASSERT_GE(f.dimension_error.size(), 2u * f.as_box);
  EXPECT_LE(Median(f.dimension_error), 0.01) << "m";
  EXPECT_LE(Median(f.centre_error), 0.015) << "m";
  ASSERT_GE(f.axis_error_deg.size(), f.as_box / 2u);
  EXPECT_LE(Median(f.axis_error_deg), 2.0) << "deg";
}

// Appends a plane through `point` with `normal` (no inliers) to a hand-made model.
void AddPlane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, FrameModel* model) {
  DetectedPlane p;
  p.id = static_cast<int>(model->planes.size());
  p.plane = Plane::FromPointNormal(point, normal);
  p.centroid = point;
  model->planes.push_back(p);
}

// A tall face seen edge-on, split by the segmenter into a large part and a sliver: the edge from
// the next face to the sliver is whole but 20 cm long, the edge to the large part runs out of the
// image after 58 cm. The object reaches at least 58 cm up, so the short whole edge is not its
// height (it made the hall's 2.8 m pillar a 20 cm "box" that the robot then walked into).
TEST(Frontend, AWholeEdgeShorterThanACutOneOnTheSameAxisIsNotTheObjectsDimension) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const auto measure = [&](double cut_length) {
    FrameModel model;
    const auto add_plane = [&](const Eigen::Vector3d& point, const Eigen::Vector3d& normal) { AddPlane(point, normal, &model); };
    add_plane({1.0, 0.0, 0.3}, {-1.0, 0.0, 0.0});                                     // west face
    add_plane({1.2, -0.5, 0.3}, {0.0, 1.0, 0.0});                                     // north face
    add_plane({1.05, -0.5, 0.15}, {std::sin(6.0 * M_PI / 180), 1.0, 0.0});            // its sliver
    const auto add_edge = [&](int a, int b, double length, bool cut) {
      PlaneEdge e;
      e.plane_a = a;
      e.plane_b = b;
      e.start = {1.0, -0.5, 0.06};
      e.end = e.start + length * up;
      e.direction = up;
      e.length = length;
      e.end_cut = cut;
      model.edges.push_back(e);
    };
    add_edge(0, 1, cut_length, true);
    add_edge(0, 2, 0.20, false);
    // The floor, and the faces' whole edges along it: an object unmeasured along an axis is dropped.
    add_plane({1.0, -0.3, 0.06}, up);
    model.floor = 3;
    const auto add_floor_edge = [&](int face, const Eigen::Vector3d& direction, double length) {
      PlaneEdge e;
      e.plane_a = 3;
      e.plane_b = face;
      e.start = {1.0, -0.5, 0.06};
      e.direction = direction;
      e.end = e.start + length * direction;
      e.length = length;
      model.edges.push_back(e);
    };
    add_floor_edge(0, Eigen::Vector3d::UnitY(), 0.4);
    add_floor_edge(1, Eigen::Vector3d::UnitX(), 0.3);
    FrameObject object;
    object.planes = {0, 1, 2};
    model.objects.push_back(object);
    MeasureObjects(Cloud(), ObjectConfig{}, up, &model);
    return model.objects.empty() ? FrameObject{} : model.objects[0];
  };
  const FrameObject pillar = measure(0.58);
  ASSERT_EQ(pillar.planes.size(), 3u) << "the object was dropped";
  EXPECT_NEAR(pillar.dimensions[2] * 100.0, 58.0, 1e-9);
  EXPECT_FALSE(pillar.dimension_complete[2]);
  // A cut edge longer only by noise (1 cm, within edge_length_tolerance 3 cm): the whole edge stands.
  const FrameObject box = measure(0.21);
  EXPECT_NEAR(box.dimensions[2] * 100.0, 20.0, 1e-9);
  EXPECT_TRUE(box.dimension_complete[2]);
}

// A box's side split by the segmenter at its rounded front corner: a 6 cm piece 6 deg off the
// rest, which holds the other 24 cm. Both meet the floor, along two pieces of one line, each
// whole. The box is 30 cm deep, not 24 (learn17's lower box: 12.8 cm called whole, 18.2 cm
// labelled; 18.5 cm with the pieces joined).
TEST(Frontend, TwoPiecesOfOneEdgeMeasureTheObjectTogether) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  // `gap`: the corner piece moved that far off the rest along the line [m].
  const auto measure = [&](const ObjectConfig& config, double gap) {
    FrameModel model;
    const auto add_plane = [&](const Eigen::Vector3d& point, const Eigen::Vector3d& normal) { AddPlane(point, normal, &model); };
    const double tilt = 6.0 * M_PI / 180.0;
    add_plane({1.0, -0.1, 0.0}, up);                                     // 0: the floor
    add_plane({1.0, -0.1, 0.05}, {-1.0, 0.0, 0.0});                      // 1: the front
    add_plane({1.03, 0.0, 0.05}, {-std::sin(tilt), std::cos(tilt), 0.0});  // 2: the side's corner piece
    add_plane({1.18, 0.0, 0.05}, {0.0, 1.0, 0.0});                       // 3: the rest of the side
    const auto add_edge = [&](int a, int b, const Eigen::Vector3d& start, const Eigen::Vector3d& direction, double length) {
      PlaneEdge e;
      e.plane_a = a;
      e.plane_b = b;
      e.start = start;
      e.direction = direction;
      e.end = start + length * direction;
      e.length = length;
      model.edges.push_back(e);
    };
    add_edge(0, 1, {1.0, -0.2, 0.0}, Eigen::Vector3d::UnitY(), 0.2);
    add_edge(0, 2, {1.0 - gap, 0.0, 0.0}, {std::cos(tilt), std::sin(tilt), 0.0}, 0.06);
    add_edge(0, 3, {1.06, 0.0, 0.0}, Eigen::Vector3d::UnitX(), 0.24);
    add_edge(1, 2, {1.0, 0.0, 0.0}, up, 0.1);
    model.floor = 0;
    FrameObject object;
    object.planes = {1, 2, 3};
    model.objects.push_back(object);
    MeasureObjects(Cloud(), config, up, &model);
    return model.objects.empty() ? FrameObject{} : model.objects[0];
  };
  const FrameObject joined = measure(ObjectConfig{}, 0.0);
  ASSERT_EQ(joined.planes.size(), 3u) << "the object was dropped";
  EXPECT_NEAR(std::abs(joined.axes.col(0).x()), 1.0, 1e-9);  // the front's normal
  EXPECT_NEAR(joined.dimensions[0] * 100.0, 30.0, 0.1) << "cm";
  EXPECT_TRUE(joined.dimension_complete[0]);
  EXPECT_NEAR(joined.dimensions[1] * 100.0, 20.0, 1e-9) << "cm";
  EXPECT_NEAR(joined.dimensions[2] * 100.0, 10.0, 1e-9) << "cm";
  ObjectConfig off;
  off.edge_join_distance = 0.0;
  EXPECT_NEAR(measure(off, 0.0).dimensions[0] * 100.0, 24.0, 1e-9) << "cm";  // one piece, called whole
  // 1.5 cm apart along the line (edge_join_gap 2 cm): one edge, 31.5 cm; 3 cm apart: two.
  EXPECT_NEAR(measure(ObjectConfig{}, 0.015).dimensions[0] * 100.0, 31.5, 0.1) << "cm";
  EXPECT_NEAR(measure(ObjectConfig{}, 0.03).dimensions[0] * 100.0, 24.0, 1e-9) << "cm";
}

TEST(Frontend, DegenerateFramesGiveAnEmptyOrPartialModelAndAReason) {
  const Frontend frontend = MakeFrontend();
  RgbdFrame empty;
  empty.depth = DepthImage(640, 480, 0.0f);
  const FrameModel none = frontend.Process(empty);
  EXPECT_TRUE(none.planes.empty() && none.objects.empty());
  EXPECT_EQ(none.reason, "no valid depth in the frame");

  // One wall, then one wall and the floor: planes but no angle, no object.
  const FrameModel wall = frontend.Process(testing::RenderDefaultScene(testing::LookAt({3.5, -2.0, 1.2}, {4.5, -2.0, 1.2}), 1).frame);
  EXPECT_GE(wall.planes.size(), 1u);
  EXPECT_TRUE(wall.objects.empty());
  EXPECT_FALSE(wall.reason.empty());
  const FrameModel two = frontend.Process(testing::RenderDefaultScene(testing::LookAt({3.0, -2.0, 0.6}, {4.5, -2.0, 0.3}), 2).frame);
  EXPECT_TRUE(two.objects.empty());
  EXPECT_FALSE(two.reason.empty()) << two.planes.size() << " planes";

  // Only parallel planes: the floor seen from straight above.
  const FrameModel parallel = frontend.Process(testing::RenderDefaultScene(testing::LookAt({0.5, -2.0, 1.5}, {0.52, -2.0, 0.0}), 3).frame);
  EXPECT_TRUE(parallel.edges.empty());
  EXPECT_TRUE(parallel.objects.empty());

  // Heavy dropouts: half the pixels gone. No crash, and nothing is invented: every object found
  // is a real one.
  sim::RenderConfig config;
  config.noise.random_dropout_probability = 0.5;
  const sim::VirtualCamera camera(DefaultScene(), XtionCamera(), config);
  const Pose3 pose = testing::BoxViewpoints()[3];
  const sim::RenderedFrame r = camera.Render(pose, 4);
  RgbdFrame frame;
  frame.depth = r.depth;
  const FrameModel sparse = frontend.Process(frame);
  for (const FrameObject& o : sparse.objects) EXPECT_NE(OwnerOf(sparse, o, r.labels), "") << "an invented object";
  std::set<std::string> owners;
  for (const FrameObject& o : sparse.objects) owners.insert(OwnerOf(sparse, o, r.labels));
  EXPECT_EQ(owners.size(), sparse.objects.size()) << "one object per real one";
}

TEST(Frontend, AUserAddsAClassWithAPatternAndNoCode) {
  testing::TempDir dir;
  // A "crate": a box no taller than 30 cm, tried before the shipped patterns.
  std::string patterns = "patterns:\n  - class: crate\n    nodes:\n      - {name: top, orientation: horizontal}\n"
                         "      - {name: a, orientation: vertical}\n      - {name: b, orientation: vertical}\n"
                         "    edges: [top-a, top-b, a-b]\n    max_height: 0.3\n";
  const Frontend frontend = MakeFrontend(dir.Write("patterns.yaml", patterns));
  const testing::SimFrame sim = testing::RenderDefaultScene(testing::BoxViewpoints()[5], 9);
  const FrameModel model = frontend.Process(sim.frame);
  int crates = 0;
  for (const FrameObject& o : model.objects) crates += OwnerOf(model, o, sim.labels) == "box" && o.label == "crate";
  EXPECT_EQ(crates, 1);
}

TEST(Frontend, BadPatternFilesAreErrorsNamingTheFile) {
  testing::TempDir dir;
  const std::string orientation = dir.Write("o.yaml", "patterns:\n  - class: x\n    nodes: [{name: a, orientation: diagonal}]\n");
  EXPECT_TRUE(testing::ThrowsWith([&] { LoadPatterns(orientation); }, {orientation + ":3", "must be floor, horizontal, vertical, any or support, not 'diagonal'"}));
  const std::string edge = dir.Write("e.yaml", "patterns:\n  - class: x\n    nodes: [{name: a}]\n    edges: [a-b]\n");
  EXPECT_TRUE(testing::ThrowsWith([&] { LoadPatterns(edge); }, {edge, "edge 'a-b'"}));
  const std::string none = dir.Write("n.yaml", "patterns: []\n");
  EXPECT_TRUE(testing::ThrowsWith([&] { LoadPatterns(none); }, {none, "no patterns"}));
  const std::string typo = dir.Write("t.yaml", "patterns:\n  - clas: x\n");
  EXPECT_TRUE(testing::ThrowsWith([&] { LoadPatterns(typo); }, {typo + ":2", "unknown key 'patterns[0].clas'"}));
}

}  // namespace
}  // namespace planemap

namespace planemap {
namespace {

// A pole stands between the camera and the box's nearest vertical edge, hiding it from the
// floor to above the box's top corner: the two side faces never meet in the image. Their edge
// is inferred (hidden) from the top's cut edges with both sides, the box found whole, and the
// inferred corner and edge are where the true ones are. Without the inference there is no box.
TEST(Frontend, ABoxWhoseVerticalEdgeIsHiddenBehindAPoleIsFound) {
  YAML::Node root = YAML::LoadFile(SourcePath("configs/scenes/default.yaml"));
  const sim::Scene plain = sim::ParseScene(root, "default.yaml");
  const sim::Cuboid& box = plain.cuboids[plain.object("box").cuboids[0]];
  // The box's vertical edge nearest (0.9, 0, 1.1), and its top corner; the camera looks at the
  // box along its diagonal through that edge, both sides in view.
  const Eigen::Vector3d from(0.9, 0.0, 1.1);
  const Eigen::Vector3d h = box.dimensions / 2;
  Eigen::Vector3d corner_top = Eigen::Vector3d::Zero(), corner_bottom;
  double nearest = 1e9;
  for (const double sx : {-1.0, 1.0}) {
    for (const double sy : {-1.0, 1.0}) {
      const Eigen::Vector3d top = box.T_world_box * Eigen::Vector3d(sx * h.x(), sy * h.y(), h.z());
      if ((top - from).norm() < nearest) {
        nearest = (top - from).norm();
        corner_top = top;
        corner_bottom = box.T_world_box * Eigen::Vector3d(sx * h.x(), sy * h.y(), -h.z());
      }
    }
  }
  Eigen::Vector3d outward = corner_top - box.T_world_box.translation();
  outward.z() = 0.0;
  const Eigen::Vector3d eye = corner_top + 1.4 * outward.normalized() + Eigen::Vector3d(0.0, 0.0, 0.75);
  // A pole 4 cm thick 60% of the way from the eye to the edge's middle, hiding it and the corner.
  const Eigen::Vector3d middle = 0.5 * (corner_top + corner_bottom);
  const Eigen::Vector3d at = eye + 0.6 * (middle - eye);
  YAML::Node pole;
  pole["name"] = "pole";
  pole["type"] = "furniture";
  pole["position"] = std::vector<double>{at.x(), at.y(), 0.0};
  pole["rpy_deg"] = std::vector<double>{0.0, 0.0, 0.0};
  pole["color"] = std::vector<int>{90, 90, 100};
  YAML::Node shaft;
  shaft["name"] = "shaft";
  shaft["position"] = std::vector<double>{0.0, 0.0, 0.45};
  shaft["dimensions"] = std::vector<double>{0.04, 0.04, 0.9};
  pole["parts"].push_back(shaft);
  root["objects"].push_back(pole);
  const sim::Scene scene = sim::ParseScene(root, "default.yaml + pole");
  sim::RenderConfig render;
  const sim::VirtualCamera camera(scene, XtionCamera(), render);
  const Pose3 T_world_camera = LookAt(eye, box.T_world_box.translation());
  RgbdFrame frame;
  sim::RenderedFrame rendered = camera.Render(T_world_camera, 7);
  frame.depth = std::move(rendered.depth);
  frame.color = std::move(rendered.color);
  const Pose3 T_camera_world = T_world_camera.inverse();

  FrontendConfig without;
  without.intersections.hidden_edges = false;
  FrontendConfig two_faces_only = without;  // its top meets each side: faces joined two by two
  two_faces_only.graph.two_face_min_angle_deg = 60.0;
  without.graph.two_face_min_angle_deg = 0.0;
  const PatternsConfig patterns = LoadPatterns(SourcePath("configs/patterns.yaml"));
  FrontendConfig with;
  with.intersections.hidden_edges = true;
  const FrameModel model = Frontend(XtionCamera(), with, patterns).Process(frame);
  const FrameModel before = Frontend(XtionCamera(), without, patterns).Process(frame);
  // The box's side faces that meet at the hidden edge: the planes whose normals are within 5 deg
  // of the two true side normals next to it.
  const Eigen::Vector3d up = T_camera_world.linear() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d edge_true = (T_camera_world * corner_bottom - T_camera_world * corner_top).normalized();
  auto box_object = [&](const FrameModel& m) -> const FrameObject* {
    for (const FrameObject& o : m.objects) {
      int sides = 0, top = 0;
      for (int p : o.planes) {
        const Eigen::Vector3d n = m.planes[p].plane.normal;
        top += n.dot(up) > std::cos(5.0 * M_PI / 180);
        sides += std::abs(n.dot(up)) < std::sin(5.0 * M_PI / 180);
      }
      if (top == 1 && sides == 2) return &o;
    }
    return nullptr;
  };
  ASSERT_EQ(box_object(before), nullptr) << "the hidden edge was needed";
  // Without the hidden edge, the top and each side meet in convex edges and the sides stand on
  // the floor: an object of faces joined two by two (issue 56), no corner needed.
  const FrameModel pairs = Frontend(XtionCamera(), two_faces_only, patterns).Process(frame);
  const FrameObject* by_pairs = box_object(pairs);
  ASSERT_NE(by_pairs, nullptr);
  EXPECT_TRUE(by_pairs->angles.empty());
  EXPECT_EQ(by_pairs->support, pairs.floor);
  EXPECT_EQ(by_pairs->label, "box");
  const FrameObject* found = box_object(model);
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->label, "box");
  const PlaneEdge* hidden = nullptr;
  for (const PlaneEdge& e : model.edges) {
    if (e.hidden) hidden = &e;
  }
  ASSERT_NE(hidden, nullptr);
  // The pole hides the edge from the floor to above the top: both corners are inferred (the
  // top's, the floor's), and the edge runs between them.
  const Eigen::Vector3d top = T_camera_world * corner_top, bottom = T_camera_world * corner_bottom;
  const double corner_error = std::min(std::max((hidden->start - top).norm(), (hidden->end - bottom).norm()),
                                       std::max((hidden->start - bottom).norm(), (hidden->end - top).norm()));
  const double angle_error = std::acos(std::min(1.0, std::abs(hidden->direction.dot(edge_true)))) * 180 / M_PI;
  std::printf("hidden edge: ends %.1f cm from the true corners (worse end), %.1f deg off the true edge, %.1f cm long "
              "(true %.1f), ends cut: %d %d; the box's height %.1f cm (complete: %d)\n", 100 * corner_error, angle_error,
              100 * hidden->length, 100 * box.dimensions.z(), hidden->start_cut, hidden->end_cut, 100 * found->dimensions[2],
              found->dimension_complete[2]);
  EXPECT_LT(corner_error, 0.02) << "m";
  EXPECT_LT(angle_error, 2.0) << "deg";
  EXPECT_TRUE(hidden->Complete()) << "both ends are corners";
  EXPECT_NEAR(found->dimensions[2], box.dimensions.z(), 0.01) << "m";
}

}  // namespace
}  // namespace planemap
