#include "planemap/nav/search.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace planemap::nav {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Whether a landmark is a face of an object the map's measurements rule out as the target
// (another class with its height measured, or another size: nav/target.h).
bool ExplainedAsNotTheTarget(const PlaneMap& map, int landmark, const TargetDescription& target) {
  for (const MapObject& o : map.objects) {
    if (!RuledOut(o, target)) continue;
    if (std::find(o.landmarks.begin(), o.landmarks.end(), landmark) != o.landmarks.end()) return true;
  }
  return false;
}

// Whether a face lies in the plane of a taller landmark beside it: a strip of a wall (its bottom,
// seen past an obstacle that hides the rest), not a face of its own. A box against a wall stands
// off it by its depth.
bool PartOfTallerPlane(const PlaneMap& map, const PlaneLandmark& face, const Eigen::Vector3d& centroid,
                       const SearchConfig& config) {
  for (const PlaneLandmark& w : map.landmarks) {
    if (w.id == face.id || w.id == map.Floor() || w.high.z() <= config.candidate_max_height) continue;
    if (w.plane.normal.dot(face.plane.normal) < std::cos(config.coplanar_angle_deg * kDeg)) continue;
    if (std::abs(w.plane.SignedDistance(centroid)) > config.coplanar_distance) continue;
    if (w.Overlaps(face.low, face.high, config.coplanar_distance)) return true;
  }
  return false;
}

bool LookedAt(const std::vector<Viewpoint>& viewpoints, const SearchCandidate& c, double radius) {
  for (const Viewpoint& v : viewpoints) {
    if (!v.Faces()) continue;
    if (v.candidate.landmark == c.landmark || (v.candidate.center - c.center).norm() < radius) return true;
  }
  return false;
}

// Whether the map's floor has a point within `radius` of p: floor seen, not only inside the
// floor's extent, which the planner takes as free (behind a shelf's front, say, is the shelf).
bool OnSeenFloor(const PlaneMap& map, const Eigen::Vector2d& p, double radius) {
  const int floor = map.Floor();
  if (floor < 0) return false;
  for (const Eigen::Vector3f& q : map.landmarks[floor].points) {
    if ((q.head<2>().cast<double>() - p).squaredNorm() <= radius * radius) return true;
  }
  return false;
}

}  // namespace

std::vector<SearchCandidate> SearchCandidates(const PlaneMap& map, const Pose2& robot,
                                              const SearchConfig& config, const TargetDescription& target) {
  std::vector<SearchCandidate> candidates;
  const int floor = map.Floor();
  const double max_vertical = std::sin(config.candidate_vertical_tolerance_deg * kDeg);
  for (const PlaneLandmark& l : map.landmarks) {
    if (l.id == floor || l.points.empty() || l.observations < config.candidate_min_observations) continue;
    if (std::abs(l.plane.normal.z()) > max_vertical) continue;
    if (ExplainedAsNotTheTarget(map, l.id, target)) continue;
    const Eigen::Vector2d n = l.plane.normal.head<2>().normalized();
    const Eigen::Vector2d along(-n.y(), n.x());  // the face's horizontal direction
    double low = std::numeric_limits<double>::infinity(), high = -low, top = -low;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3f& p : l.points) {
      const Eigen::Vector2d q = p.head<2>().cast<double>();
      low = std::min(low, along.dot(q));
      high = std::max(high, along.dot(q));
      top = std::max(top, static_cast<double>(p.z()));
      centroid += p.cast<double>();
    }
    centroid /= static_cast<double>(l.points.size());
    const Eigen::Vector2d mean = centroid.head<2>();
    if (top > config.candidate_max_height || high - low > config.candidate_max_width ||
        high - low < config.candidate_min_width)
      continue;
    if (PartOfTallerPlane(map, l, centroid, config)) continue;
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

std::vector<ExploreView> ExploreViews(const PlaneMap& map, const Pose2& robot, const SearchConfig& config,
                                      const PlannerConfig& planner) {
  const int floor = map.Floor();
  if (floor < 0) return {};
  const PlaneLandmark& f = map.landmarks[floor];
  const OccupancyGrid grid = BuildOccupancyGrid(map, planner, {}, robot.Position());
  if (grid.Empty() || !(f.low.head<2>().array() <= f.high.head<2>().array()).all()) return {};
  // The floor's extent on cells of explore_cell: seen (a floor point in it), blocked (an obstacle
  // or the extent's border within half a cell), else unseen.
  const double cell = config.explore_cell;
  const Eigen::Vector2d origin = f.low.head<2>();
  const int nx = static_cast<int>(std::ceil((f.high.x() - f.low.x()) / cell)) + 1;
  const int ny = static_cast<int>(std::ceil((f.high.y() - f.low.y()) / cell)) + 1;
  if (static_cast<double>(nx) * ny > 4e6) return {};
  enum : unsigned char { kUnseen, kSeen, kBlocked };
  std::vector<unsigned char> state(static_cast<size_t>(nx) * ny, kUnseen);
  const auto centre = [&](int i, int j) { return Eigen::Vector2d(origin + cell * Eigen::Vector2d(i + 0.5, j + 0.5)); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (grid.Clearance(centre(i, j)) < 0.5 * cell) state[j * nx + i] = kBlocked;
    }
  }
  for (const Eigen::Vector3f& p : f.points) {
    const int i = static_cast<int>(std::floor((p.x() - origin.x()) / cell));
    const int j = static_cast<int>(std::floor((p.y() - origin.y()) / cell));
    if (i >= 0 && j >= 0 && i < nx && j < ny && state[j * nx + i] == kUnseen) state[j * nx + i] = kSeen;
  }
  // From each viewpoint (every other cell, where the robot may stand), rays every 3 deg; each
  // unseen cell counts once, for the first ray that reaches it in range.
  constexpr int kRays = 120;
  const int fov_rays = std::max(1, static_cast<int>(std::lround(config.explore_fov_deg / (360.0 / kRays))));
  const double area = cell * cell;
  std::vector<int> stamp(state.size(), -1);
  std::vector<ExploreView> views;
  int viewpoint = 0;
  const auto evaluate = [&](const Eigen::Vector2d& v) {
    ++viewpoint;
    std::vector<double> gain(kRays, 0.0);
    for (int r = 0; r < kRays; ++r) {
      const double a = 2.0 * M_PI * r / kRays;
      const Eigen::Vector2d d(std::cos(a), std::sin(a));
      for (double t = 0.5 * cell; t <= config.explore_max_range; t += 0.5 * cell) {
        const Eigen::Vector2d q = v + t * d;
        const int ci = static_cast<int>(std::floor((q.x() - origin.x()) / cell));
        const int cj = static_cast<int>(std::floor((q.y() - origin.y()) / cell));
        if (ci < 0 || cj < 0 || ci >= nx || cj >= ny) break;
        const size_t k = static_cast<size_t>(cj) * nx + ci;
        if (state[k] == kBlocked) break;  // the camera does not see past an obstacle
        if (state[k] == kUnseen && t >= config.explore_min_range && stamp[k] != viewpoint) {
          stamp[k] = viewpoint;
          gain[r] += area;
        }
      }
    }
    // The heading whose field of view takes in the most.
    double best = -1.0;
    int best_ray = 0;
    for (int r = 0; r < kRays; ++r) {
      double sum = 0.0;
      for (int k = -fov_rays / 2; k <= fov_rays / 2; ++k) sum += gain[(r + k + kRays) % kRays];
      if (sum > best) best = sum, best_ray = r;
    }
    if (best >= config.explore_min_area) views.push_back({Pose2{v.x(), v.y(), WrapAngle(2.0 * M_PI * best_ray / kRays)}, best});
  };
  // Where the robot stands (turning there to look needs no walk), then every other cell of seen
  // floor: the planner takes the floor's whole extent as free, but behind a shelf's front, say,
  // is the shelf.
  if (grid.Free(robot.Position())) evaluate(robot.Position());
  for (int j = 0; j < ny; j += 2) {
    for (int i = 0; i < nx; i += 2) {
      const Eigen::Vector2d v = centre(i, j);
      const double walk = (v - robot.Position()).norm();
      if (walk > config.explore_max_walk || state[j * nx + i] != kSeen || !grid.Free(v)) continue;
      evaluate(v);
    }
  }
  const auto score = [&](const ExploreView& e) {
    return e.unseen_area - config.explore_walk_cost * (e.pose.Position() - robot.Position()).norm();
  };
  std::stable_sort(views.begin(), views.end(),
                   [&](const ExploreView& a, const ExploreView& b) { return score(a) > score(b); });
  return views;
}

Search::Search(const SearchConfig& config, const MissionConfig& mission, const PlannerConfig& planner,
               const GraspConfig& grasp, Humanoid* robot)
    : config_(config),
      planner_(planner),
      settle_time_(mission.settle_time),
      robot_(robot),
      walk_(Scenario::kPathFeedback, mission, planner, grasp, robot) {
  ValidateConfig(config, "search.");
  auto below = [](double low, double high, const char* low_name, const char* high_name) {
    if (low < high) return;
    char what[200];
    std::snprintf(what, sizeof(what), "search.%s (%g) must be below search.%s (%g)", low_name, low, high_name, high);
    throw std::invalid_argument(what);
  };
  below(config.candidate_min_width, config.candidate_max_width, "candidate_min_width", "candidate_max_width");
  below(config.explore_min_range, config.explore_max_range, "explore_min_range", "explore_max_range");
  if (config.explore_fov_deg > 180.0) {
    char what[120];
    std::snprintf(what, sizeof(what), "search.explore_fov_deg (%g) must be at most 180 deg", config.explore_fov_deg);
    throw std::invalid_argument(what);
  }
}

Search::~Search() = default;

bool Search::Next(const PlaneMap& map, const Pose2& estimate, const TargetDescription& target,
                  std::string* reason) {
  int faces = 0, explores = 0;
  for (const Viewpoint& v : viewpoints_) {
    faces += v.Faces();
    explores += v.Explores();
  }
  std::string last_failure;
  if (faces >= config_.views_max) {
    *reason = "looked again at " + std::to_string(faces) + " candidate faces (search.views_max)";
  } else {
    const std::vector<SearchCandidate> candidates = SearchCandidates(map, estimate, config_, target);
    int fresh = 0;
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
        if (!OnSeenFloor(map, pose.Position(), config_.explore_cell)) {
          last_failure = "the viewpoint stands on floor not seen yet";
          continue;
        }
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
      *reason = "every candidate face was looked at again (" + std::to_string(faces) + " viewpoints)";
    } else {
      *reason = "no viewpoint of the " + std::to_string(fresh) +
                " candidate faces left can be walked to: " + last_failure;
    }
  }
  if (config_.explore && explores >= config_.explore_views_max) {
    *reason += "; explored from " + std::to_string(explores) + " views (search.explore_views_max)";
  } else if (config_.explore) {
    // Exploring: the best view that can be walked to (the first few tried); none near enough,
    // the best anywhere on the seen floor: the room is searched when no view is left.
    std::vector<ExploreView> views = ExploreViews(map, estimate, config_, planner_);
    if (views.empty()) {
      SearchConfig anywhere = config_;
      anywhere.explore_max_walk = std::numeric_limits<double>::infinity();
      views = ExploreViews(map, estimate, anywhere, planner_);
    }
    for (size_t k = 0; k < std::min<size_t>(views.size(), 10); ++k) {
      const PlanResult plan = walk_.PlanTo(map, views[k].pose, estimate);
      if (plan.ok) {
        Viewpoint v{views[k].pose, {}, views[k].unseen_area};
        v.candidate.center = views[k].pose.Position();
        viewpoints_.push_back(v);
        return true;
      }
      last_failure = plan.reason;
    }
    char none[160];
    std::snprintf(none, sizeof(none), "; no view on the seen floor brings %.1f m^2 of floor not seen yet into view (search.explore_*)",
                  config_.explore_min_area);
    *reason += views.empty() ? std::string(none)
                             : "; none of the " + std::to_string(views.size()) +
                                   " exploring views can be walked to: " + last_failure;
  }
  if (turns_ >= config_.turns_max) {
    *reason += "; turned on the spot " + std::to_string(turns_) + " times (search.turns_max)";
    return false;
  }
  // Turning on the spot: a round robot turning in place sweeps no floor it does not stand on.
  ++turns_;
  const double turn = config_.turn_step_deg * kDeg;
  robot_->MoveTo(0.0, 0.0, turn);
  turning_ = true;
  turn_still_since_.reset();
  Viewpoint v;
  v.pose = {estimate.x, estimate.y, WrapAngle(estimate.theta + turn)};
  v.candidate.center = estimate.Position();
  v.turn = true;
  viewpoints_.push_back(v);
  return true;
}

void Search::Update(double time, const std::optional<Pose2>& estimate, const PlaneMap* map) {
  if (!turning_) return walk_.Update(time, estimate, nullptr, map);
  if (robot_->IsWalking()) {
    turn_still_since_.reset();
    return;
  }
  if (!turn_still_since_) turn_still_since_ = time;
  if (time - *turn_still_since_ >= settle_time_) turning_ = false;
}

bool Search::Walking() const { return turning_ || walk_.Status().outcome == MissionStatus::Outcome::kRunning; }

MissionStatus Search::Status() const {
  if (!viewpoints_.empty() && viewpoints_.back().turn) {
    if (turning_) return {MissionStatus::Outcome::kRunning, "turning on the spot"};
    return {MissionStatus::Outcome::kReached, "turned on the spot"};
  }
  return walk_.Status();
}

bool Search::GaveUpView() const {
  return !turning_ && !viewpoints_.empty() && !viewpoints_.back().turn &&
         walk_.Status().outcome == MissionStatus::Outcome::kStopped && walk_.Blocked();
}

const std::vector<Viewpoint>& Search::Viewpoints() const { return viewpoints_; }

const SearchConfig& Search::Config() const { return config_; }

}  // namespace planemap::nav
