#pragma once
// What the frontend sees in one frame, as plain data: planes, their real intersections, the
// plane graph's trihedral angles (corners). Camera optical frame throughout.
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planemap/core/detected_plane.h"

namespace planemap {

// A real intersection of two planes (paper eqs. 2-6): where their inliers meet.
struct PlaneEdge {
  int plane_a = -1, plane_b = -1;  // plane ids, plane_a < plane_b
  Eigen::Vector3d start = Eigen::Vector3d::Zero();  // segment on the planes' intersection line [m]
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit, from start to end
  double length = 0.0;       // extent of the edge points along the line [m]
  double length_eq6 = 0.0;   // the paper's eq. (6): sqrt(d_diagonal^2 - 4 d_thresh^2) [m]
  int points = 0;            // inliers of either plane within d_thresh of both
  // An end is cut when it lies at the image border or next to pixels without depth: the edge
  // may go on beyond it, so its length only bounds the true length from below.
  bool start_cut = false, end_cut = false;
  // Convex (a box's own edge): each plane's points beside the edge lie behind the other plane,
  // as on a solid's faces. Concave: one plane runs on in front of the other, as the table under
  // a box or a box standing on another one.
  bool convex = true;
  // Hidden: not seen but inferred, a solid's edge behind an occluder (see IntersectionConfig::
  // hidden_edges). It runs between the two corners it was inferred from, or from the one as far
  // as its two faces reach, its far end cut. points and length_eq6 are 0.
  bool hidden = false;
  bool Complete() const { return !start_cut && !end_cut; }
};

// A corner: three planes that meet pairwise (a 3-cycle of the plane graph).
struct TrihedralAngle {
  std::array<int, 3> planes{};  // plane ids of its faces (a face in pieces: its lowest-id piece), increasing
  std::array<int, 3> edges{};   // indices into FrameModel::edges: (p0,p1), (p0,p2), (p1,p2)
  Eigen::Vector3d corner = Eigen::Vector3d::Zero();  // the point on all three planes [m]
};

// Trihedral angles that share graph edges, aggregated angle by angle: one plane-based object.
struct FrameObject {
  std::vector<int> planes;  // plane ids of the object's faces, every piece of a face in pieces
                            // (never the floor or other structure)
  std::vector<int> angles;  // indices into FrameModel::angles; empty for an object of two faces
  // The plane the object stands on (the floor, a table, another object's top), for an object of
  // two faces (a top and a front, or two sides, meeting in a convex edge), which needs one; -1
  // for an object built from trihedral angles.
  int support = -1;
  std::string label = "unknown";  // class from the graph patterns

  // Geometry (camera frame). Axes: columns x, y, z with z up (the floor's normal), x the normal
  // of the object's largest vertical face.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d dimensions = Eigen::Vector3d::Zero();  // longest edge along each axis [m]
  std::array<bool, 3> dimension_complete{};              // that edge is fully visible
  double height = 0.0;  // highest point above the floor (vertical extent without a floor) [m]
  // The top was seen or a vertical edge is whole: `height` is measured, not only a lower bound,
  // and a class that depends on it is decided rather than guessed.
  bool height_known = false;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();      // eq. (7), mean over the angles [m]
  std::vector<int> grasp_sides;  // plane ids of faces a two-handed grasp could hold (a face in
                                 // pieces: its lowest-id piece; its axis the face's plane's)
  int grasp_side = -1;           // the chosen one (most facing the camera), -1 if none
  Eigen::Vector3d grasp_axis = Eigen::Vector3d::Zero();  // its normal (toward the camera)
};

struct FrameModel {
  std::vector<DetectedPlane> planes;
  std::vector<PlaneEdge> edges;
  std::vector<TrihedralAngle> angles;
  std::vector<FrameObject> objects;
  int floor = -1;                 // plane id of the floor, -1 if not seen
  std::vector<bool> structure;    // per plane: floor, walls and other room-sized planes
  std::string reason;  // why the model is empty or partial; empty when all is well
  // Faces in pieces (FindFaces): per plane, the plane standing for its face (the lowest id of
  // the face's pieces, its own id when it is a face alone), and the face's plane fitted to all
  // its pieces' inliers. Empty: every plane is a face of its own.
  std::vector<int> face_of;
  std::vector<Plane> face_plane;
  int FaceOf(int plane) const { return plane < static_cast<int>(face_of.size()) ? face_of[plane] : plane; }
  const Plane& FacePlane(int plane) const {
    return plane < static_cast<int>(face_plane.size()) ? face_plane[plane] : planes[plane].plane;
  }

  // Index into `edges` of the edge between two planes, or -1.
  int EdgeBetween(int a, int b) const;
};

}  // namespace planemap
