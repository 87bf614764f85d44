#include "planemap/nav/odometry_calibration.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>

namespace planemap::nav {

OdometryCalibration::OdometryCalibration(const OdometryCalibrationConfig& config) : config_(config) {
  ValidateConfig(config_, "odometry_calibration.");
  information_ = Eigen::Vector2d(1.0 / (config_.scale_prior_std * config_.scale_prior_std),
                                 1.0 / (config_.lateral_prior_std * config_.lateral_prior_std))
                     .asDiagonal();
}

Pose2 OdometryCalibration::Correct(const Pose2& odometry) {
  if (!config_.enabled) return odometry;
  if (!last_odometry_) {
    last_odometry_ = corrected_ = odometry;
    increment_ = Pose2{};
    return odometry;
  }
  increment_ = Between(*last_odometry_, odometry);
  last_odometry_ = odometry;
  const double walked = std::hypot(increment_.x, increment_.y);
  const Pose2 corrected{increment_.x * (1.0 + Scale()), increment_.y + Lateral() * walked, increment_.theta};
  corrected_ = Compose(*corrected_, corrected);
  return *corrected_;
}

void OdometryCalibration::Observe(const std::optional<Pose2>& measured) {
  if (!config_.enabled || !last_odometry_) return;
  if (!measured) {
    Close();
  } else if (!last_measured_) {
    open_ = Stretch{};  // a stretch starts at this pose
  } else {
    // The odometry's increment since the last frame, into the world by the measured heading there.
    const double walked = std::hypot(increment_.x, increment_.y);
    const Eigen::Rotation2Dd R(last_measured_->theta);
    Eigen::Matrix2d A;
    A.col(0) = R * Eigen::Vector2d(increment_.x, 0.0);
    A.col(1) = R * Eigen::Vector2d(0.0, walked);
    const Eigen::Vector2d r =
        (measured->Position() - last_measured_->Position()) - R * Eigen::Vector2d(increment_.x, increment_.y);
    if ((r - A * parameters_).norm() > config_.max_frame_residual) {
      Close();
      open_ = Stretch{};
    } else {
      open_->A += A;
      open_->r += r;
      open_->walked += walked;
    }
  }
  last_measured_ = measured;
  Solve();
}

bool OdometryCalibration::OpenCounts() const { return open_ && open_->walked >= config_.min_stretch; }

Eigen::Matrix2d OdometryCalibration::Information() const {
  return OpenCounts() ? Eigen::Matrix2d(information_ + StretchInformation(*open_)) : information_;
}

Eigen::Matrix2d OdometryCalibration::Covariance() const { return Information().inverse(); }

double OdometryCalibration::CalibratedDistance() const {
  return used_distance_ + (OpenCounts() ? open_->walked : 0.0);
}

// The stretch's displacement error: its two end poses', and the gait's random walk along it.
double OdometryCalibration::StretchVariance(const Stretch& s) const {
  return 2.0 * config_.end_pose_std * config_.end_pose_std +
         config_.walk_noise * config_.walk_noise * s.walked;
}

Eigen::Matrix2d OdometryCalibration::StretchInformation(const Stretch& s) const {
  return s.A.transpose() * s.A / StretchVariance(s);
}

Eigen::Vector2d OdometryCalibration::StretchGradient(const Stretch& s) const {
  return s.A.transpose() * s.r / StretchVariance(s);
}

void OdometryCalibration::Close() {
  if (OpenCounts()) {
    information_ += StretchInformation(*open_);
    gradient_ += StretchGradient(*open_);
    used_distance_ += open_->walked;
  }
  open_.reset();
}

void OdometryCalibration::Solve() {
  const Eigen::Vector2d g = OpenCounts() ? Eigen::Vector2d(gradient_ + StretchGradient(*open_)) : gradient_;
  parameters_ = Information().ldlt().solve(g);
}

}  // namespace planemap::nav
