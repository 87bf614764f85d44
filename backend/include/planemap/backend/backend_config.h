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
  // Batch: the plane observations' noise, estimated from the data (variance component
  // estimation; the model and the estimate: backend/src/noise_estimation.h). A plane fit's
  // covariance takes its thousands of pixels as independent, but a structured-light sensor's
  // depth errs in blocks and its distortion bends whole surfaces. On real frames at the true
  // poses an observation is off its surface by 0.50 deg and 2.8 mm at the median on TUM
  // fr3/structure_notexture_far (its fit claims 0.018 deg and 0.05 mm), 1.5 deg and 4.3 mm on
  // fr1/rpy, 0.19 deg and 0.35 mm on ICL-NUIM kt0, and surfaces differ: 0.2-0.3 deg for fr3's
  // floor and near panels, 2-6 deg for its far wall strips. Weighed by the fits' covariances
  // (floored at plane_min_std_deg / plane_min_std, which stay as lower bounds), the batch
  // followed the planes' errors: fr3 went from tracking's 0.56 to 0.98 cm ATE. So each fit's
  // covariance is taken as if from N_eff independent pixels (times N / N_eff: a far strip keeps
  // its larger spread, a plane its tilt-to-shift ratio), and N_eff is estimated after each solve
  // from the residuals and the problem solved again, at most noise_rounds times, until it moves
  // by less than noise_tolerance. It comes out 5-14 on fr1/rpy, 23-41 on fr3 and 150-650 on ICL
  // kt0 (strides 1 to 20), about 4500 on a rendered walk (nearly independent pixels); at stride 1
  // the three real ones went to 2.71, 0.62 and 0.57 cm (tracking 3.57, 0.56, 0.73).
  // Tried and not kept: a floor per landmark estimated the same way (fr3 0.70 cm: a landmark that
  // fixes the poses keeps too little of its error in its residuals to measure), and tracking's
  // motion noise estimated with the planes' floor: it was computed from the same planes, so its
  // residuals cannot tell its noise; it shrank to 0.01 mm on ICL kt0 in eight rounds and the
  // batch became tracking (0.73 cm there). So tracking's motion keeps odometry_sigma.
  int noise_rounds = 8;               // 0: N_eff stays at noise_initial_pixels
  // N_eff the batch starts from, and keeps where too few observations tell (frames far apart,
  // each surface seen once or twice): near the geometric mean of the real sensors' above, so
  // that a structured-light sensor's planes are not taken as independent pixels where nothing
  // says otherwise. 0: the pixels independent.
  double noise_initial_pixels = 50.0;  // [px]
  double noise_tolerance = 0.05;      // [ratio]
  // An observation whose residual keeps less than this share of its error (a landmark seen once,
  // or twice in frames it alone fixes: most of them where frames are far apart) tells too little
  // of the noise to count; with fewer than noise_min_samples left the noise stays as it is.
  double noise_min_redundancy = 0.2;  // [ratio]
  int noise_min_samples = 10;
  int noise_probes = 64;              // random vectors for the residuals' redundancy (Hutchinson)
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
    v("noise_rounds", noise_rounds, Check::kNonNegative);
    v("noise_initial_pixels", noise_initial_pixels, Check::kNonNegative);
    v("noise_tolerance", noise_tolerance, Check::kPositive);
    v("noise_min_redundancy", noise_min_redundancy, Check::kProbability);
    v("noise_min_samples", noise_min_samples, Check::kPositive);
    v("noise_probes", noise_probes, Check::kPositive);
    v("window_size", window_size, Check::kPositive);
    v("window_max_iterations", window_max_iterations, Check::kPositive);
    v("window_tracking_sigma", window_tracking_sigma, Check::kNonNegative);
    v("window_tracking_sigma_deg", window_tracking_sigma_deg, Check::kNonNegative);
  }
};

}  // namespace planemap
