#include "planemap/nav/target.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace planemap::nav {
namespace {

// How far a measured dimension is outside the told one's tolerance [m]; 0 when it fits. A
// dimension only bounded from below fits while the bound is not past the told size.
double Excess(double measured, bool complete, double told, double tolerance) {
  const double over = measured - told - tolerance;
  if (!complete) return std::max(0.0, over);
  return std::max({0.0, over, told - measured - tolerance});
}

}  // namespace

std::string SizeConflict(const MapObject& object, const TargetDescription& target) {
  if (!target.size) return "";
  const Eigen::Vector3d& told = *target.size;
  const Eigen::Vector3d& d = object.dimensions;
  const auto& whole = object.dimension_complete;
  const double tol = target.tolerance;
  const double height = Excess(d.z(), whole[2], told.z(), tol);
  const double straight = std::max(Excess(d.x(), whole[0], told.x(), tol), Excess(d.y(), whole[1], told.y(), tol));
  const double crossed = std::max(Excess(d.x(), whole[0], told.y(), tol), Excess(d.y(), whole[1], told.x(), tol));
  if (height == 0.0 && std::min(straight, crossed) == 0.0) return "";
  char text[200];
  std::snprintf(text, sizeof(text), "%.0f x %.0f x %.0f cm%s, the target %.0f x %.0f x %.0f cm (within %.0f cm)",
                100 * d.x(), 100 * d.y(), 100 * d.z(), whole[0] && whole[1] && whole[2] ? "" : " (some only bounded)",
                100 * told.x(), 100 * told.y(), 100 * told.z(), 100 * tol);
  return text;
}

bool RuledOut(const MapObject& object, const TargetDescription& target) {
  if (object.label != target.label && object.label != "unknown" && object.dimension_complete[2]) return true;
  return !SizeConflict(object, target).empty();
}

}  // namespace planemap::nav
