#include "planemap/nav/simulated_humanoid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace planemap::nav {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// The camera on a head leaning by (lateral, vertical) [m] and (roll, yaw) [rad] over a base pose.
Pose3 HeadCamera(const Pose2& base, const HumanoidConfig& config, double lateral, double vertical, double roll,
                 double yaw) {
  const Pose3 T_base_head =
      MakePoseRpy(roll, config.camera_pitch_deg * kDegToRad, yaw,
                  Eigen::Vector3d(config.camera_forward_offset, lateral, config.camera_height + vertical));
  Pose3 T_world_camera = ToPose3(base) * T_base_head;
  T_world_camera.linear() = T_world_camera.linear() * RotationBodyFromOptical();
  return T_world_camera;
}

// sin(a) / a, stable near 0.
double Sinc(double a) { return std::abs(a) < 1e-6 ? 1.0 - a * a / 6.0 : std::sin(a) / a; }

Eigen::Vector2d Rotate(double angle, const Eigen::Vector2d& v) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

// SE(2) exponential and logarithm, xi = (v_x [m], v_y [m], omega [rad]): the motion of constant
// forward, sideways and turning speed for unit time, i.e. a circular arc. exp((a + b) xi) =
// exp(a xi) exp(b xi), which is what lets a walk be cut into equal footsteps along one arc.
// The translation part uses V(w) = Sinc(w / 2) R(w / 2).
Pose2 Exp(const Eigen::Vector3d& xi) {
  const double w = xi.z();
  const Eigen::Vector2d t = Sinc(0.5 * w) * Rotate(0.5 * w, xi.head<2>());
  return {t.x(), t.y(), WrapAngle(w)};
}

Eigen::Vector3d Log(const Pose2& p) {
  const double w = WrapAngle(p.theta);
  const Eigen::Vector2d v = Rotate(-0.5 * w, p.Position()) / Sinc(0.5 * w);
  return {v.x(), v.y(), w};
}

// 0 -> 0, 1 -> 1 with zero speed at both ends, so the body does not jerk between footsteps.
double SmoothStep(double u) { return u * u * (3.0 - 2.0 * u); }

Eigen::Vector3d StepLimits(const HumanoidConfig& c) {
  return {c.max_step_x, c.max_step_y, c.max_step_theta_deg * kDegToRad};
}

bool Fits(const Pose2& step, const Eigen::Vector3d& limits) {
  const Eigen::Vector3d s(step.x, step.y, step.theta);
  return (s.cwiseAbs().array() <= limits.array() * (1.0 + 1e-9)).all();
}

// The fewest equal footsteps exp(xi / n) that walk xi within the limits. Each component of xi / n
// bounds the step's, but turning while walking bends the step, hence the search upwards.
int StepsNeeded(const Eigen::Vector3d& xi, const Eigen::Vector3d& limits) {
  const Eigen::Vector3d ratio = xi.cwiseAbs().cwiseQuotient(limits);
  int n = std::max(1, static_cast<int>(std::ceil(ratio.maxCoeff() - 1e-9)));
  while (!Fits(Exp(xi / n), limits)) ++n;
  return n;
}

// The relative motion `step` carried out up to fraction s in [0, 1], along its arc.
Pose2 PartOf(const Pose2& step, double s) { return Exp(s * Log(step)); }

}  // namespace

SimulatedHumanoid::SimulatedHumanoid(const HumanoidConfig& config, const Pose2& start, std::uint64_t seed)
    : config_(config), rng_(seed), true_pose_(start), belief_(start) {
  ValidateConfig(config_, "humanoid.");
  // Drawn once: a real robot's gait errs the same way in every step of a run.
  bias_scale_ = config_.bias_scale_std * unit_normal_(rng_);
  bias_lateral_ = config_.bias_lateral_std * unit_normal_(rng_);
  bias_yaw_ = config_.bias_yaw_deg_std * kDegToRad * unit_normal_(rng_);
}

void SimulatedHumanoid::MoveTo(double dx, double dy, double dtheta) {
  if (!std::isfinite(dx) || !std::isfinite(dy) || !std::isfinite(dtheta)) {
    throw std::invalid_argument("SimulatedHumanoid::MoveTo: the displacement is not finite");
  }
  goal_ = Compose(OdometryPose(), Pose2{dx, dy, dtheta});
  if (!step_) StartNextStep(time_);
}

void SimulatedHumanoid::Stop() { goal_.reset(); }

bool SimulatedHumanoid::IsWalking() const { return step_.has_value(); }

void SimulatedHumanoid::Advance(double dt) {
  if (!(dt >= 0.0) || !std::isfinite(dt)) {
    throw std::invalid_argument("SimulatedHumanoid::Advance: dt must be finite and >= 0, got " +
                                std::to_string(dt));
  }
  const double end = time_ + dt;
  // Steps chain without pause, however long dt is.
  while (step_ && step_->start + config_.step_duration <= end) {
    const double step_end = step_->start + config_.step_duration;
    FinishStep();
    StartNextStep(step_end);
  }
  time_ = end;
}

Pose2 SimulatedHumanoid::TruePose() const {
  return step_ ? Compose(true_pose_, PartOf(step_->actual, StepFraction())) : true_pose_;
}

Pose2 SimulatedHumanoid::OdometryPose() const {
  return step_ ? Compose(belief_, PartOf(step_->commanded, StepFraction())) : belief_;
}

Pose3 SimulatedHumanoid::CameraPose() const {
  // Head sway as in sim/src/walk.cpp, locked to the footsteps: the head leans over the stance
  // foot, so one sway period spans two steps, and bobs once a step. Every term is zero at a step's
  // ends, so the head never jumps; the first and last steps of a walk also fade it in and out.
  double lateral = 0.0, vertical = 0.0, roll = 0.0, yaw = 0.0;
  if (step_) {
    const double u = std::clamp((time_ - step_->start) / config_.step_duration, 0.0, 1.0);
    double fade = 1.0;
    if (step_->first) fade *= SmoothStep(u);
    if (step_->last) fade *= SmoothStep(1.0 - u);
    const double stance_side = step_->left ? -1.0 : 1.0;  // the left foot swings: lean right
    const double lean = fade * stance_side * std::sin(M_PI * u);
    lateral = config_.sway_lateral * lean;
    vertical = fade * config_.sway_vertical * 0.5 * (1.0 - std::cos(2.0 * M_PI * u));
    roll = -config_.sway_roll_deg * kDegToRad * lean;  // leaning left lifts the right side
    yaw = config_.sway_yaw_deg * kDegToRad * lean;
  }
  return HeadCamera(TruePose(), config_, lateral, vertical, roll, yaw);
}

Pose3 NominalCameraPose(const Pose2& base, const HumanoidConfig& config) {
  return HeadCamera(base, config, 0.0, 0.0, 0.0, 0.0);
}

void SimulatedHumanoid::StartNextStep(double start_time) {
  const bool fade_in = !step_ || step_->last;
  step_.reset();
  if (!goal_) return;
  // Planned from the belief: the robot cannot know where it really is.
  const Pose2 remaining = Between(belief_, *goal_);
  const Eigen::Vector3d xi = Log(remaining);
  if (xi.cwiseAbs().maxCoeff() < 1e-12) {  // arrived (or told to walk nowhere): no time, no noise
    goal_.reset();
    return;
  }
  const int n = StepsNeeded(xi, StepLimits(config_));
  Step step;
  step.start = start_time;
  step.commanded = n == 1 ? remaining : Exp(xi / n);  // the last step lands on the goal exactly
  step.actual = NoisyStep(step.commanded);
  step.left = next_left_;
  step.first = fade_in;
  step.last = n == 1;
  next_left_ = !next_left_;
  step_ = step;
}

void SimulatedHumanoid::FinishStep() {
  true_pose_ = Compose(true_pose_, step_->actual);
  belief_ = Compose(belief_, step_->commanded);
  const double half = 0.5 * config_.foot_separation;
  footsteps_.push_back({step_->start + config_.step_duration, step_->left,
                        Compose(true_pose_, Pose2{0.0, step_->left ? half : -half, 0.0})});
  // step_ stays until StartNextStep, which reads how the walk went on.
}

double SimulatedHumanoid::StepFraction() const {
  return SmoothStep(std::clamp((time_ - step_->start) / config_.step_duration, 0.0, 1.0));
}

Pose2 SimulatedHumanoid::NoisyStep(const Pose2& commanded) {
  // Drawn in a fixed order so a seed replays the same run.
  const double noise_x = unit_normal_(rng_), noise_y = unit_normal_(rng_), noise_theta = unit_normal_(rng_);
  const double walked = std::hypot(commanded.x, commanded.y);  // [m]
  Pose2 actual;
  actual.x = commanded.x * (1.0 + bias_scale_) + config_.step_noise_xy * noise_x;
  actual.y = commanded.y + bias_lateral_ * walked + config_.step_noise_xy * noise_y;
  actual.theta = commanded.theta + bias_yaw_ + config_.step_noise_theta_deg * kDegToRad * noise_theta;
  return actual;
}

}  // namespace planemap::nav
