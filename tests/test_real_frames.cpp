// The frontend on real Kinect frames: the OSD boxes (a ground-truth label for every point) and
// TUM office frames. Figures are printed; the issue's checks are asserted.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "planemap/core/detected_plane.h"
#include "planemap/core/statistics.h"
#include "planemap/frontend/frontend.h"
#include "planemap/frontend/osd_labels.h"
#include "planemap/frontend/pcd_source.h"
#include "planemap/io/tum_sequence.h"
#include "test_support.h"

namespace planemap {
namespace {

using testing::SharedPath;
using testing::SourcePath;

constexpr double kRadToDeg = 180.0 / M_PI;

CameraIntrinsics OpenNi() { return LoadCameraIntrinsics(SourcePath("configs/cameras/tum_openni_default.yaml")); }

Frontend MakeFrontend(const FrontendConfig& config = FrontendConfig{}) {
  return Frontend(OpenNi(), config, LoadPatterns(SourcePath("configs/patterns.yaml")));
}

// A top (within 15 deg of horizontal) and two sides (within 15 deg of vertical, at least 60 deg
// apart) among the faces' normals.
bool TopAndTwoSides(const std::vector<Eigen::Vector3d>& normals, const Eigen::Vector3d& up) {
  bool top = false, two_sides = false;
  std::vector<Eigen::Vector3d> sides;
  for (const Eigen::Vector3d& n : normals) {
    const double c = std::abs(n.dot(up));
    top |= c > std::cos(15.0 / kRadToDeg);
    if (c < std::sin(15.0 / kRadToDeg)) sides.push_back(n);
  }
  for (size_t a = 0; a < sides.size(); ++a) {
    for (size_t b = a + 1; b < sides.size(); ++b) two_sides |= std::abs(sides[a].dot(sides[b])) < 0.5;
  }
  return top && two_sides;
}

struct BoxFigures {
  int boxes_with_three_faces = 0, found = 0, complete_dimensions = 0;
  std::vector<double> iou, perpendicular_error_deg, dimension_error;
  // Faces' normals against their labelled faces'; the angles between faces against those between
  // the labelled faces; the labelled faces' own angles off 90 deg.
  std::vector<double> normal_error_deg, angle_error_deg, labelled_perpendicular_error_deg;
  // Pairs of faces not on two labelled faces (one without a labelled face, or both on one).
  int scenes = 0, table_found = 0, table_in_object = 0, unmatched_pairs = 0;
};

double Worst(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

// Figures for the boxes of scene `index` (only box `only_box` when it is not 0).
void EvaluateOsdScene(int index, const Frontend& frontend, BoxFigures* f, int only_box = 0) {
  const PcdFrame pcd = LoadOrganizedPcd(SharedPath("data/osd_boxes_learn/pcd/learn" + std::to_string(index) + ".pcd"), OpenNi());
  const FrameModel model = frontend.Process(*pcd.cloud);
  ++f->scenes;
  // The table: the floor of this frame, mostly table-labelled points, in no object.
  if (model.floor >= 0) {
    int table = 0;
    for (int i : model.planes[model.floor].inliers) table += IsOsdTable(pcd.labels[i]);
    if (table > 0.7 * model.planes[model.floor].inliers.size()) ++f->table_found;
    for (const FrameObject& o : model.objects) {
      f->table_in_object += std::count(o.planes.begin(), o.planes.end(), model.floor) > 0;
    }
  }
  const std::vector<LabelledFace> table = LabelledTable(*pcd.cloud, pcd.labels);
  ASSERT_EQ(table.size(), 1u) << "learn" << index << ": no plane through the table's labelled points";
  const Eigen::Vector3d table_up = table[0].plane.normal;
  // Which labelled box each detected plane belongs to (70% of its inliers).
  std::map<int, std::vector<int>> planes_of_box;
  for (const DetectedPlane& p : model.planes) {
    std::map<int, int> votes;
    for (int i : p.inliers) ++votes[OsdObjectOf(pcd.labels[i])];
    for (const auto& [box, n] : votes) {
      if (box > 0 && n > 0.7 * p.inliers.size()) planes_of_box[box].push_back(p.id);
    }
  }
  for (const auto& [box, faces] : LabelledFaces(*pcd.cloud, pcd.labels)) {
    if (only_box != 0 && box != only_box) continue;
    // Does the box show its top and two sides? Decided from its labelled points, not from what
    // the frontend found.
    std::vector<Eigen::Vector3d> face_normals;
    for (const LabelledFace& face : faces) face_normals.push_back(face.plane.normal);
    if (!TopAndTwoSides(face_normals, table_up)) continue;
    ++f->boxes_with_three_faces;
    // Found: an object whose faces are all this box's, among them its top and two sides.
    const std::vector<int>& planes = planes_of_box[box];
    const FrameObject* found = nullptr;
    for (const FrameObject& o : model.objects) {
      std::vector<Eigen::Vector3d> normals;
      for (int p : o.planes) normals.push_back(model.FacePlane(p).normal);
      if (std::all_of(o.planes.begin(), o.planes.end(), [&](int p) { return std::count(planes.begin(), planes.end(), p); }) &&
          TopAndTwoSides(normals, table_up)) {
        found = &o;
      }
    }
    if (found == nullptr) {
      std::printf("learn%d: box %d shows top and two sides, but no object has them\n", index, box);
      continue;
    }
    ++f->found;
    // Intersection over union of the object's inliers and the box's labelled points.
    std::set<int> mine, truth;
    for (int p : found->planes) mine.insert(model.planes[p].inliers.begin(), model.planes[p].inliers.end());
    for (size_t i = 0; i < pcd.labels.size(); ++i) {
      if (OsdObjectOf(pcd.labels[i]) == box && IsValidPoint((*pcd.cloud)[i])) truth.insert(static_cast<int>(i));
    }
    int both = 0;
    for (int i : mine) both += truth.count(i);
    f->iou.push_back(static_cast<double>(both) / (mine.size() + truth.size() - both));
    // The object's faces: a plane, or the pieces of one face (FrameModel::face_of) with the plane
    // fitted to them all; each judged once, as one face.
    std::map<int, std::vector<int>> pieces;
    for (int p : found->planes) pieces[model.FaceOf(p)].push_back(p);
    std::vector<int> object_faces;
    for (const auto& [face, members] : pieces) object_faces.push_back(face);
    // Each face's labelled face: the one holding most of its inliers.
    std::vector<const LabelledFace*> truth_of(object_faces.size(), nullptr);
    for (size_t a = 0; a < object_faces.size(); ++a) {
      std::vector<int> inliers;
      for (int p : pieces[object_faces[a]]) inliers.insert(inliers.end(), model.planes[p].inliers.begin(), model.planes[p].inliers.end());
      std::sort(inliers.begin(), inliers.end());
      size_t best = 0;
      for (const LabelledFace& face : faces) {
        std::vector<int> common;
        std::set_intersection(inliers.begin(), inliers.end(), face.points.begin(), face.points.end(), std::back_inserter(common));
        if (common.size() > best) {
          best = common.size();
          truth_of[a] = &face;
        }
      }
      if (truth_of[a] == nullptr) continue;
      f->normal_error_deg.push_back(NormalAngle(model.FacePlane(object_faces[a]), truth_of[a]->plane) * kRadToDeg);
      if (f->normal_error_deg.back() > 3.0) {
        std::printf("learn%d box %d: face %d (%zu piece(s), %zu px) is %.1f deg from its labelled face (%zu px, %zu in common)\n",
                    index, box, object_faces[a], pieces[object_faces[a]].size(), inliers.size(), f->normal_error_deg.back(),
                    truth_of[a]->points.size(), best);
      }
    }
    // Faces mutually perpendicular, and the angles between them against those between their
    // labelled faces (cartons are not square to 5 deg: see below).
    for (size_t a = 0; a < object_faces.size(); ++a) {
      for (size_t b = a + 1; b < object_faces.size(); ++b) {
        const int fa = object_faces[a], fb = object_faces[b];
        const double angle = NormalAngle(model.FacePlane(fa), model.FacePlane(fb)) * kRadToDeg;
        f->perpendicular_error_deg.push_back(std::abs(angle - 90.0));
        double labelled = std::nan("");
        if (truth_of[a] != nullptr && truth_of[b] != nullptr && truth_of[a] != truth_of[b]) {
          labelled = NormalAngle(truth_of[a]->plane, truth_of[b]->plane) * kRadToDeg;
          f->labelled_perpendicular_error_deg.push_back(std::abs(labelled - 90.0));
          f->angle_error_deg.push_back(std::abs(angle - labelled));
        } else {
          f->unmatched_pairs++;
        }
        if (std::abs(angle - 90.0) > 3.0) {
          std::printf("learn%d box %d: faces %d (%zu piece(s)) and %d (%zu piece(s)) at %.1f deg, their labelled faces at %.1f deg\n",
                      index, box, fa, pieces[fa].size(), fb, pieces[fb].size(), angle, labelled);
        }
      }
    }
    // Dimensions against the extent of the labelled points along the object's axes (1st-99th
    // percentile, so single stray points do not count).
    for (int k = 0; k < 3; ++k) {
      if (!found->dimension_complete[k]) continue;
      // A box standing on the table is as tall as its top is above the table: the labels of a
      // box's sides may stop short of the table (learn2's 13 mm above it, others' 2-6 mm).
      const double measured =
          OsdLabelledExtent(*pcd.cloud, std::vector<int>(truth.begin(), truth.end()), found->axes.col(k), table[0].plane);
      f->dimension_error.push_back(std::abs(found->dimensions[k] - measured));
      if (std::abs(found->dimensions[k] - measured) > 0.01) {
        std::printf("learn%d box %d: dimension %d is %.1f mm, labelled %.1f mm\n", index, box, k,
                    1000 * found->dimensions[k], 1000 * measured);
      }
      ++f->complete_dimensions;
    }
  }
}

TEST(RealFrames, OsdBoxesAreFoundWithTheirFacesAndSizes) {
  PLANEMAP_REQUIRE_SHARED("data/osd_boxes_learn/pcd");
  const Frontend frontend = MakeFrontend();
  BoxFigures f;
  for (int i = 0; i <= 24; ++i) EvaluateOsdScene(i, frontend, &f);
  auto median = [](std::vector<double> v) { return v.empty() ? 0.0 : Percentile(v, 0.5); };
  auto worst = [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); };
  const int angles_over_5 =
      static_cast<int>(std::count_if(f.angle_error_deg.begin(), f.angle_error_deg.end(), [](double e) { return e > 5.0; }));
  std::printf("OSD learn 0-24: table found in %d/%d scenes (in an object: %d); boxes showing top and two sides: %d, "
              "found as objects: %d\n  IoU with labelled points median %.2f (min %.2f); faces' normals vs labelled faces' "
              "median %.1f, worst %.1f deg\n  faces off 90 deg median %.1f, worst %.1f deg (labelled faces: median %.1f, "
              "worst %.1f); angles between faces vs between labelled faces: median %.1f, worst %.1f deg, %d of %d "
              "pairs over 5 deg (%d unmatched)\n  %d complete dimensions, |error| vs labelled size median %.1f mm, worst %.1f mm\n",
              f.table_found, f.scenes, f.table_in_object, f.boxes_with_three_faces, f.found, median(f.iou),
              f.iou.empty() ? 0.0 : *std::min_element(f.iou.begin(), f.iou.end()), median(f.normal_error_deg),
              worst(f.normal_error_deg), median(f.perpendicular_error_deg), worst(f.perpendicular_error_deg),
              median(f.labelled_perpendicular_error_deg), worst(f.labelled_perpendicular_error_deg),
              median(f.angle_error_deg), worst(f.angle_error_deg), angles_over_5, static_cast<int>(f.angle_error_deg.size()),
              f.unmatched_pairs, f.complete_dimensions, 1000 * median(f.dimension_error), 1000 * worst(f.dimension_error));
  EXPECT_EQ(f.table_found, f.scenes);
  EXPECT_EQ(f.table_in_object, 0);
  // Issue 3 asks that every box showing its top and two sides be found, with its faces mutually
  // perpendicular within 5 deg. Which boxes show them is read from the labels (planes by RANSAC
  // through each box's labelled points), and a box counts as found only by an object holding a
  // top and two sides of it. On these real scenes that holds for all 13 boxes. learn13's front
  // box is found since the search for thin strips looks again across pixels without depth: its
  // narrow left face (about 20 px wide, 62 deg from the view; 1418 labelled points on one plane
  // within 5 mm) showed as parts of 346 and 310 pixels 4 px apart, each under the 400 a plane
  // needs; joined, they make a 768-pixel plane, 86 deg from the front. The lower of two stacked
  // boxes (learn17, box 1), whose top shows only as two ledges 2-3 cm wide beside the upper box
  // (fitted 4.2 and 6.9 deg off the labelled top) and its right side as two planes 5.8 deg apart,
  // is found since pieces of one face are fitted as one face (0.5 deg off the labelled top), and
  // its corner may lie on an edge's line past its cut end (FacesInPieces..., below). Faces are
  // judged as faces: a face in pieces is one face, its plane fitted to all its pieces.
  // The upper box there is found since thin strips no cell fits are searched for planes
  // (its right side, a diagonal strip 10-18 px wide) and since a plane is not merged with a
  // parallel one a step away (its left side and the lower box's, 1.7 cm apart). learn18's back
  // box is found though its vertical corner is hidden behind the box in front of it: its top,
  // cut in two by that box, is one plane (coplanar pieces with an occluder between them), and
  // the edge between its sides is inferred (a hidden edge).
  // Perpendicular within 5 deg is more than these cartons are: planes fitted to the labelled
  // points of the found boxes' faces are themselves up to 11 deg off 90 (learn18's back box,
  // whose right side is bent; learn13's small box, learn24's first and third 5.6-6.5 deg), so
  // each angle between two faces is checked against the angle between their labelled faces. All
  // 39 pairs are within 5 deg of it (the worst 3.6 deg; 5.2 before strips took back their faces:
  // learn17's upper box's left side held the left ledge's rows, next test). Complete dimensions
  // are within 1 cm of the labelled size (the labelled points' extent; for a box standing on the
  // table, its height is its top's above the table: learn2's labels stop 13 mm above the table,
  // where some 400 points on its faces' planes are unlabelled, and its height measured 10.2 mm
  // over the labelled extent is 2.8 mm under its top's height).
  // What is asserted: the table, every box found, and that what is found is right: faces'
  // normals as close to the labelled faces' as the simulated frames' bound, 1 deg, at the
  // median; the angles between faces; every complete dimension within 1 cm (an occluded edge
  // once passed for a whole one, 22 cm short; learn18's bottom edge, ending in the front box's
  // shadow, 11 cm short):
  EXPECT_EQ(f.boxes_with_three_faces, 13);
  EXPECT_EQ(f.found, 13);
  // learn13's front box: its rounded vertical corner is two planes of its own (1033 and 1006
  // pixels, between the front and the narrow side), not faces of the box (its top's far part,
  // 766 pixels 6.7 deg off the rest, is a piece of its top).
  EXPECT_GE(*std::min_element(f.iou.begin(), f.iou.end()), 0.75);
  EXPECT_LE(median(f.normal_error_deg), 1.0) << "deg";
  EXPECT_EQ(f.unmatched_pairs, 0);
  EXPECT_EQ(angles_over_5, 0);  // the issue's "perpendicular within 5 deg", against the labelled faces
  EXPECT_LE(median(f.perpendicular_error_deg), 5.0) << "deg";
  EXPECT_LE(median(f.dimension_error), 0.01) << "m";
  EXPECT_LE(worst(f.dimension_error), 0.01) << "m";
}

// Issue 56: boxes that show two faces (a top and a side, or two sides; read from the labelled
// points, OsdFacesShown) standing on the table or on another box, with objects of two faces on
// (graph.two_face_min_angle_deg 60, the default) and off. ScoreOsdBoxes: found by a box
// object whose centre lies in the box's labelled points' bounding box grown by 3 cm and whose
// cuboid grown by 2 cm holds half of them or more; complete dimensions against the labelled
// extent; a false box is a box object near no labelled box.
TEST(RealFrames, OsdBoxesShowingTwoFacesAreFoundOnTheirSupport) {
  PLANEMAP_REQUIRE_SHARED("data/osd_boxes_learn/pcd");
  for (const bool two_face_objects : {true, false}) {
    FrontendConfig config;
    config.graph.two_face_min_angle_deg = two_face_objects ? 60.0 : 0.0;
    const Frontend frontend = MakeFrontend(config);
    std::map<int, int> boxes, found;  // by faces shown
    std::map<int, std::vector<double>> dimension_error;
    int false_boxes = 0, box_objects = 0;
    for (int i = 0; i <= 24; ++i) {
      const PcdFrame pcd = LoadOrganizedPcd(SharedPath("data/osd_boxes_learn/pcd/learn" + std::to_string(i) + ".pcd"), OpenNi());
      const OsdBoxScore score = ScoreOsdBoxes(*pcd.cloud, pcd.labels, frontend.Process(*pcd.cloud));
      false_boxes += score.false_boxes;
      box_objects += score.box_objects;
      for (const OsdBoxResult& box : score.boxes) {
        ++boxes[box.faces_shown];
        found[box.faces_shown] += box.object >= 0;
        auto& errors = dimension_error[box.faces_shown];
        errors.insert(errors.end(), box.dimension_error.begin(), box.dimension_error.end());
        for (double e : box.dimension_error) {
          if (two_face_objects && e > 0.01) std::printf("learn%d box %d (%d faces): a dimension %.1f mm off\n", i, box.box, box.faces_shown, 1000 * e);
        }
      }
    }
    auto median = [](const std::vector<double>& v) { return v.empty() ? 0.0 : Percentile(v, 0.5); };
    std::printf("OSD learn 0-24, objects of two faces %s: %d box objects, %d false\n", two_face_objects ? "on" : "off",
                box_objects, false_boxes);
    for (const int faces : {2, 3}) {
      std::printf("  boxes showing %d faces: %d, found %d; %zu complete dimensions, |error| median %.1f mm\n", faces,
                  boxes[faces], found[faces], dimension_error[faces].size(), 1000 * median(dimension_error[faces]));
    }
    EXPECT_EQ(boxes[2], 45);
    EXPECT_EQ(boxes[3], 13);
    EXPECT_EQ(false_boxes, 0);
    EXPECT_GE(found[3], 11);
    EXPECT_LE(median(dimension_error[3]), 0.005) << "m";
    if (two_face_objects) {
      EXPECT_GE(found[2], 0.6 * boxes[2]);
      ASSERT_GE(dimension_error[2].size(), static_cast<size_t>(found[2]));
      EXPECT_LE(median(dimension_error[2]), 0.01) << "m";
    } else {
      EXPECT_EQ(found[2], 0);  // what the issue found: three faces had to meet at a corner
    }
  }
}

TEST(RealFrames, AStripTakesBackItsFaceAndAnEdgeEndsOnTheLedgeItStandsOn) {
  PLANEMAP_REQUIRE_SHARED("data/osd_boxes_learn/pcd");
  // learn17: a box stacked on a larger one, whose top shows only as ledges 2-3 cm wide around it.
  // The right ledge's plane took the lower rows of the upper box's side (a strip found later, its
  // pixels a few millimetres from the ledge's plane) and came out 13.6 deg off level; the upper
  // box's front took the left ledge's rows and its normal came out 5.8 deg off its labelled face.
  // A strip takes back the pixels beside it that lie on it rather than on their plane (planes
  // nearer than 1 m, which the consensus check leaves alone). Then the upper box's vertical
  // edge, ended by the ledge it stands on, stopped 7.7 mm above it (the last rows went to neither
  // face's band): it now ends where it meets the ledge's plane.
  FrontendConfig before;
  before.segmentation.organized.strip_take_back_rounds = 0;
  before.intersections.end_on_ending_plane = false;
  FrontendConfig no_end_on_plane;
  no_end_on_plane.intersections.end_on_ending_plane = false;
  BoxFigures now, then, take_back_only;  // the upper box (box 2)
  EvaluateOsdScene(17, MakeFrontend(), &now, 2);
  EvaluateOsdScene(17, MakeFrontend(before), &then, 2);
  EvaluateOsdScene(17, MakeFrontend(no_end_on_plane), &take_back_only, 2);
  ASSERT_EQ(now.found, 1);
  ASSERT_EQ(then.found, 1);
  ASSERT_EQ(take_back_only.found, 1);
  EXPECT_GT(Worst(then.normal_error_deg), 5.0) << "deg";
  EXPECT_LE(Worst(now.normal_error_deg), 5.0) << "deg";
  EXPECT_LT(then.complete_dimensions, 3);  // the height: its lower end was taken for cut
  EXPECT_EQ(take_back_only.complete_dimensions, 3);
  EXPECT_GT(Worst(take_back_only.dimension_error), 0.01) << "m";
  EXPECT_EQ(now.complete_dimensions, 3);
  EXPECT_LE(Worst(now.dimension_error), 0.01) << "m";
}

TEST(RealFrames, EdgesEndWhereTheCameraSeesThemEnd) {
  PLANEMAP_REQUIRE_SHARED("data/osd_boxes_learn/pcd");
  // learn22: a box stacked on another, its sides flush with the lower box's, which lends the
  // side planes a few pixels below the upper box; and one side's last centimetre left out by the
  // segmenter, then missing depth, while the top runs on. Taken at face value, the vertical
  // edge ran 1.4 cm down into free space (the camera sees 5 cm past it there) and a 23 cm edge
  // counted whole at 21 cm. An end in front of what the camera sees moves in to the surface; an
  // edge going on past its end unseen (a surface no plane took, or a face running into missing
  // depth) is cut.
  FrontendConfig before;
  before.intersections.free_space_min_run = 1 << 20;
  before.intersections.unseen_run_length = 1e3;
  BoxFigures now, then;
  EvaluateOsdScene(22, MakeFrontend(), &now);
  EvaluateOsdScene(22, MakeFrontend(before), &then);
  ASSERT_EQ(now.found, 1);
  ASSERT_EQ(then.found, 1);
  ASSERT_FALSE(now.dimension_error.empty());
  EXPECT_GT(*std::max_element(then.dimension_error.begin(), then.dimension_error.end()), 0.01) << "m";
  EXPECT_LE(*std::max_element(now.dimension_error.begin(), now.dimension_error.end()), 0.01) << "m";
}

// learn17's lower box (box 1, labels 20-29): the object all of whose faces hold mostly its
// points. Its top shows only as two ledges beside the upper box (one face in two pieces, as is
// its right side: see FacesInPieces... below).
const FrameObject* Learn17LowerBox(const FrameModel& model, const PcdFrame& pcd) {
  const FrameObject* lower = nullptr;
  for (const FrameObject& o : model.objects) {
    bool all = true;
    for (int p : o.planes) {
      int mine = 0;
      for (int i : model.planes[p].inliers) mine += OsdObjectOf(pcd.labels[i]) == 1;
      all = all && mine > 0.7 * model.planes[p].inliers.size();
    }
    if (all) lower = &o;
  }
  return lower;
}

// The extent of box `box`'s labelled points along `axis` (1st to 99th percentile) [m].
double LabelledExtent(const PcdFrame& pcd, int box, const Eigen::Vector3d& axis) {
  std::vector<double> along;
  for (size_t i = 0; i < pcd.labels.size(); ++i) {
    if (OsdObjectOf(pcd.labels[i]) == box && IsValidPoint((*pcd.cloud)[i])) {
      along.push_back(axis.dot((*pcd.cloud)[i].getVector3fMap().cast<double>()));
    }
  }
  return Percentile(along, 0.99) - Percentile(along, 0.01);
}

TEST(RealFrames, ASideSplitAtItsRoundedCornerIsMeasuredAlongBothPieces) {
  PLANEMAP_REQUIRE_SHARED("data/osd_boxes_learn/pcd");
  // learn17's lower box: its right side is two planes 5.8 deg apart, one at the rounded front
  // corner, each meeting the table along a piece of one line. Measured from one piece, the box
  // was 12.8 cm deep, called whole.
  const PcdFrame pcd = LoadOrganizedPcd(SharedPath("data/osd_boxes_learn/pcd/learn17.pcd"), OpenNi());
  ObjectConfig off;
  off.edge_join_distance = 0.0;
  FrontendConfig before;
  before.objects = off;
  for (const bool join : {true, false}) {
    const FrameModel model = MakeFrontend(join ? FrontendConfig{} : before).Process(*pcd.cloud);
    const FrameObject* lower = Learn17LowerBox(model, pcd);
    ASSERT_NE(lower, nullptr) << (join ? "joined" : "not joined");
    // Its depth (the axis across the front) against the labelled points' extent along it.
    const double labelled = LabelledExtent(pcd, 1, lower->axes.col(0));
    std::printf("learn17 lower box, edge pieces %s: %.1f cm deep (%s), labelled %.1f cm\n", join ? "joined" : "apart",
                100 * lower->dimensions[0], lower->dimension_complete[0] ? "whole" : "cut", 100 * labelled);
    ASSERT_TRUE(lower->dimension_complete[0]);
    if (join) {
      EXPECT_NEAR(lower->dimensions[0], labelled, 0.01) << "m";
    } else {
      EXPECT_GT(std::abs(lower->dimensions[0] - labelled), 0.03) << "m";
    }
  }
}

TEST(RealFrames, FacesInPiecesMakeTheLowerOfTwoStackedBoxesWithItsTopAndSides) {
  PLANEMAP_REQUIRE_SHARED("data/osd_boxes_learn/pcd");
  // learn17's lower box: its top shows only as two ledges 2-3 cm wide on either side of the box
  // standing on it (planes 8.8 deg apart, each tilted by its rounded rim), and its right side as
  // two planes 5.8 deg apart. Each ledge meets the front along a piece of the front's top edge,
  // and each side piece meets the table along a piece of one line: pieces of one face, fitted as
  // one. The top meets the side only 15 cm behind the front (3 cm of edge, cut where the right
  // ledge narrows under d_thresh), so the corner of front, top and side lies on that edge's line
  // past its cut end. Before both, no object held the box's top (12 of 13 boxes found); with the
  // corner rule alone, the right ledge is the top, 13.5 deg off, and the side's pieces two faces.
  const PcdFrame pcd = LoadOrganizedPcd(SharedPath("data/osd_boxes_learn/pcd/learn17.pcd"), OpenNi());
  FrontendConfig no_pieces, no_corner;
  no_pieces.graph.face_piece_max_angle_deg = 0.0;
  no_corner.graph.corner_past_cut_distance = 0.0;
  BoxFigures with, without_pieces, without_corner;  // box 1, the lower box
  EvaluateOsdScene(17, MakeFrontend(), &with, 1);
  EvaluateOsdScene(17, MakeFrontend(no_pieces), &without_pieces, 1);
  EvaluateOsdScene(17, MakeFrontend(no_corner), &without_corner, 1);
  EXPECT_EQ(without_corner.found, 0);
  ASSERT_EQ(without_pieces.found, 1);
  EXPECT_GT(without_pieces.unmatched_pairs, 0);
  EXPECT_GT(Worst(without_pieces.angle_error_deg), 5.0) << "deg";
  ASSERT_EQ(with.found, 1);
  EXPECT_GE(with.iou[0], 0.75);
  EXPECT_EQ(with.unmatched_pairs, 0);
  // Its faces (top and side each fitted to their pieces) against its labelled faces.
  std::printf("learn17 lower box: IoU %.2f; faces vs labelled faces worst %.1f deg; angles between faces vs labelled worst %.1f deg\n",
              with.iou[0], Worst(with.normal_error_deg), Worst(with.angle_error_deg));
  EXPECT_LE(Worst(with.normal_error_deg), 3.0) << "deg";
  EXPECT_LE(Worst(with.angle_error_deg), 5.0) << "deg";
  // Each ledge on its own is farther from the labelled top than the two fitted together.
  const FrameModel model = MakeFrontend().Process(*pcd.cloud);
  const FrameObject* lower = Learn17LowerBox(model, pcd);
  ASSERT_NE(lower, nullptr);
  const Eigen::Vector3d up = lower->axes.col(2);
  std::vector<int> top;
  for (int p : lower->planes) {
    if (std::abs(model.FacePlane(p).normal.dot(up)) > std::cos(15.0 / kRadToDeg)) top.push_back(p);
  }
  ASSERT_EQ(top.size(), 2u) << "the top's pieces";
  EXPECT_EQ(model.FaceOf(top[0]), model.FaceOf(top[1]));
  const std::vector<LabelledFace> labelled = LabelledFaces(*pcd.cloud, pcd.labels).at(1);
  const auto labelled_top = std::find_if(labelled.begin(), labelled.end(), [&](const LabelledFace& f) {
    return std::abs(f.plane.normal.dot(up)) > std::cos(15.0 / kRadToDeg);
  });
  ASSERT_NE(labelled_top, labelled.end());
  const double joint = NormalAngle(model.FacePlane(top[0]), labelled_top->plane) * kRadToDeg;
  for (int p : top) {
    const double alone = NormalAngle(model.planes[p].plane, labelled_top->plane) * kRadToDeg;
    std::printf("  ledge %d alone %.1f deg from the labelled top, the two fitted as one %.1f deg\n", p, alone, joint);
    EXPECT_GT(alone, joint + 2.0) << "deg";
  }
}

TEST(RealFrames, ARoundedCornerBesideAFaceIsNotAPieceOfIt) {
  PLANEMAP_REQUIRE_SHARED("data/osd_boxes_learn/pcd");
  // learn20's right box: a strip along its rounded vertical corner, 9.6 deg from the side, meets
  // the front beside the side's own edge with it (their stretches along the line overlap by
  // 10 cm). Taken for a piece of the side, it turned the side's fitted plane 5.5 deg off its
  // labelled face.
  FrontendConfig across;
  across.graph.face_piece_max_overlap = 1.0;
  BoxFigures now, then;
  EvaluateOsdScene(20, MakeFrontend(), &now, 2);
  EvaluateOsdScene(20, MakeFrontend(across), &then, 2);
  ASSERT_EQ(now.found, 1);
  ASSERT_EQ(then.found, 1);
  EXPECT_GT(Worst(then.normal_error_deg), 5.0) << "deg";
  EXPECT_LE(Worst(now.normal_error_deg), 3.0) << "deg";
}

TEST(RealFrames, AFrontsLastPixelsThatNoPlaneTookMeasureItsWidthAsItsFringe) {
  PLANEMAP_REQUIRE_SHARED("data/osd_boxes_learn/pcd");
  // learn17's lower box, 5.6 cm tall at 0.8 m (37 px, two cell rows): at its front's left end the
  // cells are mixed with the table and the background, so the segmenter offered the front's plane
  // to none of the last 7 pixel columns, flat within 1-2 mm of it. As the front's fringe
  // (intersections.fringe_px) they measure its edge with the table, the box's width.
  const PcdFrame pcd = LoadOrganizedPcd(SharedPath("data/osd_boxes_learn/pcd/learn17.pcd"), OpenNi());
  for (const int fringe : {8, 0}) {
    FrontendConfig config;
    config.intersections.fringe_px = fringe;
    const FrameModel model = MakeFrontend(config).Process(*pcd.cloud);
    const FrameObject* lower = Learn17LowerBox(model, pcd);
    ASSERT_NE(lower, nullptr) << "fringe_px " << fringe;
    const double labelled = LabelledExtent(pcd, 1, lower->axes.col(1));
    std::printf("learn17 lower box, fringe_px %d: %.1f cm wide (%s), labelled %.1f cm\n", fringe,
                100 * lower->dimensions[1], lower->dimension_complete[1] ? "whole" : "cut", 100 * labelled);
    ASSERT_TRUE(lower->dimension_complete[1]);
    if (fringe > 0) {
      EXPECT_NEAR(lower->dimensions[1], labelled, 0.01) << "m";
    } else {
      EXPECT_LT(lower->dimensions[1], labelled - 0.01) << "m";
    }
  }
}

TEST(RealFrames, OsdSurfacesAreTheTableThenEachBoxsFaces) {
  PLANEMAP_REQUIRE_SHARED("data/osd_boxes_learn/pcd/learn17.pcd");
  // What bench_frontend evaluates the segmenters' planes against: learn17's table, then the faces
  // of its two stacked boxes, as the tests above find them.
  const PcdFrame pcd = LoadOrganizedPcd(SharedPath("data/osd_boxes_learn/pcd/learn17.pcd"), OpenNi());
  std::vector<LabelledFace> expected = LabelledTable(*pcd.cloud, pcd.labels);
  ASSERT_EQ(expected.size(), 1u);
  for (const auto& [box, faces] : LabelledFaces(*pcd.cloud, pcd.labels)) expected.insert(expected.end(), faces.begin(), faces.end());
  const LabelledSurfaces surfaces = OsdSurfaces(*pcd.cloud, pcd.labels);
  ASSERT_EQ(surfaces.planes_camera.size(), expected.size());
  std::map<std::uint16_t, std::vector<int>> pixels;
  for (size_t i = 0; i < surfaces.labels.size(); ++i) {
    if (surfaces.labels.pixels()[i] != 0) pixels[surfaces.labels.pixels()[i]].push_back(static_cast<int>(i));
  }
  for (size_t k = 0; k < expected.size(); ++k) {
    const std::uint16_t surface = static_cast<std::uint16_t>(k + 1);
    EXPECT_EQ(pixels[surface], expected[k].points) << "surface " << surface;
    const Plane& plane = surfaces.planes_camera.at(surface);
    EXPECT_TRUE(plane.normal == expected[k].plane.normal && plane.offset == expected[k].plane.offset) << "surface " << surface;
  }
}

TEST(RealFrames, TumOfficeFramesGivePlanesAndNoInventedObjects) {
  PLANEMAP_REQUIRE_SHARED("data/tum_frame_pairs");
  PLANEMAP_REQUIRE_SHARED("data/tum_fr1_rpy_slice");
  const Frontend frontend = MakeFrontend();
  int frames = 0;
  for (const std::string dir : {"data/tum_frame_pairs/fr1_xyz", "data/tum_frame_pairs/fr3_long_office_household", "data/tum_fr1_rpy_slice"}) {
    const TumSequence sequence = TumSequence::Open(SharedPath(dir), OpenNi());
    for (size_t k = 0; k < sequence.size(); k += 25) {
      const FrameModel model = frontend.Process(sequence.LoadFrame(k));
      ++frames;
      int large = 0;
      for (const DetectedPlane& p : model.planes) large += p.inliers.size() >= 10000;
      std::map<std::string, int> classes;
      for (const FrameObject& o : model.objects) ++classes[o.label];
      std::string summary;
      for (const auto& [c, n] : classes) summary += " " + std::to_string(n) + " " + c;
      std::printf("%s #%zu: %zu planes (%d with 10k+ points), floor %s, %zu angles, objects:%s\n", dir.c_str(), k,
                  model.planes.size(), large, model.floor >= 0 ? "yes" : "no", model.angles.size(),
                  summary.empty() ? " none" : summary.c_str());
      EXPECT_GE(large, 2) << dir << " #" << k << ": desk, floor or walls";
      // An object's faces are never room structure, and every object rests on a trihedral angle
      // or is two faces meeting in a convex edge that stand on a support facing up, not one of them.
      for (const FrameObject& o : model.objects) {
        for (int p : o.planes) EXPECT_FALSE(model.structure[p]);
        if (!o.angles.empty()) continue;
        ASSERT_GE(o.support, 0);
        EXPECT_EQ(std::count(o.planes.begin(), o.planes.end(), o.support), 0);
        EXPECT_GT(model.FacePlane(o.support).normal.dot(o.axes.col(2)), std::cos(30.0 / kRadToDeg));
        bool convex = false;
        for (const PlaneEdge& e : model.edges) {
          convex = convex || (e.convex && std::count(o.planes.begin(), o.planes.end(), e.plane_a) &&
                              std::count(o.planes.begin(), o.planes.end(), e.plane_b));
        }
        EXPECT_TRUE(convex);
      }
    }
  }
  EXPECT_GE(frames, 6);
}

}  // namespace
}  // namespace planemap

namespace planemap {
namespace {

TEST(PcdSource, BadFilesAreErrorsNamingTheFile) {
  testing::TempDir dir;
  const CameraIntrinsics camera = OpenNi();
  auto header = [](int width, int height, const std::string& fields, int points) {
    return "# .PCD v0.7\nVERSION 0.7\nFIELDS " + fields + "\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " +
           std::to_string(width) + "\nHEIGHT " + std::to_string(height) + "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
           std::to_string(points) + "\nDATA ascii\n";
  };
  const std::string missing = dir.path() + "/missing.pcd";
  EXPECT_TRUE(testing::ThrowsWith([&] { LoadOrganizedPcd(missing, camera); }, {missing, "no such PCD file"}));
  // Once a crash in PCL's reader: a file whose header gives no points.
  const std::string garbage = dir.Write("garbage.pcd", "not a point cloud\n");
  EXPECT_TRUE(testing::ThrowsWith([&] { LoadOrganizedPcd(garbage, camera); }, {garbage, "not a PCD file"}));
  const std::string unorganized = dir.Write("unorganized.pcd", header(3, 1, "x y z", 3) + "0 0 1\n0 1 1\n1 0 1\n");
  EXPECT_TRUE(testing::ThrowsWith([&] { LoadOrganizedPcd(unorganized, camera); }, {unorganized, "WIDTH 3 but the camera's is 640", "organized"}));
  const std::string no_z = dir.Write("no_z.pcd", header(640, 480, "x y w", 640 * 480) + "0 0 1\n");
  EXPECT_TRUE(testing::ThrowsWith([&] { LoadOrganizedPcd(no_z, camera); }, {no_z, "no 'z' field"}));
  const std::string truncated = dir.Write("truncated.pcd", header(640, 480, "x y z", 640 * 480) + "0 0 1\n0 1 1\n");
  EXPECT_TRUE(testing::ThrowsWith([&] { LoadOrganizedPcd(truncated, camera); }, {truncated, "truncated or corrupt"}));
}

// The header is read against the PCD format before PCL sees it: PCL's reader takes keys by prefix,
// lets a later line redefine the fields and allocates what the header claims (fuzz_pcd).
TEST(PcdSource, HeadersOutsideTheFormatAreErrorsNamingTheLine) {
  testing::TempDir dir;
  CameraIntrinsics camera;
  camera.width = 2;
  camera.height = 1;
  const std::string good =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n0.1 0.2 1.5\nnan nan nan\n";
  const std::string file = dir.Write("good.pcd", good);
  const PcdFrame frame = LoadOrganizedPcd(file, camera);
  EXPECT_NEAR((*frame.cloud)[0].z, 1.5f, 1e-6f);
  EXPECT_TRUE(std::isnan((*frame.cloud)[1].z));
  // Each case: a header line replaced (by its key), and the error that names it.
  auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return dir.Write("bad.pcd", text);
  };
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"SIZE 4 4 4", "SIZEx 4 4 4", ":4: not a PCD file ('SIZEx' is no header key)"},
      {"SIZE 4 4 4", "SIZE 4 4", ":4: not a PCD file (SIZE has 2 value(s), 3 expected (one for each field))"},
      {"SIZE 4 4 4", "SIZE 4 4 3", ":4: not a PCD file (SIZE 3 is no field size"},
      {"TYPE F F F", "TYPE F F D", ":5: not a PCD file (TYPE 'D' is none of F, I, U)"},
      {"COUNT 1 1 1", "COUNT 1 1 -1", ":6: not a PCD file (COUNT '-1' is no number)"},
      {"WIDTH 2\nHEIGHT 1", "HEIGHT 1\nWIDTH 2", ":7: not a PCD file (no WIDTH before HEIGHT)"},
      {"VERSION 0.7\nFIELDS x y z", "FIELDS x y z\nVERSION 0.7", ":3: not a PCD file (VERSION after FIELDS; the header's keys"},
      {"HEIGHT 1\n", "HEIGHT 1\nHEIGHT 1\n", ":9: not a PCD file (HEIGHT given twice"},
      {"VIEWPOINT 0 0 0 1 0 0 0", "VIEWPOINT 0 0 0 1 0 0", ":9: not a PCD file (VIEWPOINT has 6 value(s), 7 expected)"},
      {"POINTS 2\n", "", ":10: not a PCD file (no POINTS before DATA)"},
      {"DATA ascii", "DATA asci", ":11: not a PCD file (DATA 'asci' is none of ascii, binary, binary_compressed)"},
      {"FIELDS x y z", std::string("FIELDS x y\x01 z"), ":3: not a PCD file (a header line holds the byte 0x01)"},
  };
  for (const auto& [from, to, what] : cases) {
    const std::string bad = with(from, to);
    EXPECT_TRUE(testing::ThrowsWith([&] { LoadOrganizedPcd(bad, camera); }, {bad + what})) << to;
  }
}

// A real frame cut short inside its compressed data.
TEST(PcdSource, ARealFrameCutShortIsAnErrorNamingTheFile) {
  PLANEMAP_REQUIRE_SHARED("data/osd_boxes_learn/pcd/learn2.pcd");
  testing::TempDir dir;
  const CameraIntrinsics camera = OpenNi();
  std::ifstream in(SharedPath("data/osd_boxes_learn/pcd/learn2.pcd"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string cut = dir.Write("cut.pcd", bytes.substr(0, bytes.size() / 2));
  EXPECT_TRUE(testing::ThrowsWith([&] { LoadOrganizedPcd(cut, camera); }, {cut, "truncated or corrupt"}));
}

}  // namespace
}  // namespace planemap
