#pragma once
// Step 3 of the frontend: real intersections of plane pairs (paper eqs. 2-6).
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/frame_model.h"
#include "planemap/core/intrinsics.h"
#include "planemap/frontend/organized_cloud.h"

namespace planemap {

struct IntersectionConfig {
  double d_thresh = 0.03;          // an edge point lies within this of both planes [m]
  double d_min = 0.0;              // ... and farther than this from both (the paper's noise guard) [m]
  int min_points = 40;             // fewer edge points: no real intersection
  double min_length = 0.02;        // shorter edges are noise where two planes touch [m]
  double min_angle_deg = 30.0;     // planes closer to parallel do not intersect [deg]
  int border_margin = 4;           // an edge end this close to the image border is cut [px]
  int cut_search = 6;              // an end with no depth within this many pixels beyond it is cut [px]
  // A face seen at more than this ray-to-normal angle may go on past an end without depth (a
  // structured-light sensor reads nothing there); at less, a pixel without depth past the end is
  // the sensor's dropout at the depth edge, not the face [deg].
  double grazing_angle_deg = 70.0;
  double occluder_min_gap = 0.02; // a surface this much nearer than the edge's continuation hides it [m]
  double end_max_distance = 0.15;  // a nearer surface beyond an end ends the edge only if its
                                   // point there lies this close to the end [m]
  double support_tolerance = 0.02;  // a support ends a face's edge unless more than
  double support_max_share = 0.05;  // this share of the face's points lie this far beneath it
                                    // [m], [fraction]
  double face_run_length = 0.02;    // a face going on this far along the line past an end
                                    // (the other face hidden) cuts it [m]
  double unseen_run_length = 0.005;  // a surface on the line that no plane took, or a face
                                     // running into missing depth, going on this far past an
                                     // end cuts it [m]
  // An end that a plane through it ends (a support under a vertical edge, a third face) moves to
  // where the line meets that plane, if that is at most end_on_ending_plane_max away along the
  // line and the plane is at least min_angle_deg from parallel to it. [on/off], [m]
  bool end_on_ending_plane = true;
  double end_on_ending_plane_max = 0.02;
  int free_space_min_run = 3;      // an edge end this many pixels or more in front of what the
                                   // camera sees there moves in to where it is not [px]
  // A face's last pixels beside cells not its own (mixed with the table under a box, or with the
  // background past its silhouette) may have gone to no plane: the organized segmenter offers a
  // pixel only the planes of the cells around it. For the edges, such pixels count as a plane's
  // (its fringe) when they lie within fringe_distance_base + fringe_distance_quadratic z^2 of it
  // and connect to its inliers through 4-neighbours like them, up to fringe_px pixels out (each
  // to the nearest such plane). The planes themselves are left as they are. [px] (0: off), [m], [1/m]
  int fringe_px = 8;
  double fringe_distance_base = 0.005;
  double fringe_distance_quadratic = 0.005;
  double band_width = 0.09;        // each plane's extent along the edge is measured on its inliers
                                   // from d_thresh to this far from the other plane [m]
  double end_trim_fraction = 0.0;  // share of each plane's band points ignored at either end
  // Each band point is moved along its pixel's ray onto its own fitted plane before the extents
  // are taken. A depth sensor's error lies along the ray, so a point beside a face's end is shifted
  // along the edge by its depth error times the ray's cosine with the edge; the farthest of many
  // such points lies beyond the end (about 1-3 mm at 1-1.5 m), a bias every view shares. On the
  // plane, the point is where the pixel's exact ray meets the surface. [on/off]
  bool band_on_plane = true;
  // ... only a point whose distance to its plane is within this many robust standard deviations
  // (median absolute distance) of the band's, and which no other plane lies nearer: beyond that it
  // may be a neighbouring face's pixel the segmenter took in beside a corner, which its ray would
  // carry past the corner; such a point stays where it is. [standard deviations]
  double band_on_plane_max_sigma = 3.0;
  double max_gap = 0.05;           // points further apart along the line split the edge:
                                   // the longest run counts [m]
  // Hidden edges. Two faces of a solid whose common edge is behind an occluder (a box in front
  // of another box's vertical corner) have no real intersection: their points never meet. The
  // edge is inferred when a third plane meets both faces in real edges whose ends toward the
  // three planes' corner are cut, and the camera sees something nearer than the lines all the
  // way from those ends to the corner (or no depth there, for at most half of the pixels); the
  // two faces lie each behind the other's plane, as a solid's do (no more than
  // support_max_share of either's points support_tolerance in front of the other). The edge
  // runs between two such corners (a box's top and the floor), or from one as far as both faces
  // reach, its far end cut. A seen edge of either face that ends short of the hidden edge is cut
  // there. [on/off]
  bool hidden_edges = true;  // docs/frontend.md, "Hidden edges"
  double hidden_max_reach = 0.2;         // the corner lies at most this far past both ends [m]
  double hidden_min_determinant = 0.5;   // |det(n_a, n_b, n_c)| of the three planes, at least
  double hidden_min_depth_share = 0.5;   // share of the pixels along the way with depth, at least

  template <class V>
  void VisitFields(V&& v) {
    v("d_thresh", d_thresh, Check::kPositive);
    v("d_min", d_min, Check::kNonNegative);
    v("min_points", min_points, Check::kPositive);
    v("min_length", min_length, Check::kNonNegative);
    v("min_angle_deg", min_angle_deg, Check::kPositive);
    v("border_margin", border_margin, Check::kNonNegative);
    v("cut_search", cut_search, Check::kPositive);
    v("grazing_angle_deg", grazing_angle_deg, Check::kNonNegative);
    v("occluder_min_gap", occluder_min_gap, Check::kPositive);
    v("end_max_distance", end_max_distance, Check::kPositive);
    v("support_tolerance", support_tolerance, Check::kPositive);
    v("support_max_share", support_max_share, Check::kProbability);
    v("face_run_length", face_run_length, Check::kPositive);
    v("unseen_run_length", unseen_run_length, Check::kPositive);
    v("free_space_min_run", free_space_min_run, Check::kPositive);
    v("fringe_px", fringe_px, Check::kNonNegative);
    v("fringe_distance_base", fringe_distance_base, Check::kNonNegative);
    v("fringe_distance_quadratic", fringe_distance_quadratic, Check::kNonNegative);
    v("band_width", band_width, Check::kPositive);
    v("end_trim_fraction", end_trim_fraction, Check::kProbability);
    v("band_on_plane", band_on_plane);
    v("band_on_plane_max_sigma", band_on_plane_max_sigma, Check::kPositive);
    v("max_gap", max_gap, Check::kPositive);
    v("end_on_ending_plane", end_on_ending_plane);
    v("end_on_ending_plane_max", end_on_ending_plane_max, Check::kNonNegative);
    v("hidden_edges", hidden_edges);
    v("hidden_max_reach", hidden_max_reach, Check::kPositive);
    v("hidden_min_determinant", hidden_min_determinant, Check::kProbability);
    v("hidden_min_depth_share", hidden_min_depth_share, Check::kProbability);
  }
};

// Which nearer planes end an edge that runs into them (rather than hide its continuation): the
// room structure (floor, walls), and a horizontal surface a vertical edge goes down into (the top
// a box stands on). Without it, any plane through the edge's end ends it, which mistakes a box
// standing on another one for the end of the lower box's top edges.
struct EdgeTerminators {
  std::vector<bool> structure;                            // per plane id
  Eigen::Vector3d up = Eigen::Vector3d(0.0, -1.0, 0.0);   // unit, camera frame
  double max_tilt_deg = 30.0;  // a support is within this of horizontal, the edge of vertical
};

// Where the ray from the camera centre through camera-frame point `p` meets `plane`: a depth
// reading moved to its plane without changing its pixel. `p` itself if the ray misses the plane
// or meets it behind the camera.
Eigen::Vector3d AlongRayOntoPlane(const Plane& plane, const Eigen::Vector3d& p);

// Every real intersection among `planes` (ids as indices), in the camera frame; then, with
// hidden_edges, the hidden ones (PlaneEdge::hidden), after the seen ones.
std::vector<PlaneEdge> FindIntersections(const std::vector<DetectedPlane>& planes, const Cloud& cloud,
                                         const CameraIntrinsics& camera, const IntersectionConfig& config,
                                         const EdgeTerminators* terminators = nullptr);

}  // namespace planemap
