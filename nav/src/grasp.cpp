#include "planemap/nav/grasp.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "planemap/nav/planner.h"

namespace planemap::nav {
namespace {

// A grasp axis steeper than this (a top face's normal) names no side to stand at: |horizontal part|.
constexpr double kMinHorizontal = M_SQRT1_2;

// Of the footprint's side directions +-x, +-y, the one closest to `direction`.
Eigen::Vector2d ClosestSide(const Footprint& footprint, const Eigen::Vector2d& direction) {
  const Eigen::Vector2d d = direction.norm() > 1e-9 ? direction : Eigen::Vector2d(footprint.axes.col(0));
  Eigen::Vector2d best = footprint.axes.col(0);
  double best_dot = -2.0;
  for (int s = 0; s < 2; ++s) {
    for (double sign : {1.0, -1.0}) {
      const Eigen::Vector2d side = sign * footprint.axes.col(s);
      if (side.dot(d) > best_dot + 1e-12) {
        best_dot = side.dot(d);
        best = side;
      }
    }
  }
  return best;
}

Eigen::Vector3d InBase(const Pose2& robot, const Eigen::Vector3d& world) {
  const Pose2 local = Between(robot, Pose2{world.x(), world.y(), 0.0});
  return {local.x, local.y, world.z()};
}

std::string Centimetres(const char* format, double a, double b) {
  char text[160];
  std::snprintf(text, sizeof(text), format, 100.0 * a, 100.0 * b);
  return text;
}

// The reason a grasp point (base frame) at `distance` from its shoulder is out of reach, or "".
// Arms reach forward: a point behind the shoulders is out of reach whatever its distance.
std::string ReachProblem(const char* side, const Eigen::Vector3d& point, double distance,
                         const GraspConfig& config) {
  const std::string prefix = std::string(side) + " grasp point is ";
  if (point.x() <= config.shoulder_forward)
    return prefix + Centimetres("%.1f cm ahead of the base, not ahead of the shoulders (%.1f cm)", point.x(),
                                config.shoulder_forward);
  if (distance < config.reach_min)
    return prefix + Centimetres("%.1f cm from its shoulder, nearer than reach_min %.1f cm", distance,
                                config.reach_min);
  if (distance > config.reach_max)
    return prefix +
           Centimetres("%.1f cm from its shoulder, beyond reach_max %.1f cm", distance, config.reach_max);
  return "";
}

}  // namespace

GraspGeometry GraspFaces(const MapObject& object, const Eigen::Vector2d& side) {
  const Footprint footprint = FootprintOf(object);
  GraspGeometry geometry;
  geometry.axis = ClosestSide(footprint, side);
  const int along =
      std::abs(geometry.axis.dot(footprint.axes.col(0))) >= std::abs(geometry.axis.dot(footprint.axes.col(1)))
          ? 0
          : 1;
  geometry.depth = 2.0 * footprint.half_size[along];
  geometry.width = 2.0 * footprint.half_size[1 - along];
  // A robot facing -g has its left along g turned by -90 deg.
  const Eigen::Vector2d left(geometry.axis.y(), -geometry.axis.x());
  const Eigen::Vector2d centre = object.center.head<2>();
  const Eigen::Vector2d l = centre + 0.5 * geometry.width * left, r = centre - 0.5 * geometry.width * left;
  geometry.left = {l.x(), l.y(), object.center.z()};
  geometry.right = {r.x(), r.y(), object.center.z()};
  return geometry;
}

StandoffBand GraspBand(const MapObject& object, const GraspGeometry& faces, const GraspConfig& config) {
  // A grasp point at standoff s is (s, +-width/2, centre height) in the base frame; its shoulder
  // is at (shoulder_forward, +-shoulder_lateral, shoulder_height). The hand reaches it when
  // reach_min <= |point - shoulder| <= reach_max, and the point is ahead of the shoulder.
  const double half_width = 0.5 * faces.width;
  const double vertical = object.center.z() - config.shoulder_height;
  const double lateral = half_width - config.shoulder_lateral;
  StandoffBand band;
  const double near_reach = config.reach_min * config.reach_min - lateral * lateral - vertical * vertical;
  band.near = std::max(0.5 * faces.depth + config.body_clearance,
                       config.shoulder_forward + std::sqrt(std::max(0.0, near_reach)));
  // Far: both hands still reach with the robot turned by up to heading_tolerance either way. The
  // reach grows with s beyond the shoulders, so bisect between the near end and past any reach.
  const double tolerance = config.heading_tolerance_deg * M_PI / 180.0;
  const auto reaches = [&](double s) {
    for (double turn : {-tolerance, 0.0, tolerance}) {
      for (double side : {1.0, -1.0}) {
        const double x = s * std::cos(turn) + side * half_width * std::sin(turn);
        const double y = -s * std::sin(turn) + side * half_width * std::cos(turn);
        const Eigen::Vector3d offset(x - config.shoulder_forward, std::abs(y) - config.shoulder_lateral, vertical);
        if (x <= config.shoulder_forward || offset.norm() > config.reach_max) return false;
      }
    }
    return true;
  };
  if (!reaches(band.near)) {
    band.far = -std::numeric_limits<double>::infinity();
    return band;
  }
  double lo = band.near, hi = config.shoulder_forward + config.reach_max + half_width;
  for (int k = 0; k < 50; ++k) {
    const double mid = 0.5 * (lo + hi);
    (reaches(mid) ? lo : hi) = mid;
  }
  band.far = lo;
  return band;
}

std::vector<Eigen::Vector2d> GraspSides(const MapObject& object, const GraspConfig& config,
                                        const Eigen::Vector2d& toward_robot) {
  const Footprint footprint = FootprintOf(object);
  const Eigen::Vector2d toward = toward_robot.norm() > 1e-9 ? Eigen::Vector2d(toward_robot.normalized())
                                                            : Eigen::Vector2d(footprint.axes.col(0));
  struct Side {
    Eigen::Vector2d axis;
    bool facing;
    double width;
  };
  std::vector<Side> feasible;
  for (int s = 0; s < 2; ++s) {
    for (double sign : {1.0, -1.0}) {
      const Eigen::Vector2d side = sign * footprint.axes.col(s);
      const GraspGeometry faces = GraspFaces(object, side);
      if (faces.width < config.hand_span_min || faces.width > config.hand_span_max) continue;
      const StandoffBand band = GraspBand(object, faces, config);
      if (band.Empty()) continue;
      feasible.push_back({side, side.dot(toward) > 0.0, band.Width()});
    }
  }
  // A feasible side facing the robot beats one facing away; among equals, the widest band wins.
  std::stable_sort(feasible.begin(), feasible.end(), [](const Side& a, const Side& b) {
    if (a.facing != b.facing) return a.facing;
    return a.width > b.width;
  });
  std::vector<Eigen::Vector2d> sides;
  for (const Side& s : feasible) sides.push_back(s.axis);
  return sides;
}

Eigen::Vector2d ChooseGraspSide(const MapObject& object, const GraspConfig& config,
                                const Eigen::Vector2d& toward_robot) {
  const std::vector<Eigen::Vector2d> sides = GraspSides(object, config, toward_robot);
  if (!sides.empty()) return sides.front();
  const Footprint footprint = FootprintOf(object);
  const Eigen::Vector2d toward = toward_robot.norm() > 1e-9 ? Eigen::Vector2d(toward_robot.normalized())
                                                            : Eigen::Vector2d(footprint.axes.col(0));
  const Eigen::Vector2d horizontal = object.grasp_axis.head<2>();
  if (object.has_grasp_axis && horizontal.norm() >= kMinHorizontal * object.grasp_axis.norm())
    return ClosestSide(footprint, horizontal);
  return ClosestSide(footprint, toward);
}

MapObject AnchoredToMappedFaces(const MapObject& object, const std::vector<PlaneLandmark>& landmarks,
                                const GraspConfig& config) {
  const Footprint footprint = FootprintOf(object);
  const double min_cos = std::cos(config.face_anchor_max_angle_deg * M_PI / 180.0);
  MapObject anchored = object;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector3d a(footprint.axes(0, k), footprint.axes(1, k), 0.0);
    const double half = footprint.half_size[k];
    double shift = 0.0;
    int views = -1;
    for (int id : object.landmarks) {
      if (id < 0 || id >= static_cast<int>(landmarks.size()) || landmarks[id].id != id) continue;
      const PlaneLandmark& l = landmarks[id];
      const double cos = l.plane.normal.dot(a);
      if (std::abs(cos) < min_cos || l.observations < config.face_anchor_min_views || l.observations <= views) continue;
      // The plane n . p + d = 0 meets the line centre + t a at t; the face there is on the side of t.
      const double t = -(l.plane.normal.dot(object.center) + l.plane.offset) / cos;
      const double face = t >= 0.0 ? half : -half;
      if (std::abs(t - face) > half) continue;  // the face beyond the whole extent, or past the centre
      shift = t - face;
      views = l.observations;
    }
    anchored.center += shift * a;
  }
  return anchored;
}

Pose2 PreGraspPose(const MapObject& object, const GraspConfig& config, const Eigen::Vector2d& side) {
  const GraspGeometry geometry = GraspFaces(object, side);
  const StandoffBand band = GraspBand(object, geometry, config);
  const double standoff = band.Empty() ? band.near : band.Middle();
  const Eigen::Vector2d p = object.center.head<2>() + standoff * geometry.axis;
  return {p.x(), p.y(), std::atan2(-geometry.axis.y(), -geometry.axis.x())};
}

GraspCheck CheckGrasp(const MapObject& object, const Pose2& robot, const GraspConfig& config) {
  const GraspGeometry geometry = GraspFaces(object, robot.Position() - object.center.head<2>());
  GraspCheck check;
  check.width = geometry.width;
  check.left_point = InBase(robot, geometry.left);
  check.right_point = InBase(robot, geometry.right);
  if (check.left_point.y() < check.right_point.y()) std::swap(check.left_point, check.right_point);
  const Eigen::Vector3d shoulder(config.shoulder_forward, config.shoulder_lateral, config.shoulder_height);
  check.left_distance = (check.left_point - shoulder).norm();
  check.right_distance =
      (check.right_point - Eigen::Vector3d(shoulder.x(), -shoulder.y(), shoulder.z())).norm();
  if (check.width < config.hand_span_min) {
    check.reason = Centimetres("object is %.1f cm across, narrower than hand_span_min %.1f cm", check.width,
                               config.hand_span_min);
  } else if (check.width > config.hand_span_max) {
    check.reason = Centimetres("object is %.1f cm across, wider than hand_span_max %.1f cm", check.width,
                               config.hand_span_max);
  } else {
    check.reason = ReachProblem("left", check.left_point, check.left_distance, config);
    if (check.reason.empty())
      check.reason = ReachProblem("right", check.right_point, check.right_distance, config);
  }
  check.ok = check.reason.empty();
  return check;
}

}  // namespace planemap::nav
