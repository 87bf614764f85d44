#pragma once
// The pre-grasp pose and the grasp check (paper section 4.1-4.2: the object's centre and the axis
// of the side chosen for grasping drive the approach). The robot stands facing the grasp side,
// the hands close on the two vertical faces to its left and right, at the object's centre height.
//
// Arm model: a small humanoid (Nao-like) crouched in front of an object on the floor, its torso
// leaning forward; each hand reaches a shell around its shoulder. World z = 0 is the floor.
//
// Where to stand has no free parameter: along the grasp axis, the base may stand no nearer than
// the object's near face plus body_clearance (the toes) and no farther than where a hand still
// reaches its grasp point, even turned by a few degrees. The robot aims at the middle of that band, so an error toward the object
// and one away from it are tolerated alike, and of the object's sides it grasps from the one,
// facing it, whose band is widest.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/plane_map.h"
#include "planemap/nav/pose2.h"

namespace planemap::nav {

struct GraspConfig {
  double body_clearance = 0.09;    // base origin to the object's near face, at least: toes (8 cm) + gap [m]
  double shoulder_forward = 0.05;  // shoulder joints ahead of the base origin (leaning torso) [m]
  double shoulder_lateral = 0.10;  // each shoulder to the side of the base origin [m]
  double shoulder_height = 0.26;   // shoulders above the floor, crouched [m]
  double reach_min = 0.19;         // a hand's grasp point from its shoulder, nearest [m]
  double reach_max = 0.265;        // ... farthest [m]
  double hand_span_min = 0.10;     // narrowest object across the grasp points [m]
  double hand_span_max = 0.40;     // widest [m]
  double heading_tolerance_deg = 5.0;  // the standoff band keeps the grasp with the robot turned this much [deg]
  // A face's mapped plane places the object along its axis (AnchoredToMappedFaces) when it is
  // this parallel to that face [deg] ...
  double face_anchor_max_angle_deg = 10.0;
  int face_anchor_min_views = 3;  // ... and seen in this many frames

  template <class V>
  void VisitFields(V&& v) {
    v("body_clearance", body_clearance, Check::kNonNegative);
    v("shoulder_forward", shoulder_forward, Check::kAny);
    v("shoulder_lateral", shoulder_lateral, Check::kNonNegative);
    v("shoulder_height", shoulder_height, Check::kPositive);
    v("reach_min", reach_min, Check::kNonNegative);
    v("reach_max", reach_max, Check::kPositive);
    v("hand_span_min", hand_span_min, Check::kNonNegative);
    v("hand_span_max", hand_span_max, Check::kPositive);
    v("heading_tolerance_deg", heading_tolerance_deg, Check::kNonNegative);
    v("face_anchor_max_angle_deg", face_anchor_max_angle_deg, Check::kPositive);
    v("face_anchor_min_views", face_anchor_min_views, Check::kNonNegative);
  }
};

// How an object is grasped: from which side, and where the hands close.
struct GraspGeometry {
  Eigen::Vector2d axis = Eigen::Vector2d::UnitX();  // g: horizontal, unit, out of the grasp face (world)
  double depth = 0.0;                               // object's extent along g [m]
  double width = 0.0;                               // across g, between the grasp points [m]
  Eigen::Vector3d left = Eigen::Vector3d::Zero();   // grasp points (world), left and right as
  Eigen::Vector3d right = Eigen::Vector3d::Zero();  // seen by a robot facing -g [m]
};

// The faces of the footprint side, of +-x and +-y, closest to `side` (world xy).
GraspGeometry GraspFaces(const MapObject& object, const Eigen::Vector2d& side);

// The standoffs (object centre to base origin, along the grasp axis) from which the robot can grasp
// those faces: near = the toes' clearance (or reach_min), far = where a hand, with the robot turned
// by heading_tolerance_deg, is at reach_max [m]. Empty if far < near.
struct StandoffBand {
  double near = 0.0;
  double far = 0.0;
  bool Empty() const { return far < near; }
  double Width() const { return far - near; }
  double Middle() const { return 0.5 * (near + far); }
};
StandoffBand GraspBand(const MapObject& object, const GraspGeometry& faces, const GraspConfig& config);

// Every side whose width fits the hand span and whose standoff band is not empty, as unit world
// xy axes out of those faces, in order of preference: facing the robot (`toward_robot`, from the
// object toward the robot) first, then the widest band. Empty when none is.
std::vector<Eigen::Vector2d> GraspSides(const MapObject& object, const GraspConfig& config,
                                        const Eigen::Vector2d& toward_robot);

// The side to grasp from, as a unit world xy axis out of that face: of the sides whose width fits
// the hand span and whose standoff band is not empty, the one with the widest band among those
// facing the robot (`toward_robot`, from the object toward the robot), else among all. Without
// any such side: the object's grasp axis from the frontend if horizontal, else the side closest to
// the robot, and the grasp check will say why it fails.
Eigen::Vector2d ChooseGraspSide(const MapObject& object, const GraspConfig& config,
                                const Eigen::Vector2d& toward_robot);

// The object as the hands meet it: along each horizontal axis of its footprint, its centre moved
// so that a face lies on its mapped plane (the object's face landmark most seen along that axis,
// at least face_anchor_min_views, within face_anchor_max_angle_deg of it, and no farther from
// where the dimensions put that face than half the extent). The map's centre is the mean of
// every view's (eq. 7), and views that saw the box in part guess its hidden sides: the centre can
// lie centimetres off the faces the robot sees close up (generated room 43: 6.8 cm across the
// grasp axis, the face right to 0.2 cm), and the standoff and the grasp points are placed from
// it. An axis without such a face keeps the map's centre. Only the grasp geometry takes it:
// matching, the grid and the search keep the map's centre.
MapObject AnchoredToMappedFaces(const MapObject& object, const std::vector<PlaneLandmark>& landmarks,
                                const GraspConfig& config);

// Where the robot stands to grasp from the side closest to `side`: centre_xy + g * the middle of
// the standoff band (its near end if the band is empty), facing -g (the camera's main axis along
// the grasp axis).
Pose2 PreGraspPose(const MapObject& object, const GraspConfig& config, const Eigen::Vector2d& side);

struct GraspCheck {
  bool ok = false;
  std::string reason;                                     // the first check that failed
  double width = 0.0;                                     // across the grasp points [m]
  Eigen::Vector3d left_point = Eigen::Vector3d::Zero();   // base frame (x forward, y left, z up) [m]
  Eigen::Vector3d right_point = Eigen::Vector3d::Zero();  // [m]
  double left_distance = 0.0;                             // each point to its shoulder [m]
  double right_distance = 0.0;                            // [m]
};

// Whether the robot at `robot` can grasp the object: the width within the hand span, and each
// grasp point ahead of the shoulders and inside its arm's reach shell [reach_min, reach_max]
// around its shoulder; the faces are the side the robot stands at. Defaults: the default scene's box
// (grasped across its 0.35 m) passes with the robot up to 2 cm and 5 deg off its pre-grasp pose,
// and fails from 10 cm off.
GraspCheck CheckGrasp(const MapObject& object, const Pose2& robot, const GraspConfig& config);

}  // namespace planemap::nav
