#pragma once
// Online calibration of a walking robot's odometry from its own visual pose estimates.
//
// A humanoid's gait errs the same way all through a run: its steps come out a few per cent long or
// short, and it drifts to one side by so much per metre walked (SimulatedHumanoid's per-run bias;
// a real Nao does the same on a given floor). Where the planes in view fix every direction, the
// tracker measures the walk; where they do not (the last steps toward a box whose faces are below
// the image, say), it follows the odometry, and the gait's bias becomes the estimate's error.
//
// The model, per odometry increment (dx, dy, dtheta) in the base frame:
//   true = (dx (1 + scale), dy + lateral * |(dx, dy)|, dtheta),
// linear in (scale [-], lateral [m/m]). Each stretch of consecutive frames whose poses were measured
// (tracked: the planes fixed every direction) gives two equations: the measured displacement minus
// the odometry's, each odometry increment turned into the world by the measured heading, against
// the increments' sum. Differences telescope, so a stretch's noise is that of its two end poses
// (end_pose_std, head sway mostly) plus the gait's random step errors along it (walk_noise); a
// Gaussian prior on both parameters keeps the solution at zero until the robot has walked.
// The heading is not calibrated: two non-parallel planes (the floor and one wall) already measure it.
#include <Eigen/Core>
#include <optional>

#include "planemap/core/config.h"
#include "planemap/nav/pose2.h"

namespace planemap::nav {

struct OdometryCalibrationConfig {
  bool enabled = true;             // false: Correct() returns the odometry unchanged
  double scale_prior_std = 0.10;   // prior on the forward scale error, std [-]
  double lateral_prior_std = 0.10; // prior on the sideways drift per metre walked, std [m/m]
  double end_pose_std = 0.01;      // error of a measured base pose at a stretch's end (head sway) [m]
  double walk_noise = 0.015;       // random gait error over a walk of d metres: walk_noise * sqrt(d) [m]
  double min_stretch = 0.05;       // measured stretches shorter than this are not used [m walked]
  // A frame whose measured motion differs from the corrected odometry's by more than this is not
  // one the walk explains (a tracking jump): it ends the stretch and is left out.
  double max_frame_residual = 0.02;  // [m]

  template <class V>
  void VisitFields(V&& v) {
    v("enabled", enabled);
    v("scale_prior_std", scale_prior_std, Check::kPositive);
    v("lateral_prior_std", lateral_prior_std, Check::kPositive);
    v("end_pose_std", end_pose_std, Check::kPositive);
    v("walk_noise", walk_noise, Check::kNonNegative);
    v("min_stretch", min_stretch, Check::kNonNegative);
    v("max_frame_residual", max_frame_residual, Check::kPositive);
  }
};

class OdometryCalibration {
 public:
  // Throws std::invalid_argument for an invalid config.
  explicit OdometryCalibration(const OdometryCalibrationConfig& config);

  // Every frame, in time order: the walking engine's odometry pose now. Returns the corrected
  // odometry pose, in a frame of its own that starts where the odometry started: the raw motion
  // since the last call, corrected by the calibration so far, added to the last corrected pose.
  Pose2 Correct(const Pose2& odometry);
  // After Correct(), for the same instant: the base pose the planes measured, or nullopt when they
  // did not fix it (degraded, lost or dropped frame).
  void Observe(const std::optional<Pose2>& measured);

  double Scale() const { return parameters_.x(); }    // forward scale error [-]
  double Lateral() const { return parameters_.y(); }  // sideways drift [m per m walked]
  Eigen::Matrix2d Covariance() const;                 // of (scale, lateral)
  double CalibratedDistance() const;  // walked in the stretches used so far, the open one too [m]

 private:
  struct Stretch {
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();  // d(measured displacement) / d(scale, lateral)
    Eigen::Vector2d r = Eigen::Vector2d::Zero();  // measured minus odometry displacement [m]
    double walked = 0.0;                          // [m]
  };
  void Close();    // ends the open stretch; used when long enough
  void Solve();    // parameters_ from the closed stretches and the open one
  bool OpenCounts() const;              // a stretch is open and long enough to use
  Eigen::Matrix2d Information() const;  // prior + closed stretches + the open one if it counts
  double StretchVariance(const Stretch& s) const;                // [m^2]
  Eigen::Matrix2d StretchInformation(const Stretch& s) const;    // A^T A / variance
  Eigen::Vector2d StretchGradient(const Stretch& s) const;       // A^T r / variance

  OdometryCalibrationConfig config_;
  Eigen::Vector2d parameters_ = Eigen::Vector2d::Zero();
  Eigen::Matrix2d information_;                            // prior + closed stretches
  Eigen::Vector2d gradient_ = Eigen::Vector2d::Zero();     // information-weighted residual sum
  std::optional<Pose2> last_odometry_, corrected_;
  Pose2 increment_;                       // the raw odometry motion of the last Correct() call
  std::optional<Pose2> last_measured_;    // the previous frame's measured pose, if any
  std::optional<Stretch> open_;
  double used_distance_ = 0.0;
};

}  // namespace planemap::nav
