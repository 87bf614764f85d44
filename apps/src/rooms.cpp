// Generated rooms for the approach: a seeded generator of scene files and the reach check.
#include "planemap/apps/rooms.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>

#include "planemap/core/error.h"
#include "planemap/core/plane_map.h"
#include "planemap/sim/scene.h"

namespace planemap {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A thing's footprint on the floor while rooms are laid out: centre, yaw, half extents.
struct Rect {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double yaw = 0.0;
  Eigen::Vector2d half = Eigen::Vector2d::Zero();

  Eigen::Matrix2d Axes() const {
    Eigen::Matrix2d a;
    a << std::cos(yaw), -std::sin(yaw), std::sin(yaw), std::cos(yaw);
    return a;
  }
  nav::Footprint Footprint() const { return {center, Axes(), half}; }
  std::array<Eigen::Vector2d, 4> Corners() const {
    const Eigen::Matrix2d a = Axes();
    std::array<Eigen::Vector2d, 4> c;
    int k = 0;
    for (double su : {-1.0, 1.0}) {
      for (double sv : {-1.0, 1.0}) c[k++] = center + a.col(0) * su * half.x() + a.col(1) * sv * half.y();
    }
    return c;
  }
};

// The least distance between two rectangles, 0 where they overlap [m]: their outlines sampled
// every centimetre against the other's exact footprint.
double Gap(const Rect& a, const Rect& b) {
  const nav::Footprint fa = a.Footprint(), fb = b.Footprint();
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [r, other] : {std::pair{&a, &fb}, std::pair{&b, &fa}}) {
    const std::array<Eigen::Vector2d, 4> c = r->Corners();
    const int order[] = {0, 1, 3, 2, 0};
    for (int e = 0; e < 4; ++e) {
      const Eigen::Vector2d p = c[order[e]], q = c[order[e + 1]];
      const int n = std::max(1, static_cast<int>(std::ceil((q - p).norm() / 0.01)));
      for (int k = 0; k <= n; ++k) best = std::min(best, other->Distance(p + (q - p) * k / n));
    }
  }
  if (fa.Distance(b.center) == 0.0 || fb.Distance(a.center) == 0.0) return 0.0;
  return best;
}

// Uniform draws from a 64-bit Mersenne twister, the same on every platform.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double Uniform(double low, double high) { return low + (high - low) * ((engine_() >> 11) * 0x1.0p-53); }
  int Integer(int low, int high) { return low + static_cast<int>(engine_() % static_cast<std::uint64_t>(high - low + 1)); }
  bool Chance(double p) { return Uniform(0.0, 1.0) < p; }

 private:
  std::mt19937_64 engine_;
};

std::uint64_t Mix(std::uint64_t x) {  // SplitMix64's finaliser
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// A number as a scene file writes it: millimetres.
YAML::Node Num(double x) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3f", std::abs(x) < 5e-4 ? 0.0 : x);
  return YAML::Node(std::string(text));
}
YAML::Node Flow(std::initializer_list<double> values) {
  YAML::Node n;
  for (double v : values) n.push_back(Num(v));
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}
YAML::Node Color(Random& random, int low, int high) {
  YAML::Node n;
  for (int k = 0; k < 3; ++k) n.push_back(random.Integer(low, high));
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

// The room: x in [x0, x1], y in [y0, y1]; the start at the origin.
struct Room {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  // The least distance from the rectangle's corners to a wall, negative when outside [m].
  double WallMargin(const Rect& r) const {
    double m = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector2d& c : r.Corners()) {
      m = std::min({m, c.x() - x0, x1 - c.x(), c.y() - y0, y1 - c.y()});
    }
    return m;
  }
  // Wall w (0 south y = y0, 1 east x = x1, 2 north y = y1, 3 west x = x0): a point along it at
  // fraction u, and its inward normal.
  Eigen::Vector2d WallPoint(int w, double u) const {
    switch (w) {
      case 0: return {x0 + u * (x1 - x0), y0};
      case 1: return {x1, y0 + u * (y1 - y0)};
      case 2: return {x1 - u * (x1 - x0), y1};
      default: return {x0, y1 - u * (y1 - y0)};
    }
  }
  static Eigen::Vector2d Inward(int w) {
    const Eigen::Vector2d n[] = {{0, 1}, {-1, 0}, {0, -1}, {1, 0}};
    return n[w];
  }
};

double Yaw(const Eigen::Vector2d& direction) { return std::atan2(direction.y(), direction.x()); }

// One thing placed in the room: its footprint and its scene-file entry.
struct Thing {
  Rect rect;
  YAML::Node node;
  std::string kind;
};

YAML::Node Part(const std::string& name, std::initializer_list<double> position, std::initializer_list<double> dimensions) {
  YAML::Node p;
  p["name"] = name;
  p["position"] = Flow(position);
  p["dimensions"] = Flow(dimensions);
  p.SetStyle(YAML::EmitterStyle::Flow);
  return p;
}

YAML::Node ObjectNode(const std::string& name, const std::string& type, const Eigen::Vector3d& position, double yaw) {
  YAML::Node o;
  o["name"] = name;
  o["type"] = type;
  o["position"] = Flow({position.x(), position.y(), position.z()});
  o["rpy_deg"] = Flow({0.0, 0.0, std::remainder(yaw / kDeg, 360.0)});
  return o;
}

// A box (the target or another) of dimensions d, yaw, standing on the floor.
Thing BoxThing(Random& random, const std::string& name, const Eigen::Vector2d& center, double yaw, const Eigen::Vector3d& d) {
  Thing t;
  t.kind = "box";
  t.rect = {center, yaw, 0.5 * d.head<2>()};
  t.node = ObjectNode(name, "box", {center.x(), center.y(), 0.5 * d.z()}, yaw);
  t.node["dimensions"] = Flow({d.x(), d.y(), d.z()});
  // Cardboard: one hue, each face a little lighter or darker (lit differently in a real room).
  const int r = random.Integer(140, 215), g = random.Integer(100, 175), b = random.Integer(50, 130);
  YAML::Node faces;
  for (const char* face : sim::kFaceNames) {
    if (std::string(face) == "-z") continue;
    const int shade = random.Integer(-20, 20);
    YAML::Node c;
    for (int v : {r + shade, g + shade, b + shade}) c.push_back(std::clamp(v, 0, 255));
    c.SetStyle(YAML::EmitterStyle::Flow);
    faces[face] = c;
  }
  t.node["face_colors"] = faces;
  YAML::Node color;
  for (int v : {r, g, b}) color.push_back(v);
  color.SetStyle(YAML::EmitterStyle::Flow);
  t.node["color"] = color;
  return t;
}

// Furniture of the given kind centred at `center`, its front (+x) along yaw.
Thing FurnitureThing(Random& random, const std::string& kind, const std::string& name, const Eigen::Vector2d& center,
                     double yaw) {
  Thing t;
  t.kind = kind;
  if (kind == "locker") {
    const Eigen::Vector3d d(random.Uniform(0.45, 0.6), random.Uniform(0.6, 1.0), random.Uniform(1.6, 2.0));
    t.rect = {center, yaw, 0.5 * d.head<2>()};
    t.node = ObjectNode(name, "locker", {center.x(), center.y(), 0.5 * d.z()}, yaw);
    t.node["dimensions"] = Flow({d.x(), d.y(), d.z()});
    t.node["color"] = Color(random, 80, 170);
    return t;
  }
  t.node = ObjectNode(name, "furniture", {center.x(), center.y(), 0.0}, yaw);
  t.node["color"] = Color(random, 110, 200);
  YAML::Node parts;
  if (kind == "bench") {  // a seat on two slab legs
    const double l = random.Uniform(0.9, 1.5), w = random.Uniform(0.3, 0.45), h = random.Uniform(0.35, 0.48);
    t.rect = {center, yaw, {0.5 * w, 0.5 * l}};
    parts.push_back(Part("seat", {0.0, 0.0, h - 0.02}, {w, l, 0.04}));
    parts.push_back(Part("leg_left", {0.0, 0.5 * l - 0.03, 0.5 * (h - 0.04)}, {w, 0.04, h - 0.04}));
    parts.push_back(Part("leg_right", {0.0, -0.5 * l + 0.03, 0.5 * (h - 0.04)}, {w, 0.04, h - 0.04}));
  } else if (kind == "table") {  // a top on four legs, walked under
    const double l = random.Uniform(0.9, 1.4), w = random.Uniform(0.6, 0.8), h = random.Uniform(0.70, 0.76);
    t.rect = {center, yaw, {0.5 * w, 0.5 * l}};
    parts.push_back(Part("top", {0.0, 0.0, h - 0.015}, {w, l, 0.03}));
    int k = 0;
    for (double sx : {-1.0, 1.0}) {
      for (double sy : {-1.0, 1.0}) {
        parts.push_back(Part("leg_" + std::to_string(k++), {sx * (0.5 * w - 0.05), sy * (0.5 * l - 0.05), 0.5 * (h - 0.03)},
                             {0.04, 0.04, h - 0.03}));
      }
    }
  } else {  // a shelf unit, open at the front (+x), its back against a wall
    const double l = random.Uniform(0.8, 1.2), w = random.Uniform(0.3, 0.4), h = random.Uniform(1.0, 1.8);
    t.rect = {center, yaw, {0.5 * w, 0.5 * l}};
    parts.push_back(Part("left", {0.0, 0.5 * l - 0.01, 0.5 * h}, {w, 0.02, h}));
    parts.push_back(Part("right", {0.0, -0.5 * l + 0.01, 0.5 * h}, {w, 0.02, h}));
    parts.push_back(Part("back", {-0.5 * w + 0.01, 0.0, 0.5 * h}, {0.02, l - 0.04, h}));
    parts.push_back(Part("bottom", {0.01, 0.0, 0.06}, {w - 0.02, l - 0.04, 0.02}));
    parts.push_back(Part("middle", {0.01, 0.0, 0.5 * h}, {w - 0.02, l - 0.04, 0.02}));
    parts.push_back(Part("top", {0.01, 0.0, h - 0.01}, {w - 0.02, l - 0.04, 0.02}));
  }
  t.node["parts"] = parts;
  return t;
}

// Another box that the task's size tells apart from the target: one dimension, drawn at random,
// differs by distinct_size to 10 cm more, the others by up to 20%; at least min_height tall.
Eigen::Vector3d OtherBoxSize(Random& random, const Eigen::Vector3d& target, double distinct, double min_height) {
  const auto differs = [&](const Eigen::Vector3d& d) {
    const double a0 = std::min(target.x(), target.y()), a1 = std::max(target.x(), target.y());
    const double b0 = std::min(d.x(), d.y()), b1 = std::max(d.x(), d.y());
    return std::max({std::abs(a0 - b0), std::abs(a1 - b1), std::abs(target.z() - d.z())}) >= distinct;
  };
  Eigen::Vector3d d;
  for (int tries = 0; tries < 100; ++tries) {
    d = target.cwiseProduct(Eigen::Vector3d(random.Uniform(0.8, 1.2), random.Uniform(0.8, 1.2), random.Uniform(0.8, 1.2)));
    const int k = random.Integer(0, 2);
    const double change = distinct + random.Uniform(0.0, 0.1);
    d[k] = target[k] - change >= 0.12 && random.Chance(0.5) ? target[k] - change : target[k] + change;
    d.z() = std::max(d.z(), min_height);
    if (differs(d)) return d;
  }
  d.z() = std::max(target.z(), min_height) + distinct;  // taller: always told apart
  return d;
}

// Whether some side of a box of dimensions d the hands span has a standoff band at least
// `min_band` wide.
bool BoxGraspable(const Eigen::Vector3d& d, const nav::GraspConfig& grasp, double min_band) {
  MapObject o;
  o.dimensions = d;
  o.center = Eigen::Vector3d(0, 0, 0.5 * d.z());
  for (const Eigen::Vector2d& side : {Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1)}) {
    const nav::GraspGeometry faces = nav::GraspFaces(o, side);
    if (faces.width >= grasp.hand_span_min && faces.width <= grasp.hand_span_max &&
        nav::GraspBand(o, faces, grasp).Width() >= min_band)
      return true;
  }
  return false;
}

}  // namespace

RoomReach CheckRoomReach(const sim::Scene& scene, const nav::Pose2& start, const nav::PlannerConfig& planner,
                         const nav::GraspConfig& grasp, double body_height) {
  RoomReach reach;
  if (scene.task_object.empty()) {
    reach.reason = "the scene names no task object";
    return reach;
  }
  PlaneMap map;
  PlaneLandmark floor;
  floor.plane = Plane{Eigen::Vector3d::UnitZ(), 0.0};
  floor.floor_votes = 1;
  for (const sim::Surface& s : scene.surfaces) {
    if (s.object != "floor") continue;
    const Eigen::Vector3d e = (s.axis_u * s.half_u).cwiseAbs() + (s.axis_v * s.half_v).cwiseAbs();
    floor.low = s.center_world - e;
    floor.high = s.center_world + e;
  }
  map.landmarks.push_back(floor);
  const sim::SceneObject& target = scene.object(scene.task_object);
  MapObject goal;
  goal.label = target.type;
  goal.center = target.Center();
  goal.axes = target.T_world_object.linear();
  goal.dimensions = target.dimensions;
  map.objects.push_back(goal);
  for (const sim::SceneObject& o : scene.objects) {
    if (o.name == target.name) continue;
    for (size_t c : o.cuboids) {
      const sim::Cuboid& cuboid = scene.cuboids[c];
      const Eigen::Matrix3d r = cuboid.T_world_box.linear();
      const double bottom = cuboid.T_world_box.translation().z() - 0.5 * (r.cwiseAbs() * cuboid.dimensions).z();
      if (bottom >= body_height) continue;  // a table's top: walked under
      MapObject m;
      m.id = static_cast<int>(map.objects.size());
      m.center = cuboid.T_world_box.translation();
      m.center.z() = std::max(m.center.z(), 0.5 * (r.cwiseAbs() * cuboid.dimensions).z());  // in the planner's band
      m.axes = r;
      m.dimensions = cuboid.dimensions;
      map.objects.push_back(m);
    }
  }
  reach.reason = "no side of '" + target.name + "' the hands can span";
  const Eigen::Matrix3d axes = goal.axes;
  for (int k = 0; k < 2; ++k) {
    for (double sign : {1.0, -1.0}) {
      const Eigen::Vector2d side = sign * axes.col(k).head<2>().normalized();
      const nav::GraspGeometry faces = nav::GraspFaces(goal, side);
      if (faces.width < grasp.hand_span_min || faces.width > grasp.hand_span_max) continue;
      if (nav::GraspBand(goal, faces, grasp).Empty()) continue;
      const nav::Pose2 pre = nav::PreGraspPose(goal, grasp, side);
      if (!nav::CheckGrasp(goal, pre, grasp).ok) continue;
      const nav::OccupancyGrid grid = nav::BuildOccupancyGrid(map, planner, {0, pre}, start.Position());
      const nav::PlanResult plan = nav::PlanPath(grid, start, pre);
      if (!plan.ok) {
        if (!reach.ok) reach.reason = "no graspable side reached: " + plan.reason;
        continue;
      }
      if (!reach.ok || plan.length < reach.path_length) {
        reach.ok = true;
        reach.reason.clear();
        reach.pre_grasp = pre;
        reach.path_length = plan.length;
      }
    }
  }
  return reach;
}

GeneratedRoom GenerateRoom(const RoomGeneratorConfig& config, std::uint64_t seed, int index,
                           const nav::PlannerConfig& planner, const nav::GraspConfig& grasp, double body_height) {
  if (const std::string problem = config.CrossCheck(); !problem.empty()) throw InputError("rooms: " + problem);
  Random random(Mix(Mix(seed) ^ static_cast<std::uint64_t>(index)));
  const std::string name = "room_" + std::to_string(seed) + "_" + std::to_string(index);
  GeneratedRoom result;
  std::string last_reason = "no placement of the box";
  for (int attempt = 1; attempt <= config.max_attempts; ++attempt) {
    result.attempts = attempt;
    // The room around the start.
    const double lx = random.Uniform(config.room_size_min, config.room_size_max);
    const double ly = random.Uniform(config.room_size_min, config.room_size_max);
    const double sx = random.Uniform(config.start_wall_margin, lx - config.start_wall_margin);
    const double sy = random.Uniform(config.start_wall_margin, ly - config.start_wall_margin);
    const Room room{-sx, lx - sx, -sy, ly - sy};
    const Rect start_rect{{0.0, 0.0}, 0.0, {0.0, 0.0}};

    // The box: its size, then where it stands.
    Eigen::Vector3d d;
    do {
      const double narrow = random.Uniform(config.box_narrow_min, config.box_narrow_max);
      const double wide = narrow + random.Uniform(0.0, config.box_wide_extra_max);
      d = random.Chance(0.5) ? Eigen::Vector3d(narrow, wide, 0) : Eigen::Vector3d(wide, narrow, 0);
      d.z() = random.Uniform(config.box_height_min, config.box_height_max);
    } while (!BoxGraspable(d, grasp, config.box_min_band));
    const double mode = random.Uniform(0.0, 1.0);
    Rect box;
    std::string where;
    if (mode < config.near_wall_share + config.corner_share) {
      const bool corner = mode >= config.near_wall_share;
      const int w = random.Integer(0, 3);
      const double yaw = Yaw(Room::Inward(w)) + random.Uniform(-config.wall_yaw_max_deg, config.wall_yaw_max_deg) * kDeg;
      // Which of its sides faces the wall: either.
      const double turn = random.Chance(0.5) ? 0.0 : 0.5 * M_PI;
      box = {Eigen::Vector2d::Zero(), yaw + turn, 0.5 * d.head<2>()};
      const double depth = turn == 0.0 ? 0.5 * d.x() : 0.5 * d.y();
      const double across = turn == 0.0 ? 0.5 * d.y() : 0.5 * d.x();
      const double gap = random.Uniform(config.wall_gap_min, config.wall_gap_max);
      double u = random.Uniform(0.0, 1.0);
      const double length = (w % 2 == 0) ? room.x1 - room.x0 : room.y1 - room.y0;
      if (corner) {
        const double gap2 = random.Uniform(config.wall_gap_min, config.wall_gap_max);
        u = random.Chance(0.5) ? (gap2 + across) / length : 1.0 - (gap2 + across) / length;
      }
      box.center = room.WallPoint(w, u) + Room::Inward(w) * (gap + depth);
      where = corner ? "in a corner" : "by a wall";
      if (room.WallMargin(box) < 0.5 * config.wall_gap_min) {
        last_reason = "the box does not fit by the wall";
        continue;
      }
    } else {
      const double bearing = random.Uniform(-M_PI, M_PI);
      const double distance = random.Uniform(config.box_distance_min, config.box_distance_max);
      box = {distance * Eigen::Vector2d(std::cos(bearing), std::sin(bearing)), random.Uniform(-M_PI, M_PI), 0.5 * d.head<2>()};
      where = "free-standing";
      if (room.WallMargin(box) < config.free_wall_margin) {
        last_reason = "the box is too near a wall to stand free";
        continue;
      }
    }
    const double box_distance = box.center.norm();
    if (box_distance < config.box_distance_min || box_distance > config.box_distance_max) {
      last_reason = "the box is not within the distance range of the start";
      continue;
    }
    std::vector<Thing> things;
    things.push_back(BoxThing(random, "box", box.center, box.yaw, d));

    // The other things: the first may hide the box from the start.
    const int others = random.Integer(config.others_min, config.others_max);
    const bool hide = random.Chance(config.hide_share);
    bool placed_all = true;
    for (int k = 0; k < others && placed_all; ++k) {
      const bool hider = hide && k == 0;
      const char* kinds_hiding[] = {"crate", "carton", "bench"};
      const char* kinds[] = {"crate", "carton", "bench", "table", "shelf", "locker"};
      const std::string kind = hider ? kinds_hiding[random.Integer(0, 2)] : kinds[random.Integer(0, 5)];
      const std::string thing_name = kind + "_" + std::to_string(k + 1);
      bool placed = false;
      for (int tries = 0; tries < 50 && !placed; ++tries) {
        Thing t;
        if (hider) {  // on the line of sight, between a third and four fifths of the way
          const double f = random.Uniform(0.35, 0.8);
          const Eigen::Vector2d dir = box.center.normalized(), normal(-dir.y(), dir.x());
          const Eigen::Vector2d c = f * box.center + normal * random.Uniform(-0.15, 0.15);
          if (kind == "bench") {
            t = FurnitureThing(random, kind, thing_name, c, Yaw(dir) + random.Uniform(-20.0, 20.0) * kDeg);
          } else {
            const Eigen::Vector3d size = OtherBoxSize(random, d, config.distinct_size, 0.9 * d.z());
            t = BoxThing(random, thing_name, c, random.Uniform(-M_PI, M_PI), size);
          }
        } else if (kind == "shelf" || kind == "locker") {  // its back to a wall, facing the room
          const int w = random.Integer(0, 3);
          t = FurnitureThing(random, kind, thing_name, Eigen::Vector2d::Zero(), Yaw(Room::Inward(w)));
          t.rect.center = room.WallPoint(w, random.Uniform(0.1, 0.9)) + Room::Inward(w) * (t.rect.half.x() + 0.02);
          const Eigen::Vector3d p(t.rect.center.x(), t.rect.center.y(), t.node["position"][2].as<double>());
          t.node["position"] = Flow({p.x(), p.y(), p.z()});
        } else {
          const Eigen::Vector2d c(random.Uniform(room.x0, room.x1), random.Uniform(room.y0, room.y1));
          if (kind == "bench" || kind == "table") {
            t = FurnitureThing(random, kind, thing_name, c, random.Uniform(-M_PI, M_PI));
          } else {
            const Eigen::Vector3d size = OtherBoxSize(random, d, config.distinct_size, config.box_height_min);
            t = BoxThing(random, thing_name, c, random.Uniform(-M_PI, M_PI), size);
          }
        }
        t.kind = kind;
        if (room.WallMargin(t.rect) < 0.01) continue;
        if (Gap(t.rect, start_rect) < config.start_clearance) continue;
        bool apart = true;
        for (const Thing& other : things) apart = apart && Gap(t.rect, other.rect) >= config.object_gap;
        if (!apart) continue;
        things.push_back(std::move(t));
        placed = true;
      }
      placed_all = placed;
    }
    if (!placed_all) {
      last_reason = "the other things do not fit";
      continue;
    }

    // The scene file.
    YAML::Node scene;
    scene["name"] = name;
    YAML::Node task;
    task["object"] = "box";
    task.SetStyle(YAML::EmitterStyle::Flow);
    scene["task"] = task;
    scene["floor"]["center"] = Flow({0.5 * (room.x0 + room.x1), 0.5 * (room.y0 + room.y1)});
    scene["floor"]["size"] = Flow({room.x1 - room.x0, room.y1 - room.y0});
    scene["floor"]["color"] = Color(random, 120, 160);
    const char* wall_names[] = {"wall_south", "wall_east", "wall_north", "wall_west"};
    for (int w = 0; w < 4; ++w) {
      YAML::Node wall;
      wall["name"] = wall_names[w];
      const Eigen::Vector2d a = room.WallPoint(w, 0.0), b = room.WallPoint(w, 1.0);
      wall["from"] = Flow({a.x(), a.y()});
      wall["to"] = Flow({b.x(), b.y()});
      wall["height"] = Num(config.wall_height);
      wall["color"] = Color(random, 190, 230);
      wall.SetStyle(YAML::EmitterStyle::Flow);
      scene["walls"].push_back(wall);
    }
    std::string others_text;
    for (const Thing& t : things) {
      scene["objects"].push_back(t.node);
      if (&t != &things.front()) others_text += (others_text.empty() ? "" : ", ") + t.kind;
    }
    const sim::Scene parsed = sim::ParseScene(scene, name);
    result.reach = CheckRoomReach(parsed, {0.0, 0.0, 0.0}, planner, grasp, body_height);
    if (!result.reach.ok) {
      last_reason = "no reachable pre-grasp pose: " + result.reach.reason;
      continue;
    }
    char summary[512];
    std::snprintf(summary, sizeof(summary),
                  "%.1f x %.1f m; box %.0f x %.0f x %.0f cm %s %.1f m from the start at bearing %.0f deg; %s%s",
                  room.x1 - room.x0, room.y1 - room.y0, 100 * d.x(), 100 * d.y(), 100 * d.z(), where.c_str(), box_distance,
                  Yaw(box.center) / kDeg, others_text.c_str(), hide ? " (the first on the way to it)" : "");
    result.scene = scene;
    result.summary = summary;
    return result;
  }
  throw InputError("rooms: seed " + std::to_string(seed) + ", room " + std::to_string(index) + ": no room in " +
                   std::to_string(config.max_attempts) + " attempts (rooms.max_attempts); the last failed: " + last_reason);
}

}  // namespace planemap
