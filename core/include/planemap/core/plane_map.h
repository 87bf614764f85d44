#pragma once
// The map of a run: plane landmarks, the real intersections between them, the objects built on
// them, and keyframes (paper section 4.2). World frame throughout. Its size grows with the number
// of planes and objects, not with frames: each landmark keeps fixed-size point moments and a
// voxel sample of its surface whose size is bounded by the plane's area.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "planemap/core/detected_plane.h"
#include "planemap/core/plane.h"
#include "planemap/core/pose.h"

namespace planemap {

struct PlaneLandmark {
  int id = 0;                       // index in PlaneMap::landmarks
  Plane plane;                      // world frame; normal toward the cameras that saw it
  PointMoments moments;             // weighted sums of every inlier it was fit from (world)
  Eigen::Vector3d low = Eigen::Vector3d::Constant(1e30);    // extent of its inliers [m]
  Eigen::Vector3d high = Eigen::Vector3d::Constant(-1e30);
  std::vector<Eigen::Vector3f> points;  // one point per voxel of its surface (world) [m]
  int observations = 0;             // frames that saw it
  int floor_votes = 0;              // frames that took it for the floor
  int first_frame = -1, last_frame = -1;

  bool Overlaps(const Eigen::Vector3d& low_other, const Eigen::Vector3d& high_other, double margin) const {
    return Box3{low, high}.Overlaps(Box3{low_other, high_other}, margin);
  }
  // The diagonal of its inliers' box [m]; 0 before any inlier.
  double Extent() const { return low.x() <= high.x() ? (high - low).norm() : 0.0; }
};

// A real intersection of two landmarks; the merged edge is the longest one seen (paper, Fig. 4).
struct MapEdge {
  int landmark_a = -1, landmark_b = -1;  // landmark_a < landmark_b
  Eigen::Vector3d start = Eigen::Vector3d::Zero(), end = Eigen::Vector3d::Zero();  // [m]
  double length = 0.0;                   // [m]
  bool complete = false;                 // seen with neither end cut at least once
  int observations = 0;
  int convex_views = 0, concave_views = 0;  // how each view judged it (see PlaneEdge::convex)
  bool Convex() const { return convex_views >= concave_views; }
};

struct MapObject {
  int id = 0;
  std::string label = "unknown";
  std::vector<int> landmarks;            // its faces
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns x, y, z (z up), as FrameObject
  Eigen::Vector3d dimensions = Eigen::Vector3d::Zero();  // [m]
  std::array<bool, 3> dimension_complete{};
  Eigen::Vector3d center = Eigen::Vector3d::Zero();       // eq. (7), averaged over observations [m]
  bool has_grasp_axis = false;
  Eigen::Vector3d grasp_axis = Eigen::Vector3d::Zero();   // unit, world
  int observations = 0;
  // Running sums behind the averages: per axis, the complete observations of that dimension;
  // the centre from views where all three dimensions were complete (else from every view).
  std::array<int, 3> complete_count{};
  Eigen::Vector3d complete_sum = Eigen::Vector3d::Zero();
  int center_count = 0, partial_center_count = 0;
  Eigen::Vector3d center_sum = Eigen::Vector3d::Zero(), partial_center_sum = Eigen::Vector3d::Zero();
  std::vector<std::pair<std::string, int>> label_votes;  // the label is the most voted class
  std::vector<std::pair<int, int>> grasp_votes;          // (landmark, times chosen as grasp side)
  int grasp_landmark = -1;                               // the most chosen: the grasp axis is its normal
  int x_landmark = -1;                                   // the face whose normal is the x axis
  // A moved object (TrackingConfig::object_moved_*): its estimate restarts from the views that
  // saw it where it is now; views before since_frame saw it elsewhere.
  int moves = 0;         // times it was seen moved
  int since_frame = -1;  // the first frame of the views its estimate rests on
  int moved_views = 0;   // views in a row that disagree with the estimate
  int moved_from_frame = -1;  // the first of them
  // A face of it turned out to be room structure (TrackingConfig::structure_min_extent): a wall's
  // piece, seen near by, taken for a face before the map knew the wall. It is no object: every
  // reader of the map passes over it; it stays in the list so that object ids stay what they were.
  bool structure = false;
  // How certain the estimate is: marginals of the back end's solution (ceres::Covariance), set
  // when it refined the object as a cuboid. A dimension only bounded from below (held at its
  // bound) has no standard deviation (-1).
  struct Uncertainty {
    bool known = false;
    Eigen::Matrix3d dimension_covariance = Eigen::Matrix3d::Zero();  // [m^2]
    Eigen::Vector3d dimension_std = Eigen::Vector3d::Constant(-1.0);  // [m]
    Eigen::Matrix3d center_covariance = Eigen::Matrix3d::Zero();     // world axes [m^2]
    Eigen::Vector3d axes_std_deg = Eigen::Vector3d::Zero();          // direction of each box axis [deg]
    double grasp_axis_std_deg = -1.0;                                // [deg], -1 without a grasp axis
  } uncertainty;
};

// The turn about the vertical from one box's axes to another's [rad], in [-pi/4, pi/4]: a box's
// axes are known only up to a quarter turn.
inline double QuarterTurn(const Eigen::Matrix3d& from, const Eigen::Matrix3d& to) {
  return std::remainder(std::atan2(to(1, 0), to(0, 0)) - std::atan2(from(1, 0), from(0, 0)), M_PI / 2.0);
}

// The share of the smaller of two cuboids (centre, axes as columns, dimensions) that lies inside
// the other, in [0, 1]: the second is boxed in the first's axes, exact when they differ by quarter
// turns about the vertical (upright objects). Dimensions under min_dimension count as it [m].
double CuboidOverlap(const Eigen::Vector3d& center_a, const Eigen::Matrix3d& axes_a, const Eigen::Vector3d& dimensions_a,
                     const Eigen::Vector3d& center_b, const Eigen::Matrix3d& axes_b, const Eigen::Vector3d& dimensions_b,
                     double min_dimension = 0.01);

struct Keyframe {
  int frame = 0;
  double stamp = 0.0;
  Pose3 T_world_camera = Pose3::Identity();
};

struct PlaneMap {
  std::vector<PlaneLandmark> landmarks;
  std::vector<MapEdge> edges;
  std::vector<MapObject> objects;
  std::vector<Keyframe> keyframes;

  // Index into `edges` of the edge between two landmarks, or -1.
  int EdgeBetween(int a, int b) const;
  // The landmark most often taken for the floor, or -1.
  int Floor() const;
  // Bytes held: the structs and their vectors' contents.
  std::size_t MemoryBytes() const;
};

// A voxel's key (cells of `voxel` metres, |coordinates| below 2^20 cells): a landmark keeps
// one point per key.
long long VoxelKey(const Eigen::Vector3f& p, double voxel);

// The most voted key (the first on a tie); `votes` is not empty.
template <typename Key>
Key Winner(const std::vector<std::pair<Key, int>>& votes) {
  return std::max_element(votes.begin(), votes.end(), [](const auto& x, const auto& y) { return x.second < y.second; })->first;
}

// Counts `weight` votes for `key` and returns the most voted key.
template <typename Key>
Key Vote(std::vector<std::pair<Key, int>>* votes, const Key& key, int weight = 1) {
  auto it = std::find_if(votes->begin(), votes->end(), [&](const auto& v) { return v.first == key; });
  if (it == votes->end()) {
    votes->emplace_back(key, weight);
  } else {
    it->second += weight;
  }
  return Winner(*votes);
}

// Moves every part of the map by T (world -> T * world): planes, moments, points, extents,
// edges, objects and keyframes.
void TransformMap(const Pose3& T, PlaneMap* map);

}  // namespace planemap
