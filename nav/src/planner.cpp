#include "planemap/nav/planner.h"

#include <algorithm>
#include <optional>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <queue>
#include <stdexcept>
#include <utility>

namespace planemap::nav {
namespace {

// "No obstacle" in the distance transform [cells^2]: large, yet exact in double arithmetic
// together with the squared cell indices added to it.
constexpr double kFar = 1e12;
// Grids above this many cells (a floor of ~100 m x 100 m at 2 cm) are refused.
constexpr double kMaxCells = 5e7;

std::string Where(const Eigen::Vector2d& p) {
  char text[64];
  std::snprintf(text, sizeof(text), "(%.2f, %.2f)", p.x(), p.y());
  return text;
}

int CellIndex(const OccupancyGrid& grid, const Eigen::Vector2d& p) {
  const Eigen::Vector2d c = (p - grid.origin) / grid.resolution;
  if (!std::isfinite(c.x()) || !std::isfinite(c.y())) return -1;
  const long i = std::lround(c.x()), j = std::lround(c.y());
  if (i < 0 || j < 0 || i >= grid.width || j >= grid.height) return -1;
  return static_cast<int>(j * grid.width + i);
}

Eigen::Vector2d CellCentre(const OccupancyGrid& grid, int k) {
  return grid.origin + grid.resolution * Eigen::Vector2d(k % grid.width, k / grid.width);
}

// Felzenszwalb & Huttenlocher, "Distance transforms of sampled functions" (2012): the lower
// envelope of parabolas rooted at f, i.e. min_q' ((q - q')^2 + f[q']), for one line of cells.
void SquaredDistance1d(std::vector<double>* f, std::vector<int>* v, std::vector<double>* z) {
  const int n = static_cast<int>(f->size());
  const auto cross = [&](int q, int p) { return ((*f)[q] + q * q - ((*f)[p] + p * p)) / (2.0 * (q - p)); };
  int k = 0;
  (*v)[0] = 0;
  (*z)[0] = -std::numeric_limits<double>::infinity();
  (*z)[1] = std::numeric_limits<double>::infinity();
  for (int q = 1; q < n; ++q) {
    double s = cross(q, (*v)[k]);
    while (s <= (*z)[k]) s = cross(q, (*v)[--k]);
    (*v)[++k] = q;
    (*z)[k] = s;
    (*z)[k + 1] = std::numeric_limits<double>::infinity();
  }
  std::vector<double> d(n);
  for (int q = 0, j = 0; q < n; ++q) {
    while ((*z)[j + 1] < q) ++j;
    d[q] = (q - (*v)[j]) * (q - (*v)[j]) + (*f)[(*v)[j]];
  }
  *f = std::move(d);
}

// Exact Euclidean distance [cells^2] from every cell to the nearest blocked one: rows, then columns.
std::vector<double> SquaredDistanceTransform(const std::vector<std::uint8_t>& blocked, int w, int h) {
  std::vector<double> d(blocked.size());
  for (size_t k = 0; k < d.size(); ++k) d[k] = blocked[k] ? 0.0 : kFar;
  const int n = std::max(w, h);
  std::vector<int> v(n);
  std::vector<double> z(n + 1), line;
  for (int j = 0; j < h; ++j) {
    line.assign(d.begin() + j * w, d.begin() + (j + 1) * w);
    SquaredDistance1d(&line, &v, &z);
    std::copy(line.begin(), line.end(), d.begin() + j * w);
  }
  line.resize(h);
  for (int i = 0; i < w; ++i) {
    for (int j = 0; j < h; ++j) line[j] = d[j * w + i];
    SquaredDistance1d(&line, &v, &z);
    for (int j = 0; j < h; ++j) d[j * w + i] = line[j];
  }
  return d;
}

// Blocks the cells whose square could hold a point of the footprint: centre within half a diagonal.
void MarkFootprint(const OccupancyGrid& grid, const Footprint& footprint,
                   std::vector<std::uint8_t>* blocked) {
  const double half_diagonal = grid.resolution * M_SQRT1_2;
  const Eigen::Vector2d reach =
      footprint.axes.cwiseAbs() * footprint.half_size + Eigen::Vector2d::Constant(half_diagonal);
  const Eigen::Vector2d low = (footprint.center - reach - grid.origin) / grid.resolution;
  const Eigen::Vector2d high = (footprint.center + reach - grid.origin) / grid.resolution;
  for (int j = std::max(0, int(std::floor(low.y())));
       j <= std::min(grid.height - 1, int(std::ceil(high.y()))); ++j) {
    for (int i = std::max(0, int(std::floor(low.x())));
         i <= std::min(grid.width - 1, int(std::ceil(high.x()))); ++i) {
      const int k = j * grid.width + i;
      if (footprint.Distance(CellCentre(grid, k)) <= half_diagonal) (*blocked)[k] = 1;
    }
  }
}

// Whether an object's vertical extent meets the height band above the floor.
bool InHeightBand(const MapObject& object, const Plane& floor, const PlannerConfig& config) {
  const double half_height = 0.5 * object.axes.row(2).cwiseAbs().dot(object.dimensions);
  const double centre = floor.SignedDistance(object.center);
  return centre + half_height >= config.min_obstacle_height &&
         centre - half_height <= config.max_obstacle_height;
}

// Obstacle cells: unknown space outside the floor's extent, landmark points in the height band,
// object footprints. The target is left out: Slack() measures it exactly.
std::vector<std::uint8_t> ObstacleCells(const PlaneMap& map, const OccupancyGrid& grid,
                                        const PlaneLandmark& floor_landmark, const Eigen::Vector2d& low,
                                        const Eigen::Vector2d& high) {
  std::vector<std::uint8_t> blocked(static_cast<size_t>(grid.width) * grid.height, 0);
  for (size_t k = 0; k < blocked.size(); ++k) {
    const Eigen::Vector2d c = CellCentre(grid, static_cast<int>(k));
    blocked[k] = (c.array() < low.array()).any() || (c.array() > high.array()).any();
  }
  const Plane floor =
      floor_landmark.plane.normal.z() >= 0.0 ? floor_landmark.plane : floor_landmark.plane.Flipped();
  const PlannerConfig& config = grid.config;
  const bool has_target = grid.target.object >= 0;
  const auto is_target_face = [&](int id) {
    if (!has_target) return false;
    const std::vector<int>& faces = map.objects[grid.target.object].landmarks;
    return std::find(faces.begin(), faces.end(), id) != faces.end();
  };
  const auto near_target = [&](const Eigen::Vector2d& p) {
    return has_target && grid.target_footprint.Distance(p) <= config.target_margin;
  };
  for (const PlaneLandmark& l : map.landmarks) {
    if (l.id == floor_landmark.id || is_target_face(l.id)) continue;
    for (const Eigen::Vector3f& point : l.points) {
      const double h = floor.SignedDistance(point.cast<double>());
      if (h < config.min_obstacle_height || h > config.max_obstacle_height) continue;
      if (near_target(point.cast<double>().head<2>())) continue;
      const int k = CellIndex(grid, point.cast<double>().head<2>());
      if (k >= 0) blocked[k] = 1;
    }
  }
  for (int o = 0; o < static_cast<int>(map.objects.size()); ++o) {
    const MapObject& object = map.objects[o];
    if (o != grid.target.object && !object.structure && !near_target(object.center.head<2>()) &&
        InHeightBand(object, floor, config)) {
      MarkFootprint(grid, FootprintOf(object), &blocked);
    }
  }
  return blocked;
}

// Step cost factor of a cell: 1 with the full margin of clearance, up to 1 + clearance_cost.
double CostFactor(const OccupancyGrid& grid, double slack) {
  const double margin = grid.config.clearance_margin;
  if (margin <= 0.0) return 1.0;
  return 1.0 + grid.config.clearance_cost * std::clamp((margin - slack) / margin, 0.0, 1.0);
}

// The shortest 8-connected distance between two cells on a free grid [m]: A*'s admissible heuristic.
double Octile(const OccupancyGrid& grid, int a, int b) {
  const int di = std::abs(a % grid.width - b % grid.width), dj = std::abs(a / grid.width - b / grid.width);
  return grid.resolution * (std::max(di, dj) + (M_SQRT2 - 1.0) * std::min(di, dj));
}

std::vector<int> Backtrack(const std::vector<int>& parent, int goal) {
  std::vector<int> cells;
  for (int k = goal; k >= 0; k = parent[k]) cells.push_back(k);
  std::reverse(cells.begin(), cells.end());
  return cells;
}

// A* over 8-connected cells from `start` to `goal` (cell indices); the cells of the path, or none.
std::vector<int> AStar(const OccupancyGrid& grid, int start, int goal) {
  const int n = grid.width * grid.height;
  std::vector<double> cost(n, std::numeric_limits<double>::infinity());
  std::vector<int> parent(n, -1);
  std::vector<std::uint8_t> closed(n, 0);
  const auto heuristic = [&](int k) { return Octile(grid, k, goal); };
  using Entry = std::pair<double, int>;  // (estimated total cost, cell): ties go to the lower cell
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  cost[start] = 0.0;
  open.emplace(heuristic(start), start);
  while (!open.empty()) {
    const int k = open.top().second;
    open.pop();
    if (closed[k]) continue;
    closed[k] = 1;
    if (k == goal) break;
    const int i = k % grid.width, j = k / grid.width;
    for (int dj = -1; dj <= 1; ++dj) {
      for (int di = -1; di <= 1; ++di) {
        const int ni = i + di, nj = j + dj;
        if ((di == 0 && dj == 0) || ni < 0 || nj < 0 || ni >= grid.width || nj >= grid.height) continue;
        const int m = nj * grid.width + ni;
        if (closed[m]) continue;
        const double slack = grid.Slack(CellCentre(grid, m));
        if (slack < 0.0 && m != goal) continue;
        const double step = grid.resolution * (di != 0 && dj != 0 ? M_SQRT2 : 1.0) * CostFactor(grid, slack);
        if (cost[k] + step < cost[m]) {
          cost[m] = cost[k] + step;
          parent[m] = k;
          open.emplace(cost[m] + heuristic(m), m);
        }
      }
    }
  }
  return closed[goal] ? Backtrack(parent, goal) : std::vector<int>{};
}

// The least slack along a straight leg, sampled every half cell [m].
double MinSlack(const OccupancyGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const int samples = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.5 * grid.resolution))));
  double least = std::numeric_limits<double>::infinity();
  for (int s = 0; s <= samples; ++s) least = std::min(least, grid.Slack(a + (b - a) * (double(s) / samples)));
  return least;
}

// Line-of-sight shortcuts: from each vertex, the farthest next one reachable in a straight leg that
// keeps the clearance margin, or at least as much clearance as the stretch of path it replaces.
std::vector<Eigen::Vector2d> Shortcut(const OccupancyGrid& grid, const std::vector<Eigen::Vector2d>& points) {
  std::vector<double> slack(points.size());
  for (size_t k = 0; k < points.size(); ++k) slack[k] = grid.Slack(points[k]);
  std::vector<Eigen::Vector2d> out{points.front()};
  for (size_t i = 0; i + 1 < points.size();) {
    size_t best = i + 1;
    double path_least = std::min(slack[i], slack[i + 1]);
    for (size_t j = i + 2; j < points.size(); ++j) {
      path_least = std::min(path_least, slack[j]);
      const double needed = std::max(0.0, std::min(grid.config.clearance_margin, path_least));
      if (MinSlack(grid, points[i], points[j]) < needed) break;
      best = j;
    }
    out.push_back(points[best]);
    i = best;
  }
  return out;
}

// A* from a to b, ends replaced by the exact positions, shortcut; empty when there is no path.
std::vector<Eigen::Vector2d> Search(const OccupancyGrid& grid, const Eigen::Vector2d& a,
                                    const Eigen::Vector2d& b) {
  const std::vector<int> cells = AStar(grid, CellIndex(grid, a), CellIndex(grid, b));
  if (cells.empty()) return {};
  std::vector<Eigen::Vector2d> points;
  for (int k : cells) points.push_back(CellCentre(grid, k));
  if (points.size() == 1) points.push_back(b);
  points.front() = a;
  points.back() = b;
  return Shortcut(grid, points);
}

PlanResult Failure(std::string reason) {
  PlanResult result;
  result.reason = std::move(reason);
  return result;
}

std::string BlockedReason(const OccupancyGrid& grid, const char* what, const Eigen::Vector2d& p) {
  if (CellIndex(grid, p) < 0) return std::string(what) + " " + Where(p) + " is outside the map's floor";
  char text[160];
  std::snprintf(text, sizeof(text), " is blocked: %.1f cm from an obstacle, the robot needs %.1f cm",
                100.0 * grid.Clearance(p), 100.0 * (grid.Clearance(p) - grid.Slack(p)));
  return std::string(what) + " " + Where(p) + text;
}

// A robot standing inside its own clearance (a gait's error put it there, or an obstacle was seen
// only up close) steps out first: the nearest free point within robot_radius + clearance_margin
// that a straight step reaches without coming nearer any obstacle than it stands now. Nothing
// when the start is outside the grid or no such point exists.
std::optional<Eigen::Vector2d> StepOut(const OccupancyGrid& grid, const Eigen::Vector2d& a) {
  if (CellIndex(grid, a) < 0) return std::nullopt;
  const double here = grid.Slack(a);
  const double reach = grid.config.robot_radius + grid.config.clearance_margin;
  const int cells = static_cast<int>(std::ceil(reach / grid.resolution));
  std::optional<Eigen::Vector2d> best;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int dj = -cells; dj <= cells; ++dj) {
    for (int di = -cells; di <= cells; ++di) {
      const Eigen::Vector2d c = a + grid.resolution * Eigen::Vector2d(di, dj);
      const double distance = (c - a).norm();
      if (distance > reach || distance >= best_distance || !grid.Free(c)) continue;
      if (MinSlack(grid, a, c) < here - 1e-9) continue;  // the step would come nearer an obstacle
      best = c;
      best_distance = distance;
    }
  }
  return best;
}

}  // namespace

double Footprint::Distance(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d local = axes.transpose() * (p - center);
  return (local.cwiseAbs() - half_size).cwiseMax(0.0).norm();
}

Footprint FootprintOf(const MapObject& object) {
  Footprint f;
  f.center = object.center.head<2>();
  Eigen::Vector2d x = object.axes.col(0).head<2>();
  if (x.norm() < 1e-6) x = Eigen::Vector2d(object.axes(1, 1), -object.axes(0, 1));  // x axis vertical
  if (x.norm() < 1e-6) x = Eigen::Vector2d::UnitX();
  x.normalize();
  f.axes.col(0) = x;
  f.axes.col(1) = Eigen::Vector2d(-x.y(), x.x());
  // The box's horizontal extent along each footprint side, whatever its tilt.
  for (int s = 0; s < 2; ++s) {
    const Eigen::Vector3d side(f.axes(0, s), f.axes(1, s), 0.0);
    f.half_size[s] = 0.5 * (object.axes.transpose() * side).cwiseAbs().dot(object.dimensions.cwiseAbs());
  }
  return f;
}

double OccupancyGrid::Slack(const Eigen::Vector2d& p) const {
  const int k = CellIndex(*this, p);
  if (k < 0) return -1.0;
  double slack = clearance[k] - config.robot_radius;
  if (target.object >= 0) {
    const bool last_leg = (p - target.pre_grasp.Position()).norm() <= config.approach_distance + 1e-9;
    const double needed = last_leg ? config.final_leg_radius : config.robot_radius;
    slack = std::min(slack, target_footprint.Distance(p) - needed);
  }
  return slack;
}

double OccupancyGrid::Clearance(const Eigen::Vector2d& p) const {
  const int k = CellIndex(*this, p);
  if (k < 0) return 0.0;
  const double target_distance = target.object >= 0 ? target_footprint.Distance(p) : 1e9;
  return std::min<double>(clearance[k], target_distance);
}

OccupancyGrid BuildOccupancyGrid(const PlaneMap& map, const PlannerConfig& config,
                                 const GraspTarget& target, const std::optional<Eigen::Vector2d>& standing) {
  OccupancyGrid grid;
  grid.config = config;
  grid.resolution = config.resolution;
  const bool target_known = target.object >= 0 && target.object < static_cast<int>(map.objects.size());
  grid.target = target_known ? target : GraspTarget{};
  if (target_known) grid.target_footprint = FootprintOf(map.objects[target.object]);
  const int floor = map.Floor();
  if (floor < 0 || config.resolution <= 0.0) return grid;
  const PlaneLandmark& floor_landmark = map.landmarks[floor];
  Eigen::Vector2d low = floor_landmark.low.head<2>(), high = floor_landmark.high.head<2>();
  if (standing) {  // the floor the robot stands on is floor, seen or not
    const Eigen::Vector2d r = Eigen::Vector2d::Constant(config.robot_radius + config.clearance_margin + config.resolution);
    low = low.cwiseMin(*standing - r);
    high = high.cwiseMax(*standing + r);
  }
  const Eigen::Vector2d cells =
      (high - low + Eigen::Vector2d::Constant(2.0 * config.floor_margin)) / config.resolution;
  if (!(low.array() <= high.array()).all() || cells.prod() > kMaxCells) return grid;
  grid.origin = low - Eigen::Vector2d::Constant(config.floor_margin);
  grid.width = static_cast<int>(std::ceil(cells.x())) + 1;
  grid.height = static_cast<int>(std::ceil(cells.y())) + 1;
  std::vector<std::uint8_t> blocked = ObstacleCells(map, grid, floor_landmark, low, high);
  if (standing) {  // where the robot's body stands is no obstacle, whatever the map holds there
    for (size_t k = 0; k < blocked.size(); ++k) {
      if ((CellCentre(grid, static_cast<int>(k)) - *standing).norm() <= config.standing_radius) blocked[k] = 0;
    }
  }
  const std::vector<double> squared = SquaredDistanceTransform(blocked, grid.width, grid.height);
  // From cell centres to cell centres; any point of either cell is at most a diagonal nearer.
  grid.clearance.resize(squared.size());
  for (size_t k = 0; k < squared.size(); ++k) {
    grid.clearance[k] =
        static_cast<float>(std::max(0.0, (std::sqrt(squared[k]) - M_SQRT2) * config.resolution));
  }
  return grid;
}

PlanResult PlanPath(const OccupancyGrid& grid, const Pose2& start, const Pose2& goal) {
  if (grid.Empty()) return Failure("the occupancy grid is empty: the map has no floor (or an absurd one)");
  Eigen::Vector2d a = start.Position();
  const Eigen::Vector2d b = goal.Position();
  std::optional<Eigen::Vector2d> step_out;
  if (!grid.Free(a)) {
    step_out = StepOut(grid, a);
    if (!step_out) return Failure(BlockedReason(grid, "start", a) + ", and no step out of it keeps clear of obstacles");
    a = *step_out;
  }
  if (!grid.Free(b)) return Failure(BlockedReason(grid, "goal", b));
  const double set_back = grid.config.approach_distance;
  const Eigen::Vector2d approach = b - set_back * Eigen::Vector2d(std::cos(goal.theta), std::sin(goal.theta));
  std::vector<Eigen::Vector2d> points;
  if ((a - b).norm() <= set_back && SegmentFree(grid, a, b)) {
    points = {a, b};  // already on the last leg
  } else if (set_back > 0.0 && grid.Free(approach) && SegmentFree(grid, approach, b)) {
    points = Search(grid, a, approach);
    if (!points.empty()) points.push_back(b);
  }
  if (points.empty()) points = Search(grid, a, b);
  if (points.empty())
    return Failure("no path from start " + Where(a) + " to goal " + Where(b) + " on the free floor");
  if (step_out) points.insert(points.begin(), start.Position());
  PlanResult result;
  result.ok = true;
  result.path.push_back(start);
  for (size_t k = 1; k + 1 < points.size(); ++k) {
    const Eigen::Vector2d d = points[k + 1] - points[k];
    result.path.push_back({points[k].x(), points[k].y(), std::atan2(d.y(), d.x())});
  }
  result.path.push_back(goal);
  result.length = PathLength(result.path);
  result.control_points = ControlPoints(result.path, grid.config.control_point_spacing, goal);
  return result;
}

double PathLength(const std::vector<Pose2>& path) {
  double length = 0.0;
  for (size_t k = 1; k < path.size(); ++k) length += (path[k].Position() - path[k - 1].Position()).norm();
  return length;
}

std::vector<Pose2> ControlPoints(const std::vector<Pose2>& path, double spacing, const Pose2& goal) {
  if (path.empty()) return {goal};
  const double length = PathLength(path);
  const double wanted = spacing > 0.0 ? std::ceil(length / spacing - 1e-9) : 1.0;
  // One stop per spacing: a spacing far under a step is a typo (1e-9 m asked for 12 GB).
  constexpr double kMaxControlPoints = 1e5;
  if (wanted > kMaxControlPoints) {
    throw std::invalid_argument("planner.control_point_spacing " + config_detail::ShortNumber(spacing) + " m puts " +
                                config_detail::ShortNumber(wanted) + " control points on a " + config_detail::ShortNumber(length) +
                                " m path: more than " + config_detail::ShortNumber(kMaxControlPoints));
  }
  const int count = std::max(1, static_cast<int>(wanted));
  std::vector<Pose2> points{path.front()};
  size_t segment = 1;
  double segment_start = 0.0;  // arc length where `segment` begins [m]
  for (int k = 1; k < count; ++k) {
    const double s = length * k / count;
    double segment_length = (path[segment].Position() - path[segment - 1].Position()).norm();
    while (segment + 1 < path.size() && segment_start + segment_length <= s) {  // a corner: the leg ahead
      segment_start += segment_length;
      ++segment;
      segment_length = (path[segment].Position() - path[segment - 1].Position()).norm();
    }
    const Eigen::Vector2d from = path[segment - 1].Position(), d = path[segment].Position() - from;
    const Eigen::Vector2d p =
        from + d * std::clamp((s - segment_start) / std::max(segment_length, 1e-12), 0.0, 1.0);
    points.push_back({p.x(), p.y(), std::atan2(d.y(), d.x())});
  }
  points.push_back(goal);
  return points;
}

double SegmentSlack(const OccupancyGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return grid.Empty() ? -1.0 : MinSlack(grid, a, b);
}

bool SegmentFree(const OccupancyGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return SegmentSlack(grid, a, b) >= 0.0;
}

}  // namespace planemap::nav
