#pragma once
// The humanoid motion model interface: a relative walk command, as Nao's ALMotion::moveTo.
// A real robot implements the same interface; SimulatedHumanoid (simulated_humanoid.h)
// walks it as noisy footsteps.
#include "planemap/nav/pose2.h"

namespace planemap::nav {

class Humanoid {
 public:
  virtual ~Humanoid() = default;

  // Walks a relative displacement, in the base frame at the time of the call: dx forward [m],
  // dy to the left [m], then facing dtheta more to the left [rad]. Replaces a walk in progress.
  virtual void MoveTo(double dx, double dy, double dtheta) = 0;
  // Stops at the next footstep.
  virtual void Stop() = 0;
  // Whether a walk is still being executed.
  virtual bool IsWalking() const = 0;
  // The walking engine's dead reckoning (Nao: ALMotion::getRobotPosition): the base pose in its own
  // odometry frame, which drifts from the world; its changes are the motion it measured.
  virtual Pose2 OdometryPose() const = 0;
};

}  // namespace planemap::nav
