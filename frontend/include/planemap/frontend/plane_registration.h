#pragma once
// Pose from plane correspondences (paper sec. 4.2 and "Merging ..."): a closed-form plane-to-plane
// solution [13, 20] inside RANSAC, refined by point-to-plane ICP on points rebuilt from the planes'
// inliers. Frames: source s (the current camera), target t (the map or an earlier frame); every
// pose returned is T_target_source, so p_t = T * p_s and plane_t = TransformPlane(T, plane_s).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "planemap/core/config.h"
#include "planemap/core/detected_plane.h"
#include "planemap/core/plane.h"
#include "planemap/core/pose.h"
#include "planemap/frontend/organized_cloud.h"

namespace planemap {

struct PlaneCorrespondence {
  Plane source;         // in frame s, unit normal
  Plane target;         // in frame t, unit normal
  double weight = 1.0;  // > 0, e.g. 1 / variance; scales the pair in both least-squares problems
  // A point of the source plane's observed patch (its centroid), frame s. When set, RANSAC
  // measures a pair's distance there (|target.SignedDistance(T p)|) instead of comparing offsets,
  // which for a plane far from frame t's origin magnify a small normal error by the lever arm.
  std::optional<Eigen::Vector3d> source_point;
  // Pairs of one group are alternatives (one frame plane, several candidate landmarks): RANSAC
  // counts at most one of them, the best fitting, as an inlier. -1: a group of its own.
  int group = -1;
};

// Weighted Kabsch: the rotation R (det +1) maximising sum w b . (R a) given the correlation
// H = sum w a b^T, from H's SVD.
Eigen::Matrix3d RotationFromCorrelation(const Eigen::Matrix3d& H);

// Closed-form plane-to-plane registration [13, 20]. Rotation: weighted Kabsch on the unit normals,
// maximising sum w n_t . (R n_s) by SVD with det(R) = +1. Translation: weighted linear least
// squares on the offsets, n_t . t = d_s - d_t (from d_t = d_s - n_t . t). Returns T_target_source,
// or nothing when fewer than 3 correspondences are given, a weight is not positive and finite,
// or the normals do not span 3-D: the smallest singular value of the matrix with the unit
// normals as rows (source and target alike; weights play no part) is below `min_normal_spread`.
// Three perpendicular planes give 1, and two perpendicular planes plus a third whose normal is
// tilted by a out of their normals' plane give sqrt(2) sin(a / 2): 0.1 at 8 deg, 0.2 at 16 deg.
// `reason` then says which: parallel planes, or coplanar normals (a corridor).
std::optional<Pose3> SolvePlaneToPlane(const std::vector<PlaneCorrespondence>& correspondences,
                                       double min_normal_spread = 0.1, std::string* reason = nullptr);

struct PlaneRansacConfig {
  int max_iterations = 200;       // minimal samples drawn (all triples when there are 3-4 pairs)
  double inlier_angle_deg = 3.0;  // an inlier's transformed source normal lies this close to the target's [deg]
  double inlier_distance = 0.03;  // ... and its transformed offset this close to the target's [m]
  double min_normal_spread = 0.2; // a sample whose 3 normals' matrix has a smaller singular value
                                  // is degenerate (see SolvePlaneToPlane: 16 deg from coplanar)
  int seed = 1;                   // of the sampler, std::mt19937_64; same seed, same result
  bool refit = true;              // refit the closed form on the winner's inliers (off: the winner's pose
                                  // as it is, e.g. when a point-based refinement follows)

  template <class V>
  void VisitFields(V&& v) {
    v("max_iterations", max_iterations, Check::kPositive);
    v("inlier_angle_deg", inlier_angle_deg, Check::kPositive);
    v("inlier_distance", inlier_distance, Check::kPositive);
    v("min_normal_spread", min_normal_spread, Check::kPositive);
    v("seed", seed, Check::kNonNegative);
    v("refit", refit);
  }
};

struct PlaneRansacResult {
  Pose3 T_target_source = Pose3::Identity();
  std::vector<int> inliers;  // indices into the correspondences, ascending
  bool ok = false;
  std::string reason;        // why not ok
};

// RANSAC over correspondences (paper sec. 3: "RANSAC ... initialized in each frame with a direct
// pose estimate [20]"): solve minimal samples of 3 non-degenerate pairs, keep the pose whose
// inliers weigh most (sum of weights; ties: lower residual, errors over thresholds squared), so
// three small noisy patches do not outvote the floor; refit on its inliers. `hypotheses` (e.g. a
// motion model's prediction) are scored before the samples and win ties. When `plausibility` is
// given, each pose's support is scaled by it (a prior: how likely the robot is there; 0 rules a
// pose out, e.g. a jump a walking robot cannot make between two frames).
// Throws std::invalid_argument for a bad config.
PlaneRansacResult EstimatePoseRansac(const std::vector<PlaneCorrespondence>& correspondences,
                                     const PlaneRansacConfig& config, const std::vector<Pose3>& hypotheses = {},
                                     const std::function<double(const Pose3&)>& plausibility = nullptr);

// Point-to-plane alignment with the correspondences given by plane association: each observed
// plane's inlier points (in frame s, as weighted moments, so the cost of thousands of points is
// evaluated in constant time) against the target plane it was associated with. Minimises
// sum_i w_i sum_p (n_i . (T p) + d_i)^2 by Gauss-Newton, which is point-to-plane ICP on the
// "points rebuilt from the inliers" (sec. 4.2) where every point's partner is its plane's
// landmark rather than a nearest neighbour; unlike a plane-to-plane fit it measures errors where
// the points are, so a far plane's small normal error is not magnified by its lever arm.
struct PointsOnPlane {
  PointMoments source;  // the observed plane's inlier points, frame s (weights ~ 1 / variance)
  Plane target;         // the plane they should lie on, frame t
  double weight = 1.0;  // scales the whole group
};

struct PointToPlaneResult {
  Pose3 T_target_source = Pose3::Identity();
  // Gauss-Newton information of the left perturbation (rotation vector, translation) of T,
  // prior excluded: its small eigenvalues are the directions the planes do not fix.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  double rms = 0.0;     // weighted RMS point-to-plane distance at the solution [m]
  int iterations = 0;
};

// Starts at `initial`; a weak prior pulls toward `prior` with information prior_weight * mean
// diagonal of the data information (per direction), which keeps directions no plane observes
// (one wall: the translation along it) at the prior and leaves observed ones to the data.
// robust_scale > 0 reweights each group by 1 / (1 + (e / robust_scale)^2), e its points' mean
// distance to its plane at the current pose (Cauchy, iteratively reweighted): a wrong pairing
// does not drag the pose. Stops after max_iterations or when a step is below 1e-9 (rad and m).
PointToPlaneResult AlignPointsToPlanes(const std::vector<PointsOnPlane>& groups, const Pose3& initial,
                                       const Pose3& prior, double prior_weight = 1e-6, int max_iterations = 10,
                                       double robust_scale = 0.0);

// Whether a refinement's correction (T_before^-1 T_after) moves less than max_translation [m]
// and turns less than max_rotation_deg [deg]: larger ones are refused as a jump.
bool IsSmallCorrection(const Pose3& correction, double max_translation, double max_rotation_deg);

struct IcpConfig {
  int max_iterations = 20;
  double max_correspondence_distance = 0.05;  // farther nearest neighbours are ignored [m]
  double transformation_epsilon = 1e-8;       // stop when the squared step is below this [m^2]
  double voxel_size = 0.02;                   // pcl::VoxelGrid leaf for both clouds, 0 = off [m]

  template <class V>
  void VisitFields(V&& v) {
    v("max_iterations", max_iterations, Check::kPositive);
    v("max_correspondence_distance", max_correspondence_distance, Check::kPositive);
    v("transformation_epsilon", transformation_epsilon, Check::kPositive);
    v("voxel_size", voxel_size, Check::kNonNegative);
  }
};

struct IcpResult {
  Pose3 T_target_source = Pose3::Identity();  // the initial pose when ICP did not run
  bool converged = false;  // a step or error criterion stopped it before max_iterations
  double fitness = 0.0;    // mean squared nearest-neighbour distance within range [m^2]
  int iterations = 0;
  std::string reason;      // why it did not converge
};

// Point-to-plane ICP (pcl::IterativeClosestPointWithNormals) from an initial pose, both clouds
// voxel-downsampled first; the paper refines the closed-form pose this way on points rebuilt from
// plane inliers (sec. 4.2). Target normals must be set. Throws std::invalid_argument for a bad config.
IcpResult RefineIcp(const pcl::PointCloud<pcl::PointNormal>& source,
                    const pcl::PointCloud<pcl::PointNormal>& target, const Pose3& initial_T_target_source,
                    const IcpConfig& config);

// The paper's "reconstructed point cloud on the basis of inliers of all extracted planes": every
// `stride`-th valid inlier of `plane`, projected onto the plane, with the plane's normal (frame of
// `cloud`). Throws std::invalid_argument for stride < 1.
pcl::PointCloud<pcl::PointNormal>::Ptr PlanePoints(const DetectedPlane& plane, const Cloud& cloud, int stride);

}  // namespace planemap
