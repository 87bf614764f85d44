#include "planemap/nav/search.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace planemap::nav {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Whether a landmark is a face of an object classified as neither the target nor unknown, with
// its height measured: a class told apart by height (a box from a locker) is not decided while
// the object's top is unseen.
bool ExplainedByOtherClass(const PlaneMap& map, int landmark, const std::string& target_label) {
  for (const MapObject& o : map.objects) {
    if (o.label == target_label || o.label == "unknown" || !o.dimension_complete[2]) continue;
    if (std::find(o.landmarks.begin(), o.landmarks.end(), landmark) != o.landmarks.end()) return true;
  }
  return false;
}

bool LookedAt(const std::vector<Viewpoint>& viewpoints, const SearchCandidate& c, double radius) {
  for (const Viewpoint& v : viewpoints) {
    if (v.candidate.landmark == c.landmark || (v.candidate.center - c.center).norm() < radius) return true;
  }
  return false;
}

}  // namespace

std::vector<SearchCandidate> SearchCandidates(const PlaneMap& map, const Pose2& robot,
                                              const SearchConfig& config, const std::string& target_label) {
  std::vector<SearchCandidate> candidates;
  const int floor = map.Floor();
  const double max_vertical = std::sin(config.candidate_vertical_tolerance_deg * kDeg);
  for (const PlaneLandmark& l : map.landmarks) {
    if (l.id == floor || l.points.empty() || l.observations < config.candidate_min_observations) continue;
    if (std::abs(l.plane.normal.z()) > max_vertical) continue;
    if (ExplainedByOtherClass(map, l.id, target_label)) continue;
    const Eigen::Vector2d n = l.plane.normal.head<2>().normalized();
    const Eigen::Vector2d along(-n.y(), n.x());  // the face's horizontal direction
    double low = std::numeric_limits<double>::infinity(), high = -low, top = -low;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const Eigen::Vector3f& p : l.points) {
      const Eigen::Vector2d q = p.head<2>().cast<double>();
      low = std::min(low, along.dot(q));
      high = std::max(high, along.dot(q));
      top = std::max(top, static_cast<double>(p.z()));
      mean += q;
    }
    mean /= static_cast<double>(l.points.size());
    if (top > config.candidate_max_height || high - low > config.candidate_max_width ||
        high - low < config.candidate_min_width)
      continue;
    SearchCandidate c;
    c.landmark = l.id;
    c.center = mean + along * (0.5 * (low + high) - along.dot(mean));
    c.normal = n;
    c.distance = (c.center - robot.Position()).norm();
    candidates.push_back(c);
  }
  std::stable_sort(
      candidates.begin(), candidates.end(),
      [](const SearchCandidate& a, const SearchCandidate& b) { return a.distance < b.distance; });
  return candidates;
}

Search::Search(const SearchConfig& config, const MissionConfig& mission, const PlannerConfig& planner,
               const GraspConfig& grasp, Humanoid* robot)
    : config_(config), walk_(Scenario::kPathFeedback, mission, planner, grasp, robot) {
  ValidateConfig(config, "search.");
}

Search::~Search() = default;

bool Search::Next(const PlaneMap& map, const Pose2& estimate, const std::string& target_label,
                  std::string* reason) {
  if (static_cast<int>(viewpoints_.size()) >= config_.views_max) {
    *reason = "looked again from " + std::to_string(viewpoints_.size()) + " viewpoints (search.views_max)";
    return false;
  }
  const std::vector<SearchCandidate> candidates = SearchCandidates(map, estimate, config_, target_label);
  int fresh = 0;
  std::string last_failure;
  for (const SearchCandidate& c : candidates) {
    if (LookedAt(viewpoints_, c, config_.visited_radius)) continue;
    ++fresh;
    // Both sides of the normal; the one nearer the robot first.
    std::vector<Pose2> poses;
    for (double side : {1.0, -1.0}) {
      const double a = std::atan2(c.normal.y(), c.normal.x()) + side * config_.view_angle_deg * kDeg;
      const Eigen::Vector2d p = c.center + config_.view_distance * Eigen::Vector2d(std::cos(a), std::sin(a));
      poses.push_back({p.x(), p.y(), std::atan2(c.center.y() - p.y(), c.center.x() - p.x())});
    }
    if ((poses[1].Position() - estimate.Position()).norm() <
        (poses[0].Position() - estimate.Position()).norm())
      std::swap(poses[0], poses[1]);
    for (const Pose2& pose : poses) {
      const PlanResult plan = walk_.PlanTo(map, pose, estimate);
      if (plan.ok) {
        viewpoints_.push_back({pose, c});
        return true;
      }
      last_failure = plan.reason;
    }
  }
  if (candidates.empty()) {
    *reason = "no face in the map could be the target's (search candidates)";
  } else if (fresh == 0) {
    *reason =
        "every candidate face was looked at again (" + std::to_string(viewpoints_.size()) + " viewpoints)";
  } else {
    *reason = "no viewpoint of the " + std::to_string(fresh) +
              " candidate faces left can be walked to: " + last_failure;
  }
  return false;
}

void Search::Update(double time, const std::optional<Pose2>& estimate) {
  walk_.Update(time, estimate, nullptr);
}

bool Search::Walking() const { return walk_.Status().outcome == MissionStatus::Outcome::kRunning; }

MissionStatus Search::Status() const { return walk_.Status(); }

const std::vector<Viewpoint>& Search::Viewpoints() const { return viewpoints_; }

const SearchConfig& Search::Config() const { return config_; }

}  // namespace planemap::nav
