#pragma once
// Step 2 of the frontend: planes of one organized cloud, behind one interface.
//   organized (default): cell-wise plane fits on the image grid merged by region growing, pixels
//                        assigned to the grown planes, then a least-squares refit on the inliers;
//   msac: the paper's reference, PCL's M-estimator sample consensus extracting planes one after
//         another, each split into its connected parts on the image grid.
#include <memory>
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/detected_plane.h"
#include "planemap/frontend/organized_cloud.h"

namespace planemap {

struct OrganizedSegmenterConfig {
  int cell_size = 16;                          // side of the grid cells fitted first [px]
  double min_cell_valid_fraction = 0.8;        // cells with fewer valid pixels are skipped
  double cell_jump_relative = 0.04;            // a cell with neighbouring depths differing more than
                                               // this fraction of the depth is not planar
  double cell_max_rms_base = 0.002;            // a cell is planar if its fit RMS is below
  double cell_max_rms_quadratic = 0.004;       //   base + quadratic * z^2 [m, 1/m]
  double grow_max_angle_deg = 10.0;            // a cell joins a region if its normal is this close:
  double grow_max_angle_deg_per_m = 5.0;       //   deg + per_m * z, as cell normals get noisier [deg, deg/m]
  double grow_max_distance_base = 0.01;        // ... and its centroid this close to the region's
  double grow_max_distance_quadratic = 0.006;  //     plane: base + quadratic * z^2 [m, 1/m]
  int min_region_cells = 3;                    // smaller regions are dropped [cells]
  double merge_max_angle_deg = 5.0;            // adjacent regions this close in normal ... [deg]
  double inlier_distance_base = 0.005;         // a pixel is an inlier if |n.p + d| is below
  double inlier_distance_quadratic = 0.005;    //   base + quadratic * z^2 [m, 1/m]
  // A region grown far away, where the gates are wide, can take in a surface behind it (a
  // locker's side 3.6 m away and the wall 1.2 m behind it at the image's corner: 26% of the
  // side's inliers were the wall's, its normal came out 17 deg off). A refit with more than
  // robust_check_share of its inliers farther than half the inlier distance (clean planes: 0-2%)
  // is done again by sample consensus (robust_hypotheses planes through 3 of its inliers, seeded
  // by robust_seed): the plane most of them lie on, refitted on the inliers within the inlier
  // distance of it; the others are dropped.
  // Only planes this far or farther: nearer, the gates are tight and half the inlier distance
  // (under 5 mm) is what a real face's bulge can reach (an OSD carton's side 0.6 m away, refitted
  // by consensus, came out 7 deg turned in an earlier version). From 1 m on it also keeps a board's
  // side seen at a glancing angle apart from the board's 2 cm front edge beside it (the office's
  // shelf 1.0-1.8 m away: from 2.5 m on only, up to a quarter of the side's inliers were the edge's).
  double robust_min_depth = 1.0;               // [m]
  double robust_check_share = 0.05;            // [fraction]
  int robust_hypotheses = 20;
  int robust_seed = 1;
  // Pixels no plane took, where no cell fits (a side seen as a strip 10-18 px wide running
  // diagonally): connected parts of min_inliers or more are searched for planes by sample
  // consensus with this many hypotheses (seeded by robust_seed); 0: off.
  int leftover_hypotheses = 50;
  // Then again on the pixels still free, with parts and the planes found in them connected
  // across up to this many pixels without depth (a narrow side's pixels split by bands of
  // dropouts: learn13's front box's left side, in parts of 346 and 310 pixels 4 px apart, each
  // under min_inliers); these strips take no pixels back (below) [px]; 0: no second search.
  int leftover_bridge_px = 6;
  // A strip takes back the pixels beside it that lie on it (within half the inlier distance)
  // rather than on the plane that took them (off it by half the inlier distance or more), from
  // planes nearer than robust_min_depth and at least strip_take_back_min_angle_deg from parallel
  // to it; in up to strip_take_back_rounds rounds, each refitting the planes that lost pixels.
  // 0 rounds: off.
  int strip_take_back_rounds = 3;
  double strip_take_back_min_angle_deg = 20.0;  // [deg]

  template <class V>
  void VisitFields(V&& v) {
    v("cell_size", cell_size, Check::kPositive);
    v("min_cell_valid_fraction", min_cell_valid_fraction, Check::kProbability);
    v("cell_jump_relative", cell_jump_relative, Check::kPositive);
    v("cell_max_rms_base", cell_max_rms_base, Check::kPositive);
    v("cell_max_rms_quadratic", cell_max_rms_quadratic, Check::kNonNegative);
    v("grow_max_angle_deg", grow_max_angle_deg, Check::kPositive);
    v("grow_max_angle_deg_per_m", grow_max_angle_deg_per_m, Check::kNonNegative);
    v("grow_max_distance_base", grow_max_distance_base, Check::kPositive);
    v("grow_max_distance_quadratic", grow_max_distance_quadratic, Check::kNonNegative);
    v("min_region_cells", min_region_cells, Check::kPositive);
    v("merge_max_angle_deg", merge_max_angle_deg, Check::kNonNegative);
    v("inlier_distance_base", inlier_distance_base, Check::kPositive);
    v("inlier_distance_quadratic", inlier_distance_quadratic, Check::kNonNegative);
    v("robust_min_depth", robust_min_depth, Check::kNonNegative);
    v("robust_check_share", robust_check_share, Check::kProbability);
    v("robust_hypotheses", robust_hypotheses, Check::kPositive);
    v("robust_seed", robust_seed, Check::kNonNegative);
    v("leftover_hypotheses", leftover_hypotheses, Check::kNonNegative);
    v("leftover_bridge_px", leftover_bridge_px, Check::kNonNegative);
    v("strip_take_back_rounds", strip_take_back_rounds, Check::kNonNegative);
    v("strip_take_back_min_angle_deg", strip_take_back_min_angle_deg, Check::kNonNegative);
  }
};

struct MsacSegmenterConfig {
  double distance_threshold = 0.02;  // inlier distance of the sample consensus [m]
  int max_iterations = 200;          // hypotheses per extracted plane
  int max_planes = 20;               // extraction stops after this many
  double probability = 0.99;         // confidence that a good sample is drawn

  template <class V>
  void VisitFields(V&& v) {
    v("distance_threshold", distance_threshold, Check::kPositive);
    v("max_iterations", max_iterations, Check::kPositive);
    v("max_planes", max_planes, Check::kPositive);
    v("probability", probability, Check::kProbability);
  }
};

struct SegmenterConfig {
  std::string method = "organized";  // organized | msac
  int min_inliers = 400;             // planes with fewer inlier pixels are dropped [px]
  // Planes of one equation whose pixels lie close in the image are one surface cut in two by an
  // occluder in front of it (a box before a locker's side): they are merged.
  double coplanar_max_angle_deg = 5.0;  // normals this close ... [deg]
  double coplanar_max_distance = 0.03;  // ... each centroid this close to the other plane [m]
  int coplanar_max_gap = 40;            // ... and their pixel boxes this close [px].
  // Not merged when the camera sees past the surface between them (two box tops of one height):
  double coplanar_see_through_margin = 0.02;  // pixels between them this far beyond it (at
                                              // 1 m, growing as depth squared) ... [m]
  double coplanar_max_see_through = 0.1;      // ... are more than this share of them [fraction]
  // Farther apart, they are merged only when the camera sees an occluder across the gap: this
  // share of the pixels between them or more lie nearer than the surface by the margin above
  // (a box in front of the middle of another box's top, which it cuts into pieces more than
  // coplanar_max_gap apart). Two surfaces of one equation behind one occluder are then taken for
  // one: the simpler reading, which the image cannot tell from the other.
  double coplanar_min_occluded = 0.9;         // [fraction]
  int coplanar_max_occluded_gap = 120;        // [px]; 0: off (docs/frontend.md, coplanar pieces)
  // Nor when the plane through both fits them worse than this many times their own planes' RMS,
  // taken as at least the sensor's depth resolution (the floor at 1 m, growing as depth squared;
  // a Kinect's noise and disparity step together are about 1.7 mm at 1 m): parallel faces a step apart.
  double coplanar_max_rms_ratio = 2.0;        // [ratio]
  double coplanar_rms_floor = 0.002;          // [m at 1 m]
  double max_view_angle_deg = 85.0;  // planes seen more edge-on at their centroid are dropped:
                                     // a plane through the camera holds whole pixel strips of
                                     // unrelated points [deg]
  OrganizedSegmenterConfig organized;
  MsacSegmenterConfig msac;

  template <class V>
  void VisitFields(V&& v) {
    v("method", method, OneOf{{"organized", "msac"}});
    v("min_inliers", min_inliers, Check::kPositive);
    v("coplanar_max_angle_deg", coplanar_max_angle_deg, Check::kNonNegative);
    v("coplanar_max_distance", coplanar_max_distance, Check::kNonNegative);
    v("coplanar_max_gap", coplanar_max_gap, Check::kNonNegative);
    v("coplanar_see_through_margin", coplanar_see_through_margin, Check::kPositive);
    v("coplanar_max_see_through", coplanar_max_see_through, Check::kProbability);
    v("coplanar_min_occluded", coplanar_min_occluded, Check::kProbability);
    v("coplanar_max_occluded_gap", coplanar_max_occluded_gap, Check::kNonNegative);
    v("coplanar_max_rms_ratio", coplanar_max_rms_ratio, Check::kPositive);
    v("coplanar_rms_floor", coplanar_rms_floor, Check::kPositive);
    v("max_view_angle_deg", max_view_angle_deg, Check::kPositive);
    v("organized", organized);
    v("msac", msac);
  }
};

struct SegmentationResult {
  std::vector<DetectedPlane> planes;  // by decreasing inlier count; planes[i].id == i
  int valid_points = 0;
  std::string reason;                 // why no plane was found; empty otherwise
};

class PlaneSegmenter {
 public:
  virtual ~PlaneSegmenter() = default;
  virtual SegmentationResult Segment(const Cloud& cloud) const = 0;
};

// Throws std::invalid_argument for an unknown method or out-of-range settings.
std::unique_ptr<PlaneSegmenter> MakePlaneSegmenter(const SegmenterConfig& config);

// Merges planes one occluder cut in two (coplanar_*), drops planes seen edge-on
// (max_view_angle_deg), orders the rest by decreasing inlier count, numbers them, and sets the
// reason when there is none.
SegmentationResult FinishSegmentation(const Cloud& cloud, std::vector<DetectedPlane> planes, int valid_points,
                                      const SegmenterConfig& config);

// A detected plane from a fit and the pixels it was fitted to (or that belong to it), and the
// box of those pixels' points (empty: not computed).
DetectedPlane MakeDetectedPlane(const PlaneFit& fit, std::vector<int> inliers, const Box3& bounds = Box3{});

// The box of the plane's inlier points: its bounds when computed, else from the cloud.
Box3 InlierBounds(const Cloud& cloud, const DetectedPlane& plane);

// The moments of the given pixels' points, each weighted by the inverse of its depth noise
// variance (DepthNoiseWeight); their box into *bounds when given.
PointMoments InlierMoments(const Cloud& cloud, const std::vector<int>& inliers, Box3* bounds = nullptr);

// Refits a plane by least squares on the given pixels of the cloud, each weighted by the inverse
// of its depth noise variance (DepthNoiseWeight).
DetectedPlane FitDetectedPlane(const Cloud& cloud, std::vector<int> inliers);

}  // namespace planemap
