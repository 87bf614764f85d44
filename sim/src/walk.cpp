#include "planemap/sim/walk.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace planemap::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Where the robot's feet are at a moment of the walk.
struct BodyState {
  double x = 0, y = 0, yaw = 0;  // on the floor [m, m, rad]
  double walking_time = -1.0;    // time since this straight stretch started; < 0 standing [s]
  double stretch_left = 0.0;     // time until this straight stretch ends [s]
};

// A piece of the walk: turning on the spot or walking straight.
struct Piece {
  double duration;
  Eigen::Vector2d from, to;
  double yaw_from, yaw_to;
  bool walking;
};

double WrapAngle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

std::vector<Piece> PlanPieces(const WalkConfig& c) {
  std::vector<Eigen::Vector2d> points;
  for (size_t i = 0; i + 1 < c.waypoints.size(); i += 2) points.emplace_back(c.waypoints[i], c.waypoints[i + 1]);
  std::vector<Piece> pieces;
  double yaw = 0.0;
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const Eigen::Vector2d d = points[i + 1] - points[i];
    if (d.norm() < 1e-9) continue;
    const double heading = std::atan2(d.y(), d.x());
    if (pieces.empty()) {
      yaw = heading;
      pieces.push_back({c.hold, points[i], points[i], yaw, yaw, false});
    } else {
      const double turn = WrapAngle(heading - yaw);
      pieces.push_back({std::abs(turn) / (c.turn_rate_deg * kDegToRad), points[i], points[i], yaw, yaw + turn, false});
      yaw += turn;
    }
    pieces.push_back({d.norm() / c.speed, points[i], points[i + 1], yaw, yaw, true});
  }
  if (pieces.empty()) throw std::invalid_argument("walk: the waypoints do not leave the start point");
  pieces.push_back({c.hold, pieces.back().to, pieces.back().to, yaw, yaw, false});
  return pieces;
}

BodyState StateAt(const std::vector<Piece>& pieces, double t) {
  for (const Piece& p : pieces) {
    if (t <= p.duration || &p == &pieces.back()) {
      const double s = p.duration > 0 ? std::clamp(t / p.duration, 0.0, 1.0) : 1.0;
      const Eigen::Vector2d xy = (1 - s) * p.from + s * p.to;
      BodyState state{xy.x(), xy.y(), p.yaw_from + s * (p.yaw_to - p.yaw_from), -1.0, 0.0};
      if (p.walking) {
        state.walking_time = t;
        state.stretch_left = p.duration - t;
      }
      return state;
    }
    t -= p.duration;
  }
  return {};
}

}  // namespace

Trajectory GenerateWalk(const WalkConfig& c) {
  ValidateConfig(c, "walk.");
  if (c.waypoints.size() < 4 || c.waypoints.size() % 2 != 0) {
    throw std::invalid_argument("walk.waypoints needs x y pairs for at least two points");
  }
  const std::vector<Piece> pieces = PlanPieces(c);
  double total = 0.0;
  for (const Piece& p : pieces) total += p.duration;

  const Eigen::Matrix3d R_body_optical = RotationBodyFromOptical();
  Trajectory trajectory;
  // Every pose is held in memory (about 140 bytes each): a rate or walk that asks for more than
  // this is a typo, not a recording (a million poses: 9 hours at 30 Hz).
  constexpr double kMaxPoses = 1e6;
  const double poses = std::floor(total * c.rate) + 1;
  if (poses > kMaxPoses) {
    throw std::invalid_argument("the walk would have " + config_detail::ShortNumber(poses) + " poses (" + config_detail::ShortNumber(total) +
                                " s at walk.rate " + config_detail::ShortNumber(c.rate) + " Hz): more than " +
                                config_detail::ShortNumber(kMaxPoses));
  }
  const int frames = static_cast<int>(poses);
  for (int k = 0; k < frames; ++k) {
    const double t = k / c.rate;
    const BodyState body = StateAt(pieces, t);
    // Sway while walking, faded in and out over one step so the head does not jump.
    double lateral = 0, vertical = 0, roll = 0, yaw_sway = 0;
    if (body.walking_time >= 0.0) {
      const double step = 1.0 / c.step_frequency;
      const double fade = std::clamp(std::min(body.walking_time, body.stretch_left) / step, 0.0, 1.0);
      const double phase = M_PI * c.step_frequency * body.walking_time;  // one sway period = two steps
      lateral = fade * c.sway_lateral * std::sin(phase);
      vertical = fade * c.sway_vertical * 0.5 * (1.0 - std::cos(2.0 * phase));
      roll = fade * c.sway_roll_deg * kDegToRad * std::sin(phase);
      yaw_sway = fade * c.sway_yaw_deg * kDegToRad * std::sin(phase);
    }
    const Pose3 T_world_body = MakePoseRpy(0, 0, body.yaw, Eigen::Vector3d(body.x, body.y, 0));
    const Pose3 T_body_head = MakePoseRpy(roll, c.camera_pitch_deg * kDegToRad, yaw_sway,
                                          Eigen::Vector3d(0, lateral, c.camera_height + vertical));
    Pose3 T_world_camera = T_world_body * T_body_head;
    T_world_camera.linear() = T_world_camera.linear() * R_body_optical;
    trajectory.push_back({c.start_stamp + t, T_world_camera});
  }
  return trajectory;
}

Trajectory LoadTrajectory(const std::string& file) {
  const bool is_yaml = file.size() > 5 && (file.substr(file.size() - 5) == ".yaml" || file.substr(file.size() - 4) == ".yml");
  if (!is_yaml) return ReadTumTrajectory(file);
  const WalkConfig walk = LoadConfigFile<WalkConfig>(file);
  try {
    return GenerateWalk(walk);
  } catch (const std::invalid_argument& e) {  // a walk that cannot be planned: name its file
    ThrowInputError(file, 0, e.what());
  }
}

}  // namespace planemap::sim
