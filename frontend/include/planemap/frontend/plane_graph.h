#pragma once
// Step 4 of the frontend: the plane graph (node = plane, edge = real intersection), its trihedral
// angles (3-cycles) with their corners, the floor and other structure, and objects aggregated
// from trihedral angles that share a graph edge, angle by angle (paper section 4.1).
#include <cmath>
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/frame_model.h"
#include "planemap/frontend/organized_cloud.h"

namespace planemap {

struct PlaneGraphConfig {
  // Where "up" is in the camera frame before anything is known; the default is a camera looking
  // 20 deg down, as on the Nao's head. The floor is the lowest plane (largest offset) within
  // floor_max_angle_deg of it, below the camera and with floor_min_inliers or more: it lies under
  // every object, so a box's top, also horizontal, is never taken for it.
  std::vector<double> up_in_camera{0.0, -0.9397, -0.3420};
  double floor_max_angle_deg = 45.0;    // [deg]
  int floor_min_inliers = 5000;         // [px]
  double floor_min_distance = 0.2;      // the floor lies at least this far below the camera [m]
  double structure_min_extent = 2.0;    // planes whose inliers span more are room structure [m]
  double corner_max_distance = 0.1;     // a trihedral corner lies this close to its three edges [m]
  double corner_snap_distance = 0.03;   // an edge end this close to a corner ends at it [m]
  double corner_min_determinant = 0.3;  // |det(n1, n2, n3)|: below, the three planes are too close
                                        // to sharing a line for a stable corner
  double resting_max_tilt_deg = 30.0;   // a top and a face within this of horizontal and vertical
                                        // meeting in a concave edge: one object rests on another [deg]
  // One seen edge of a trihedral angle may reach the corner only along its line (within
  // corner_snap_distance of it), up to corner_past_cut_distance past an end of it that is cut,
  // when the other two end at the corner (a whole end of each within corner_snap_distance of
  // it): a ledge narrower than d_thresh has no band points beside the face it meets. 0: off. [m]
  double corner_past_cut_distance = 0.3;
  // Faces in pieces (FindFaces): two planes, neither structure nor meeting each other, within
  // face_piece_max_angle_deg of each other, that each meet a third plane in seen edges of one
  // kind (both convex or both concave) within that angle of each other, and whose
  // inliers lie within face_piece_max_rms (RMS, each piece's) of the plane fitted to both, are
  // pieces of one face: a box's top showing as two ledges beside a box standing on it, a side
  // in two planes. They must meet the third side by side: their edges' stretches along its line
  // overlap by at most face_piece_max_overlap (a rounded corner between a face and the third
  // plane meets the third right beside the face's own edge, across from it, not beside it); and
  // where the edges are concave (the pieces may be two objects standing on the third) they leave
  // a gap of at most face_piece_max_gap. 0 deg: off. [deg], [m], [m], [m]
  double face_piece_max_angle_deg = 10.0;
  double face_piece_max_rms = 0.005;
  double face_piece_max_overlap = 0.01;
  double face_piece_max_gap = 0.02;

  // Objects of two faces: two faces that are neither structure nor an object's already, at least
  // two_face_min_angle_deg apart, meeting in a seen convex edge (a box's top and front, or two
  // sides, its other faces turned away or hidden), where one vertical face stands on a support:
  // it meets, in a seen concave edge, a plane facing up (within resting_max_tilt_deg of up: the
  // floor, a table, another object's top), and a top lies at least two_face_min_height above
  // that support. A face stands on a support when at most two_face_below_share of its points lie
  // more than two_face_below_distance beneath it (a box behind a lower one meets that one's top
  // in a concave edge too, and goes on down past it); without a seen edge, when its lowest points
  // (1st percentile) also reach within two_face_support_gap of the support's plane, within its
  // points' bounding box grown by as much (a floor seen at a glancing angle, as from a camera
  // below a box's top, gives too few points beside the box for an edge). Of several supports,
  // one whose plane its lowest points reach within two_face_support_gap (the one with most points:
  // a floor in pieces), else the highest. 0 deg: off. [deg], [m],
  // [fraction], [m], [m]
  double two_face_min_angle_deg = 60.0;
  double two_face_min_height = 0.02;
  double two_face_below_share = 0.05;
  double two_face_below_distance = 0.02;
  double two_face_support_gap = 0.03;

  std::string CrossCheck() const {
    if (up_in_camera.size() != 3) return "up_in_camera needs 3 numbers";
    if (std::hypot(up_in_camera[0], up_in_camera[1], up_in_camera[2]) < 1e-6) return "up_in_camera must not be zero";
    return "";
  }

  template <class V>
  void VisitFields(V&& v) {
    v("up_in_camera", up_in_camera);
    v("floor_max_angle_deg", floor_max_angle_deg, Check::kPositive);
    v("floor_min_inliers", floor_min_inliers, Check::kPositive);
    v("floor_min_distance", floor_min_distance, Check::kNonNegative);
    v("structure_min_extent", structure_min_extent, Check::kPositive);
    v("corner_max_distance", corner_max_distance, Check::kPositive);
    v("corner_snap_distance", corner_snap_distance, Check::kNonNegative);
    v("corner_min_determinant", corner_min_determinant, Check::kProbability);
    v("resting_max_tilt_deg", resting_max_tilt_deg, Check::kPositive);
    v("corner_past_cut_distance", corner_past_cut_distance, Check::kNonNegative);
    v("face_piece_max_angle_deg", face_piece_max_angle_deg, Check::kNonNegative);
    v("face_piece_max_rms", face_piece_max_rms, Check::kNonNegative);
    v("face_piece_max_overlap", face_piece_max_overlap, Check::kNonNegative);
    v("face_piece_max_gap", face_piece_max_gap, Check::kNonNegative);
    v("two_face_min_angle_deg", two_face_min_angle_deg, Check::kNonNegative);
    v("two_face_min_height", two_face_min_height, Check::kNonNegative);
    v("two_face_below_share", two_face_below_share, Check::kProbability);
    v("two_face_below_distance", two_face_below_distance, Check::kNonNegative);
    v("two_face_support_gap", two_face_support_gap, Check::kNonNegative);
  }
};

// The configured up direction in the camera frame (unit), used until the floor is found.
Eigen::Vector3d UpPrior(const PlaneGraphConfig& config);

// Fills model->floor and model->structure from its planes (their inliers index into `cloud`).
void FindStructure(const Cloud& cloud, const PlaneGraphConfig& config, FrameModel* model);

// Fills model->face_of and model->face_plane: planes that are pieces of one face (see
// PlaneGraphConfig::face_piece_*), each face's plane fitted to all its pieces' inliers. Needs the
// planes, edges and structure.
void FindFaces(const Cloud& cloud, const PlaneGraphConfig& config, FrameModel* model);

// Fills model->angles and model->objects from its planes, edges, floor and structure: the
// trihedral angles, aggregated into objects angle by angle; then the objects of two faces on a
// support (PlaneGraphConfig::two_face_*). The trihedral angles need no points, so a map's graph
// (landmarks and merged edges) is aggregated the same way (Fig. 4); whether a face stands on a
// support is read from its inliers in `cloud` (a map's: its landmarks' points).
void AggregateObjects(const Cloud& cloud, const PlaneGraphConfig& config, FrameModel* model);

// FindStructure, FindFaces, then AggregateObjects.
void BuildPlaneGraph(const Cloud& cloud, const PlaneGraphConfig& config, FrameModel* model);

}  // namespace planemap
