#pragma once
// Looking again when the target is not in the map (beyond the paper, whose robot starts in view
// of its object). The paper's frontend needs three faces of a box to call it one; a box far away,
// or seen square-on, shows one face and a glancing top. That face is still in the map, as a plane
// landmark no object explains. The search walks to a viewpoint view_distance from such a face
// and view_angle_deg off its normal, where two sides and the top show, stands and looks again;
// the nearest candidate first, at most views_max viewpoints. A viewpoint stands on floor the map
// has seen (a floor point within explore_cell): the planner takes the floor's whole extent as
// free, and behind a shelf's front, say, is the shelf.
//
// A candidate face: vertical, at least candidate_min_observations frames, no taller (its top
// above the floor) than candidate_max_height, between candidate_min_width and candidate_max_width
// wide, not in the plane of a taller landmark it touches (a wall's bottom strip), and not a face
// of an object the map rules out (nav/target.h: classified as something other than the target
// or unknown with its height measured, a locker's door is no box, while two faces on the floor
// with their top unseen may be one; or measured at another size than the target's). Walls, furniture tops and the floor never are. The caller may add the latest frame's
// planes as landmarks: a face too far or too uncertain for the tracker to map (`planemap
// approach` does).
//
// Exploring, when no candidate face is left or views_max faces were looked at (a box hidden
// behind a shelf, or out of view): the next-best view over the floor the map holds. The floor's
// extent, on a grid of explore_cell, is seen where the floor landmark has points, blocked where
// the planner's grid keeps the robot off, unseen elsewhere. From where the robot stands and from
// viewpoints on seen floor within explore_max_walk (anywhere on it when none there is worth it),
// rays every 3 deg through unblocked cells find the unseen cells the camera's field of view would
// take in between explore_min_range and explore_max_range; the view whose heading takes in the
// most, less explore_walk_cost per metre walked, is walked to, if it brings explore_min_area or
// more into view. The search goes on until no view is left (the room is searched), at most
// explore_views_max views.
//
// Turning on the spot, when there is no view to walk to either (the robot faces a tall shelf that
// fills the image: no floor in the map, no face to look at): the robot turns turn_step_deg, stands
// look_time and looks, at most turns_max times. Turning in place sweeps no new floor, so it needs
// no plan; the tracker keeps the heading from the odometry meanwhile (tracking.lost_after_turn_deg).
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/plane_map.h"
#include "planemap/nav/grasp.h"
#include "planemap/nav/humanoid.h"
#include "planemap/nav/mission.h"
#include "planemap/nav/planner.h"
#include "planemap/nav/pose2.h"
#include "planemap/nav/target.h"

namespace planemap::nav {

struct SearchConfig {
  int views_max = 3;             // candidate faces walked to and looked at, at most [-]
  double view_distance = 0.7;    // viewpoint to the candidate face's centre [m]
  double view_angle_deg = 40.0;  // viewpoint off the face's normal, either side [deg]
  double look_time = 1.5;        // standing at a viewpoint, looking, before the next [s]
  // A candidate face's top above the floor, at most: below the camera (0.52 m), so a face that
  // only ends at the image's top edge (a pillar, a wall near by) is not taken for one that ends [m].
  double candidate_max_height = 0.48;
  double candidate_max_width = 0.60;               // its horizontal extent, at most ... [m]
  double candidate_min_width = 0.08;               // ... and at least: no chair leg [m]
  int candidate_min_observations = 3;              // frames that saw it, at least [-]
  // A mapped object of the target's class is a target once seen in this many frames (one view
  // of a wall 5 m away can make a "box") [-]
  int target_min_observations = 3;
  // A mapped object measured this far off the size the task gives (nav/target.h) is not the
  // target, nor are its faces candidates [m]
  double target_size_tolerance = 0.05;
  double candidate_vertical_tolerance_deg = 10.0;  // its normal this close to horizontal [deg]
  // A face in the plane of a taller landmark it touches (normals this close, its centroid this
  // near that plane) is a strip of a wall, not a candidate [deg, m]
  double coplanar_angle_deg = 5.0;
  double coplanar_distance = 0.05;
  double visited_radius = 0.40;  // a face this close to one looked at already is skipped [m]
  bool explore = true;           // with no candidate face left, look where the floor is unseen
  double explore_cell = 0.10;       // grid cell of seen and unseen floor [m]
  double explore_fov_deg = 58.0;    // the camera's horizontal field of view (Xtion: 58) [deg]
  double explore_min_range = 0.6;   // floor nearer is below the pitched camera's view [m]
  double explore_max_range = 3.0;   // floor farther is too far to map a box on (see the corridor) [m]
  double explore_max_walk = 3.0;    // viewpoints within this of the robot [m]
  double explore_min_area = 0.3;    // a view bringing less unseen floor into view is not walked to [m^2]
  double explore_walk_cost = 0.5;   // unseen floor a metre of walking must bring into view [m^2/m]
  int explore_views_max = 12;       // exploring views walked to, at most: a bound, the room is
                                    // searched when no view brings explore_min_area into view [-]
  // With no view left to walk to: turn on the spot by this much (counterclockwise) ... [deg]
  double turn_step_deg = 45.0;
  int turns_max = 7;                // ... at most this many times [-]

  template <class V>
  void VisitFields(V&& v) {
    v("views_max", views_max, Check::kNonNegative);
    v("view_distance", view_distance, Check::kPositive);
    v("view_angle_deg", view_angle_deg, Check::kNonNegative);
    v("look_time", look_time, Check::kNonNegative);
    v("candidate_max_height", candidate_max_height, Check::kPositive);
    v("candidate_max_width", candidate_max_width, Check::kPositive);
    v("candidate_min_width", candidate_min_width, Check::kNonNegative);
    v("candidate_min_observations", candidate_min_observations, Check::kNonNegative);
    v("target_min_observations", target_min_observations, Check::kPositive);
    v("target_size_tolerance", target_size_tolerance, Check::kPositive);
    v("candidate_vertical_tolerance_deg", candidate_vertical_tolerance_deg, Check::kNonNegative);
    v("coplanar_angle_deg", coplanar_angle_deg, Check::kNonNegative);
    v("coplanar_distance", coplanar_distance, Check::kNonNegative);
    v("visited_radius", visited_radius, Check::kNonNegative);
    v("explore", explore);
    v("explore_cell", explore_cell, Check::kPositive);
    v("explore_fov_deg", explore_fov_deg, Check::kPositive);
    v("explore_min_range", explore_min_range, Check::kNonNegative);
    v("explore_max_range", explore_max_range, Check::kPositive);
    v("explore_max_walk", explore_max_walk, Check::kPositive);
    v("explore_min_area", explore_min_area, Check::kNonNegative);
    v("explore_walk_cost", explore_walk_cost, Check::kNonNegative);
    v("explore_views_max", explore_views_max, Check::kNonNegative);
    v("turn_step_deg", turn_step_deg, Check::kPositive);
    v("turns_max", turns_max, Check::kNonNegative);
  }
};

// A face that may be the target's, seen too poorly to make an object of.
struct SearchCandidate {
  int landmark = -1;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();   // its extent's centre on the floor (world) [m]
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();  // unit, toward the cameras that saw it
  double distance = 0.0;                              // from the robot [m]
};

// The map's candidate faces for the target, nearest to `robot` first.
std::vector<SearchCandidate> SearchCandidates(const PlaneMap& map, const Pose2& robot,
                                              const SearchConfig& config, const TargetDescription& target);

// A view to explore from: where to stand and look, and how much floor not seen yet it takes in.
struct ExploreView {
  Pose2 pose;
  double unseen_area = 0.0;  // [m^2]
};

// The views worth walking to (bringing explore_min_area or more into view), best first; none
// when the map has no floor. `planner` sets where the robot may stand and what blocks a ray.
std::vector<ExploreView> ExploreViews(const PlaneMap& map, const Pose2& robot, const SearchConfig& config,
                                      const PlannerConfig& planner);

struct Viewpoint {
  Pose2 pose;  // where the robot stands, facing the face's centre (world); turning: the heading turned to
  SearchCandidate candidate;  // landmark -1: an exploring view or a turn
  double unseen_area = 0.0;   // exploring: the floor not seen yet it was chosen for [m^2]
  bool turn = false;          // turning on the spot (no walk)
  bool Explores() const { return candidate.landmark < 0 && !turn; }
  bool Faces() const { return candidate.landmark >= 0; }
};

class Search {
 public:
  // `robot` must outlive the search. Throws std::invalid_argument on an invalid config.
  Search(const SearchConfig& config, const MissionConfig& mission, const PlannerConfig& planner,
         const GraspConfig& grasp, Humanoid* robot);
  ~Search();

  // Plans the walk to the next viewpoint: the nearest candidate not looked at yet, from whichever
  // side is free and nearer; with none left, the best exploring view (config.explore); with none
  // of those, a turn on the spot (config.turns_max). False, with the reason, when none is left or
  // views_max walks are used.
  bool Next(const PlaneMap& map, const Pose2& estimate, const TargetDescription& target, std::string* reason);
  // Every camera frame while Walking(): drives the walk with path feedback, or waits for the
  // turn to end and the robot to settle. `map`: the current map, for obstacles seen on the way
  // (Mission::Update).
  void Update(double time, const std::optional<Pose2>& estimate, const PlaneMap* map = nullptr);
  bool Walking() const;
  // How the last walk or turn ended (kReached: standing at the viewpoint, or turned).
  MissionStatus Status() const;
  // The last walk stopped short for want of a way on (Mission::Blocked): its viewpoint, or the way
  // there, turned out blocked by an obstacle seen on the way (Mission::Update). The view is given
  // up; the robot looks from where it stands and the search goes on.
  bool GaveUpView() const;
  const std::vector<Viewpoint>& Viewpoints() const;
  const SearchConfig& Config() const;

 private:
  SearchConfig config_;
  PlannerConfig planner_;
  double settle_time_;  // mission.settle_time [s]
  Humanoid* robot_;
  Mission walk_;
  std::vector<Viewpoint> viewpoints_;
  int turns_ = 0;                        // of viewpoints_, the turns on the spot
  bool turning_ = false;                 // a turn commanded and not yet settled
  std::optional<double> turn_still_since_;  // [s]
};

}  // namespace planemap::nav
