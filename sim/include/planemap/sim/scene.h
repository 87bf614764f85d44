#pragma once
// A plane-based world: a floor, walls and objects made of boxes, with ArUco markers as texture.
// Every visible rectangle (a wall, the floor, one face of one box) is a `Surface` with its own
// label, so a rendered label image says exactly which plane each pixel sees.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <yaml-cpp/yaml.h>

#include "planemap/core/image.h"
#include "planemap/core/plane.h"
#include "planemap/core/pose.h"

namespace planemap::sim {

// Box faces in the order +x, -x, +y, -y, +z, -z of the box frame.
inline constexpr std::array<const char*, 6> kFaceNames = {"+x", "-x", "+y", "-y", "+z", "-z"};

struct Surface {
  std::uint16_t label = 0;  // pixel value in label images; 1-based, 0 = no surface
  std::string object;       // "floor", a wall's name or an object's name
  std::string part;         // the box of a multi-box object ("back", "left", ...); else empty
  std::string face;         // one of kFaceNames for box faces; else empty
  Plane plane_world;        // normal points out of the solid (into the room for walls)
  Eigen::Vector3d center_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX();  // unit, in the plane
  Eigen::Vector3d axis_v = Eigen::Vector3d::UnitY();  // unit, in the plane, n = u x v
  double half_u = 0.0;                                // half extent along axis_u [m]
  double half_v = 0.0;                                // half extent along axis_v [m]
  Rgb8 color{200, 200, 200};
};

// One cuboid; objects are built from one (a box) or several (a locker's panels).
struct Cuboid {
  Pose3 T_world_box = Pose3::Identity();                  // box centre, axes along its edges
  Eigen::Vector3d dimensions = Eigen::Vector3d::Ones();   // edge lengths along box x, y, z [m]
  std::array<std::uint16_t, 6> face_labels{};             // Surface labels, kFaceNames order
};

struct SceneObject {
  std::string name;
  std::string type;                     // "box", "locker", "open_locker" or "furniture"
  // Centre of the bounding box, x = front normal; for furniture, the frame its parts are placed in.
  Pose3 T_world_object = Pose3::Identity();
  Eigen::Vector3d dimensions = Eigen::Vector3d::Ones();  // bounding box along object x, y, z [m]
  Eigen::Vector3d bounds_center = Eigen::Vector3d::Zero();  // its centre in the object frame: zero but for furniture [m]
  std::vector<size_t> cuboids;          // indices into Scene::cuboids

  // The bounding box's centre in the world [m].
  Eigen::Vector3d Center() const { return T_world_object * bounds_center; }
};

// A square ArUco marker printed on a surface.
struct Marker {
  int id = 0;
  std::string dictionary;               // e.g. "DICT_4X4_50"
  std::uint16_t surface = 0;            // label of the surface it is printed on
  Eigen::Vector3d center_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX();  // marker image x (columns) direction
  Eigen::Vector3d axis_v = Eigen::Vector3d::UnitY();  // marker image y (rows) direction
  double size = 0.1;                    // side length including the black border [m]
  Image<std::uint8_t> bits;             // one pixel per module, 0 black, 255 white
};

struct Scene {
  std::string name;
  std::vector<Surface> surfaces;        // surfaces[i].label == i + 1
  std::vector<Cuboid> cuboids;
  std::vector<size_t> flat_surfaces;    // floor and walls: rectangles not part of a cuboid
  std::vector<SceneObject> objects;
  std::vector<Marker> markers;
  // The object the robot is sent to fetch (`task: {object: NAME}`, a box), empty when the scene
  // names none: `planemap approach` then tells the robot its class and size, and scores the run
  // against it whatever the robot approached.
  std::string task_object;

  const Surface& surface(std::uint16_t label) const { return surfaces.at(label - 1); }
  // The object with this name; throws std::out_of_range if there is none.
  const SceneObject& object(const std::string& name) const;
};

// Loads a scene file (configs/scenes/*.yaml). Throws InputError naming the file, line and key
// for unknown keys, missing or non-positive dimensions, unknown object types or marker targets.
Scene LoadScene(const std::string& file);

// The same from a parsed scene file (e.g. one a study has changed); `file` names it in errors.
Scene ParseScene(const YAML::Node& root, const std::string& file);

}  // namespace planemap::sim

#include "planemap/core/object_eval.h"

namespace planemap::sim {

// The scene's exact geometry for evaluation: objects (pose, dimensions) and every surface
// (label, owner, plane n.x + d = 0 in the world, centre, half extents).
YAML::Node SceneGroundTruth(const Scene& scene);

// The scene's objects as evaluation truths (EvaluateObjects).
std::vector<ObjectTruth> ObjectTruths(const Scene& scene);

}  // namespace planemap::sim
