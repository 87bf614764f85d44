#pragma once
// A simulated small humanoid (Nao-like): MoveTo is walked as discrete footsteps planned from the
// robot's dead-reckoned belief, and each footstep lands with a per-run bias and per-step noise,
// so open-loop walking drifts as a real one does (paper, Table 1). Time only moves in Advance().
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/pose.h"
#include "planemap/nav/humanoid.h"
#include "planemap/nav/pose2.h"

namespace planemap::nav {

// Defaults: Nao's gait in steps of a few centimetres. Walking 2 m open loop (MoveTo(0.5, 0, 0) four
// times, 52 steps) ends 20 cm from its goal (median over 200 seeds, 90 % within 5-54 cm), mostly
// sideways from the yaw bias; the paper's open-loop run ended 24.5 cm off (Table 1).
struct HumanoidConfig {
  double max_step_x = 0.04;             // longest step forward or backward [m]
  double max_step_y = 0.02;             // longest step sideways [m]
  double max_step_theta_deg = 10.0;     // largest turn in one step [deg]
  double step_duration = 0.5;           // time of one footstep [s]
  double foot_separation = 0.1;         // distance between the centres of the feet [m]
  double bias_scale_std = 0.04;         // per-run forward scale error, std [-]
  double bias_lateral_std = 0.03;       // per-run sideways drift per metre walked, std [m/m]
  double bias_yaw_deg_std = 0.3;        // per-run heading drift in every step, std [deg]
  double step_noise_xy = 0.003;         // per-step noise on each of x and y, std [m]
  double step_noise_theta_deg = 0.3;    // per-step heading noise, std [deg]
  double camera_height = 0.52;          // camera above the floor [m]
  double camera_forward_offset = 0.05;  // camera ahead of the base origin [m]
  double camera_pitch_deg = 20.0;       // camera tilted down [deg]
  double sway_lateral = 0.012;          // head sway amplitude while walking, sideways [m]
  double sway_vertical = 0.004;         // head bob amplitude while walking [m]
  double sway_roll_deg = 1.0;           // head roll amplitude while walking [deg]
  double sway_yaw_deg = 1.0;            // head yaw amplitude while walking [deg]

  template <class V>
  void VisitFields(V&& v) {
    v("max_step_x", max_step_x, Check::kPositive);
    v("max_step_y", max_step_y, Check::kPositive);
    v("max_step_theta_deg", max_step_theta_deg, Check::kPositive);
    v("step_duration", step_duration, Check::kPositive);
    v("foot_separation", foot_separation, Check::kNonNegative);
    v("bias_scale_std", bias_scale_std, Check::kNonNegative);
    v("bias_lateral_std", bias_lateral_std, Check::kNonNegative);
    v("bias_yaw_deg_std", bias_yaw_deg_std, Check::kNonNegative);
    v("step_noise_xy", step_noise_xy, Check::kNonNegative);
    v("step_noise_theta_deg", step_noise_theta_deg, Check::kNonNegative);
    v("camera_height", camera_height, Check::kPositive);
    v("camera_forward_offset", camera_forward_offset, Check::kAny);
    v("camera_pitch_deg", camera_pitch_deg, Check::kAny);
    v("sway_lateral", sway_lateral, Check::kNonNegative);
    v("sway_vertical", sway_vertical, Check::kNonNegative);
    v("sway_roll_deg", sway_roll_deg, Check::kNonNegative);
    v("sway_yaw_deg", sway_yaw_deg, Check::kNonNegative);
  }
};

// A foot set down: when it landed [s], which foot, and where (true pose on the floor).
struct Footstep {
  double time = 0.0;
  bool left = true;
  Pose2 foot;
};

// The camera (optical frame) on the head of a robot standing upright at `base`, without sway: where
// odometry puts the camera.
Pose3 NominalCameraPose(const Pose2& base, const HumanoidConfig& config);

class SimulatedHumanoid : public Humanoid {
 public:
  // Standing at `start` (world) at time 0. Throws std::invalid_argument for a bad config.
  SimulatedHumanoid(const HumanoidConfig& config, const Pose2& start, std::uint64_t seed);

  // Goal = OdometryPose() now, moved by (dx [m], dy [m], dtheta [rad], taken the short way round);
  // walked from the end of the current footstep on.
  void MoveTo(double dx, double dy, double dtheta) override;
  void Stop() override;
  bool IsWalking() const override;

  // Moves simulated time forward by dt >= 0 [s]; throws std::invalid_argument otherwise.
  void Advance(double dt);
  double Time() const { return time_; }  // [s]

  Pose2 TruePose() const;      // ground truth base pose in the world
  Pose2 OdometryPose() const override;  // the robot's belief: start plus the commanded steps
  // T_world_camera, optical frame (x right, y down, z forward), head sway included.
  Pose3 CameraPose() const;
  const std::vector<Footstep>& Footsteps() const { return footsteps_; }
  const HumanoidConfig& config() const { return config_; }
  // This run's gait bias, the ground truth for odometry calibration: forward scale error [-] and
  // sideways drift [m per m walked].
  double BiasScale() const { return bias_scale_; }
  double BiasLateral() const { return bias_lateral_; }

 private:
  struct Step {
    double start = 0.0;                // [s]
    Pose2 commanded, actual;           // displacement in the base frame at the step's start
    bool left = true;                  // the swinging foot
    bool first = false, last = false;  // fade the head sway in or out over this step
  };

  void StartNextStep(double start_time);
  void FinishStep();
  double StepFraction() const;  // of the step under way, smoothed, in [0, 1]
  Pose2 NoisyStep(const Pose2& commanded);

  HumanoidConfig config_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> unit_normal_{0.0, 1.0};
  double bias_scale_ = 0.0, bias_lateral_ = 0.0, bias_yaw_ = 0.0;  // [-], [m/m], [rad/step]
  double time_ = 0.0;                                              // [s]
  Pose2 true_pose_, belief_;   // at the start of the step under way, or now when standing
  std::optional<Pose2> goal_;  // in the belief's world; none when told to stop
  std::optional<Step> step_;   // the footstep under way
  bool next_left_ = true;
  std::vector<Footstep> footsteps_;
};

}  // namespace planemap::nav
