#pragma once
// Parameters of the back end (DESIGN.md, "The back end model"); configs/default.yaml mirrors the
// defaults under `backend:`.
#include <string>
#include <vector>

#include "planemap/core/config.h"

namespace planemap {

// The robust loss on every observation factor (plane, box face, edge length, object centre).
// Its scale is in whitened units (standard deviations): residuals beyond it count less.
struct RobustLossConfig {
  std::string type = "huber";  // huber, cauchy, soft_l1 or none
  double scale = 2.0;          // [sigma]

  template <class V>
  void VisitFields(V&& v) {
    v("type", type, OneOf{{"huber", "cauchy", "soft_l1", "none"}});
    v("scale", scale, Check::kPositive);
  }
};

struct BackendConfig {
  RobustLossConfig loss;
  // A plane fit from thousands of points claims a precision its depth steps and bends do not
  // hold: each plane observation's standard deviations are floored at these.
  double plane_min_std_deg = 0.005;       // normal [deg]
  double plane_min_std = 0.00005;         // offset [m]
  // Tracking's motion between consecutive frames, as a relative-pose factor: weak, it only holds
  // what the planes leave free (a degraded or lost frame's unobserved directions).
  double odometry_sigma = 0.02;          // per frame, translation [m]
  double odometry_sigma_deg = 1.0;       // per frame, rotation [deg]
  // Into a weak frame (tracking marked it degraded, or the planes it observed span fewer than 3
  // directions: the smallest singular value of their normals below min_normal_spread), tracking's
  // motion is the measurement of the rest: tighter.
  double min_normal_spread = 0.1;
  double degraded_odometry_sigma = 0.002;   // [m]
  double degraded_odometry_sigma_deg = 0.1; // [deg]
  double gauge_sigma = 1e-4;             // prior on the first pose (the gauge) [m]
  double gauge_sigma_deg = 0.01;         // [deg]
  // Objects of these classes become cuboids (pose + 3 positive dimensions): their faces'
  // observations act on the box (BoxFaceFactor) instead of free landmarks.
  std::vector<std::string> cuboid_labels = {"box"};
  double face_max_angle_deg = 20.0;      // a face's normal within this of a box axis [deg]
  // One view's edge length: complete edges' lengths scatter by about 1 mm from view to view on
  // the rendered walks (full sensor noise, 1-2 m), with ends moved along their rays onto their
  // planes (intersections.band_on_plane) [m].
  double edge_sigma = 0.0015;
  // An error all views' edges along one box axis share (EdgeLengthWithBiasFactor): the sensor
  // drops pixels at a silhouette the same way in every view, leaving edges about 0.5 mm short
  // (under a pixel). 0: none.
  double edge_bias_sigma = 0.0005;       // [m]
  double center_sigma = 0.02;            // one view's object centre, eq. (7) [m]
  double min_dimension = 0.01;           // dimensions stay above this [m]
  // A cuboid whose bottom lies within contact_distance of the floor stands on it (BoxContactFactor).
  bool floor_contact = true;
  double contact_distance = 0.03;        // [m]
  double contact_sigma = 0.001;          // cardboard flaps, an uneven floor [m]
  double contact_sigma_deg = 0.5;        // [deg]
  // Perpendicular priors between landmarks the map's edges join at near right angles (0: off).
  double structure_sigma_deg = 0.0;      // [deg]
  double structure_max_deviation_deg = 3.0;  // only edges this close to 90 deg [deg]
  // An observation that, placed at the solution, is more than outlier_max_angle_deg off its
  // landmark or whose centroid is more than outlier_max_distance from it (a wrong association, or
  // a surface one plane cannot hold) is dropped and the problem solved again, outlier_rounds times.
  // The gates widen to outlier_spread_factor robust standard deviations (1.4826 x the median) of
  // all the observations' residuals when those are larger: real plane observations are about
  // 1 deg off their landmarks at the median (TUM fr1/rpy), and fixed gates dropped 57% of them.
  int outlier_rounds = 2;
  double outlier_max_angle_deg = 1.0;  // [deg]
  double outlier_max_distance = 0.01;  // [m]
  double outlier_max_sigma = 3.0;      // ... and by more than this many of its own standard deviations
  double outlier_spread_factor = 3.0;  // ... and of the residuals' robust standard deviation [ratio]
  // One floor: a landmark within these of the map's floor that frames took for the floor is
  // observed as the floor (0 distance: off).
  double floor_merge_distance = 0.10;   // [m]
  double floor_merge_angle_deg = 3.0;   // [deg]
  // Solver: sparse_schur or sparse_normal_cholesky (SuiteSparse underneath).
  std::string linear_solver = "sparse_normal_cholesky";
  int max_iterations = 100;
  double function_tolerance = 1e-8;
  int threads = 1;
  bool covariance = true;                // marginal covariances of each cuboid (batch)
  // Batch: each frame's tracking pose as a weak measurement (0: none), which keeps stretches that
  // planes fix only in part from drifting along what they leave free.
  double batch_tracking_sigma = 0.01;      // [m]
  double batch_tracking_sigma_deg = 0.5;   // [deg]
  // Sliding window: the last window_size frames, the oldest held fixed; landmarks as the map has them.
  int window_size = 10;
  int window_max_iterations = 10;
  // Each window frame's tracking pose is a measurement too, with these sigmas: the planes refine
  // it, they cannot drag it where a landmark bent by a wrong association would.
  double window_tracking_sigma = 0.002;      // [m]
  double window_tracking_sigma_deg = 0.3;    // [deg]

  template <class V>
  void VisitFields(V&& v) {
    v("loss", loss);
    v("plane_min_std_deg", plane_min_std_deg, Check::kPositive);
    v("plane_min_std", plane_min_std, Check::kPositive);
    v("odometry_sigma", odometry_sigma, Check::kPositive);
    v("odometry_sigma_deg", odometry_sigma_deg, Check::kPositive);
    v("min_normal_spread", min_normal_spread, Check::kPositive);
    v("degraded_odometry_sigma", degraded_odometry_sigma, Check::kPositive);
    v("degraded_odometry_sigma_deg", degraded_odometry_sigma_deg, Check::kPositive);
    v("gauge_sigma", gauge_sigma, Check::kPositive);
    v("gauge_sigma_deg", gauge_sigma_deg, Check::kPositive);
    v("cuboid_labels", cuboid_labels);
    v("face_max_angle_deg", face_max_angle_deg, Check::kPositive);
    v("edge_sigma", edge_sigma, Check::kPositive);
    v("edge_bias_sigma", edge_bias_sigma, Check::kNonNegative);
    v("center_sigma", center_sigma, Check::kPositive);
    v("min_dimension", min_dimension, Check::kPositive);
    v("floor_contact", floor_contact);
    v("contact_distance", contact_distance, Check::kPositive);
    v("contact_sigma", contact_sigma, Check::kPositive);
    v("contact_sigma_deg", contact_sigma_deg, Check::kPositive);
    v("structure_sigma_deg", structure_sigma_deg, Check::kNonNegative);
    v("structure_max_deviation_deg", structure_max_deviation_deg, Check::kPositive);
    v("outlier_rounds", outlier_rounds, Check::kNonNegative);
    v("outlier_max_angle_deg", outlier_max_angle_deg, Check::kPositive);
    v("outlier_spread_factor", outlier_spread_factor, Check::kNonNegative);
    v("outlier_max_distance", outlier_max_distance, Check::kPositive);
    v("outlier_max_sigma", outlier_max_sigma, Check::kPositive);
    v("floor_merge_distance", floor_merge_distance, Check::kNonNegative);
    v("floor_merge_angle_deg", floor_merge_angle_deg, Check::kPositive);
    v("linear_solver", linear_solver, OneOf{{"sparse_schur", "sparse_normal_cholesky"}});
    v("max_iterations", max_iterations, Check::kPositive);
    v("function_tolerance", function_tolerance, Check::kPositive);
    v("threads", threads, Check::kPositive);
    v("covariance", covariance);
    v("batch_tracking_sigma", batch_tracking_sigma, Check::kNonNegative);
    v("batch_tracking_sigma_deg", batch_tracking_sigma_deg, Check::kNonNegative);
    v("window_size", window_size, Check::kPositive);
    v("window_max_iterations", window_max_iterations, Check::kPositive);
    v("window_tracking_sigma", window_tracking_sigma, Check::kNonNegative);
    v("window_tracking_sigma_deg", window_tracking_sigma_deg, Check::kNonNegative);
  }
};

}  // namespace planemap
