#include "planemap/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include <opencv2/aruco.hpp>

#include "planemap/core/config.h"
#include "planemap/core/error.h"

namespace planemap::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

struct FloorSpec {
  std::vector<double> center{0.0, 0.0};  // [m]
  std::vector<double> size{10.0, 10.0};  // [m]
  std::vector<double> color{150, 150, 140};
  template <class V>
  void VisitFields(V&& v) {
    v("center", center);
    v("size", size, Check::kPositive);
    v("color", color, Check::kNonNegative);
  }
};

// What the robot in the scene is sent to fetch (the approach): one of its objects, by name.
struct TaskSpec {
  std::string object;
  template <class V>
  void VisitFields(V&& v) {
    v("object", object);
  }
};

struct WallSpec {
  std::string name;
  std::vector<double> from, to;  // end points on the floor [m]
  double height = 2.5;           // [m]
  std::vector<double> color{215, 210, 200};
  template <class V>
  void VisitFields(V&& v) {
    v("name", name);
    v("from", from);
    v("to", to);
    v("height", height, Check::kPositive);
    v("color", color, Check::kNonNegative);
  }
};

struct FaceColorSpec {
  std::array<std::vector<double>, 6> colors;  // kFaceNames order; empty = the object's colour
  template <class V>
  void VisitFields(V&& v) {
    for (size_t i = 0; i < 6; ++i) v(kFaceNames[i], colors[i], Check::kNonNegative);
  }
};

// One box of a `furniture` object, placed in the object's frame.
struct PartSpec {
  std::string name;
  std::vector<double> position{0.0, 0.0, 0.0};  // box centre in the object frame [m]
  std::vector<double> rpy_deg{0.0, 0.0, 0.0};   // orientation in the object frame [deg]
  std::vector<double> dimensions;               // [m]
  std::vector<double> color;                    // empty: the object's colour
  template <class V>
  void VisitFields(V&& v) {
    v("name", name);
    v("position", position);
    v("rpy_deg", rpy_deg);
    v("dimensions", dimensions, Check::kPositive);
    v("color", color, Check::kNonNegative);
  }
};

struct ObjectSpec {
  std::string name;
  std::string type = "box";                  // box | locker | open_locker | furniture
  std::vector<double> position;              // centre of the bounding box [m]
  std::vector<double> rpy_deg{0.0, 0.0, 0.0};  // orientation [deg]
  std::vector<double> dimensions;            // along object x (depth), y (width), z (height) [m];
                                             // furniture: derived from its parts
  std::vector<double> color{180, 140, 90};
  FaceColorSpec face_colors;
  double panel_thickness = 0.02;             // open_locker panels [m]
  std::vector<PartSpec> parts;               // furniture: its boxes
  template <class V>
  void VisitFields(V&& v) {
    v("name", name);
    v("type", type);
    v("position", position);
    v("rpy_deg", rpy_deg);
    v("dimensions", dimensions, Check::kPositive);
    v("color", color, Check::kNonNegative);
    v("face_colors", face_colors);
    v("panel_thickness", panel_thickness, Check::kPositive);
    v("parts", parts);
  }
};

struct MarkerSpec {
  int id = 0;
  std::string dictionary = "DICT_4X4_50";
  double size = 0.15;                       // [m]
  std::string on = "floor";                 // "floor" or an object name
  std::string part;                         // for multi-box objects
  std::string face = "+z";                  // for objects
  std::vector<double> position{0.0, 0.0};   // floor: x y [m]; face: offset from its centre [m]
  double rotation_deg = 0.0;                // about the surface normal [deg]
  template <class V>
  void VisitFields(V&& v) {
    v("id", id, Check::kNonNegative);
    v("dictionary", dictionary);
    v("size", size, Check::kPositive);
    v("on", on);
    v("part", part);
    v("face", face);
    v("position", position);
    v("rotation_deg", rotation_deg);
  }
};

// Reads list item `index` of `list` into a spec, rejecting unknown keys.
template <typename Spec>
Spec ReadItem(const YAML::Node& item, const std::string& file, const std::string& prefix) {
  if (!item.IsMap()) ThrowInputError(file, config_detail::LineOf(item), prefix + " must be a map");
  Spec spec;
  ConfigReader reader(item, file, prefix + ".");
  spec.VisitFields(reader);
  reader.RejectUnknownKeys();
  return spec;
}

Eigen::Vector3d Vec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

Pose3 Offset(const Eigen::Vector3d& t) {
  Pose3 T = Pose3::Identity();
  T.translation() = t;
  return T;
}

Rgb8 Color(const std::vector<double>& c) {
  auto clamp = [](double x) { return static_cast<std::uint8_t>(std::min(255.0, std::max(0.0, x))); };
  return {clamp(c[0]), clamp(c[1]), clamp(c[2])};
}

class SceneBuilder {
 public:
  SceneBuilder(Scene* scene, std::string file) : scene_(scene), file_(std::move(file)) {}

  void AddFloor(const FloorSpec& spec, int line) {
    RequireSize(spec.center, 2, "floor.center", line);
    RequireSize(spec.size, 2, "floor.size", line);
    RequireSize(spec.color, 3, "floor.color", line);
    Surface s;
    s.object = "floor";
    s.center_world = {spec.center[0], spec.center[1], 0.0};
    s.axis_u = Eigen::Vector3d::UnitX();
    s.axis_v = Eigen::Vector3d::UnitY();
    s.half_u = spec.size[0] / 2;
    s.half_v = spec.size[1] / 2;
    s.color = Color(spec.color);
    scene_->flat_surfaces.push_back(AddSurface(s) - 1);
  }

  void AddWall(const WallSpec& spec, int line, const std::string& where) {
    RequireSize(spec.from, 2, where + ".from", line);
    RequireSize(spec.to, 2, where + ".to", line);
    RequireSize(spec.color, 3, where + ".color", line);
    const Eigen::Vector3d a(spec.from[0], spec.from[1], 0.0), b(spec.to[0], spec.to[1], 0.0);
    if ((b - a).norm() < 1e-6) ThrowInputError(file_, line, where + ": 'from' and 'to' coincide");
    Surface s;
    s.object = spec.name.empty() ? where : spec.name;
    s.center_world = 0.5 * (a + b) + Eigen::Vector3d(0, 0, spec.height / 2);
    // u = up, v = along the wall, so n = u x v points to the left of from -> to: list walls
    // counter-clockwise around the room and their normals face into it.
    s.axis_u = Eigen::Vector3d::UnitZ();
    s.axis_v = (b - a).normalized();
    s.half_u = spec.height / 2;
    s.half_v = (b - a).norm() / 2;
    s.color = Color(spec.color);
    scene_->flat_surfaces.push_back(AddSurface(s) - 1);
  }

  void AddObject(const ObjectSpec& spec, int line, const std::string& where) {
    if (spec.name.empty()) ThrowInputError(file_, line, where + ": an object needs a 'name'");
    if (!names_.insert(spec.name).second) ThrowInputError(file_, line, where + ": duplicate name '" + spec.name + "'");
    RequireSize(spec.position, 3, where + ".position", line);
    RequireSize(spec.rpy_deg, 3, where + ".rpy_deg", line);
    RequireSize(spec.color, 3, where + ".color", line);
    if (spec.type == "furniture") {
      AddFurniture(spec, line, where);
      return;
    }
    if (!spec.parts.empty()) ThrowInputError(file_, line, where + ": only furniture has 'parts'");
    RequireSize(spec.dimensions, 3, where + ".dimensions", line);
    SceneObject object;
    object.name = spec.name;
    object.type = spec.type;
    object.T_world_object = MakePoseRpy(spec.rpy_deg[0] * kDegToRad, spec.rpy_deg[1] * kDegToRad,
                                        spec.rpy_deg[2] * kDegToRad, Vec3(spec.position));
    object.dimensions = Vec3(spec.dimensions);
    const Eigen::Vector3d& dim = object.dimensions;
    if (spec.type == "box" || spec.type == "locker") {
      AddCuboid(&object, spec, "", Pose3::Identity(), dim);
    } else if (spec.type == "open_locker") {
      // Open at the front (+x): back, left (+y), right (-y) and top panels; the floor shows inside.
      const double t = spec.panel_thickness;
      if (2 * t >= dim.y() || t >= dim.x() || t >= dim.z()) {
        ThrowInputError(file_, line, where + ": panel_thickness " + std::to_string(t) + " m does not fit the dimensions");
      }
      AddCuboid(&object, spec, "back", Offset({-dim.x() / 2 + t / 2, 0, 0}), {t, dim.y(), dim.z()});
      AddCuboid(&object, spec, "left", Offset({t / 2, dim.y() / 2 - t / 2, 0}), {dim.x() - t, t, dim.z()});
      AddCuboid(&object, spec, "right", Offset({t / 2, -dim.y() / 2 + t / 2, 0}), {dim.x() - t, t, dim.z()});
      AddCuboid(&object, spec, "top", Offset({t / 2, 0, dim.z() / 2 - t / 2}), {dim.x() - t, dim.y() - 2 * t, t});
    } else {
      ThrowInputError(file_, line, where + ".type: unknown object type '" + spec.type +
                                       "' (known: box, locker, open_locker, furniture)");
    }
    scene_->objects.push_back(std::move(object));
  }

  void AddMarker(const MarkerSpec& spec, int line, const std::string& where);

 private:
  // Furniture: boxes placed in the object frame; its dimensions are their bounding box there.
  void AddFurniture(const ObjectSpec& spec, int line, const std::string& where) {
    if (spec.parts.empty()) ThrowInputError(file_, line, where + ": furniture needs 'parts'");
    if (!spec.dimensions.empty()) {
      ThrowInputError(file_, line, where + ": furniture takes its dimensions from its parts; remove 'dimensions'");
    }
    SceneObject object;
    object.name = spec.name;
    object.type = spec.type;
    object.T_world_object = MakePoseRpy(spec.rpy_deg[0] * kDegToRad, spec.rpy_deg[1] * kDegToRad,
                                        spec.rpy_deg[2] * kDegToRad, Vec3(spec.position));
    Eigen::Vector3d low = Eigen::Vector3d::Constant(1e30), high = -low;
    std::set<std::string> part_names;
    for (size_t i = 0; i < spec.parts.size(); ++i) {
      const PartSpec& part = spec.parts[i];
      const std::string part_where = where + ".parts[" + std::to_string(i) + "]";
      RequireSize(part.position, 3, part_where + ".position", line);
      RequireSize(part.rpy_deg, 3, part_where + ".rpy_deg", line);
      RequireSize(part.dimensions, 3, part_where + ".dimensions", line);
      if (!part.color.empty()) RequireSize(part.color, 3, part_where + ".color", line);
      const std::string name = part.name.empty() ? "part" + std::to_string(i) : part.name;
      if (!part_names.insert(name).second) ThrowInputError(file_, line, part_where + ": duplicate part name '" + name + "'");
      const Pose3 T_object_part = MakePoseRpy(part.rpy_deg[0] * kDegToRad, part.rpy_deg[1] * kDegToRad,
                                              part.rpy_deg[2] * kDegToRad, Vec3(part.position));
      ObjectSpec colours = spec;
      if (!part.color.empty()) colours.color = part.color;
      AddCuboid(&object, colours, name, T_object_part, Vec3(part.dimensions));
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d corner((c & 1) ? 0.5 : -0.5, (c & 2) ? 0.5 : -0.5, (c & 4) ? 0.5 : -0.5);
        const Eigen::Vector3d p = T_object_part * corner.cwiseProduct(Vec3(part.dimensions));
        low = low.cwiseMin(p);
        high = high.cwiseMax(p);
      }
    }
    object.dimensions = high - low;
    object.bounds_center = 0.5 * (low + high);
    scene_->objects.push_back(std::move(object));
  }

  void RequireSize(const std::vector<double>& v, size_t n, const std::string& key, int line) const {
    if (v.size() != n) {
      ThrowInputError(file_, line, key + " needs " + std::to_string(n) + " numbers, got " + std::to_string(v.size()));
    }
  }

  // Appends a surface, deriving its plane; returns its label.
  std::uint16_t AddSurface(Surface s) {
    if (scene_->surfaces.size() >= 65535) ThrowInputError(file_, 0, "more than 65535 surfaces");
    s.label = static_cast<std::uint16_t>(scene_->surfaces.size() + 1);
    s.plane_world = Plane::FromPointNormal(s.center_world, s.axis_u.cross(s.axis_v));
    scene_->surfaces.push_back(s);
    return s.label;
  }

  void AddCuboid(SceneObject* object, const ObjectSpec& spec, const std::string& part,
                 const Pose3& T_object_box, const Eigen::Vector3d& dims) {
    Cuboid cuboid;
    cuboid.T_world_box = object->T_world_object * T_object_box;
    cuboid.dimensions = dims;
    const Eigen::Matrix3d R = cuboid.T_world_box.linear();
    for (int f = 0; f < 6; ++f) {
      const int axis = f / 2;
      const double sign = f % 2 == 0 ? 1.0 : -1.0;
      const Eigen::Vector3d n = sign * R.col(axis);
      Surface s;
      s.object = object->name;
      s.part = part;
      s.face = kFaceNames[f];
      s.center_world = cuboid.T_world_box.translation() + n * dims[axis] / 2;
      const int ua = (axis + 1) % 3, va = (axis + 2) % 3;  // u x v = +axis
      s.axis_u = R.col(ua);
      s.axis_v = sign * R.col(va);
      s.half_u = dims[ua] / 2;
      s.half_v = dims[va] / 2;
      const std::vector<double>& face_color = spec.face_colors.colors[f];
      s.color = Color(face_color.size() == 3 ? face_color : spec.color);
      cuboid.face_labels[f] = AddSurface(s);
    }
    object->cuboids.push_back(scene_->cuboids.size());
    scene_->cuboids.push_back(cuboid);
  }

  Scene* scene_;
  std::string file_;
  std::set<std::string> names_;
};

cv::aruco::PREDEFINED_DICTIONARY_NAME DictionaryByName(const std::string& name, bool* ok) {
  static const std::pair<const char*, cv::aruco::PREDEFINED_DICTIONARY_NAME> kNames[] = {
      {"DICT_4X4_50", cv::aruco::DICT_4X4_50},     {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
      {"DICT_4X4_250", cv::aruco::DICT_4X4_250},   {"DICT_4X4_1000", cv::aruco::DICT_4X4_1000},
      {"DICT_5X5_50", cv::aruco::DICT_5X5_50},     {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
      {"DICT_5X5_250", cv::aruco::DICT_5X5_250},   {"DICT_5X5_1000", cv::aruco::DICT_5X5_1000},
      {"DICT_6X6_50", cv::aruco::DICT_6X6_50},     {"DICT_6X6_100", cv::aruco::DICT_6X6_100},
      {"DICT_6X6_250", cv::aruco::DICT_6X6_250},   {"DICT_6X6_1000", cv::aruco::DICT_6X6_1000},
      {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL}};
  for (const auto& [n, id] : kNames) {
    if (name == n) {
      *ok = true;
      return id;
    }
  }
  *ok = false;
  return cv::aruco::DICT_4X4_50;
}

void SceneBuilder::AddMarker(const MarkerSpec& spec, int line, const std::string& where) {
  bool known = false;
  const auto dictionary_id = DictionaryByName(spec.dictionary, &known);
  if (!known) ThrowInputError(file_, line, where + ".dictionary: unknown ArUco dictionary '" + spec.dictionary + "'");
  const cv::Ptr<cv::aruco::Dictionary> dictionary = cv::aruco::getPredefinedDictionary(dictionary_id);
  if (spec.id >= dictionary->bytesList.rows) {
    ThrowInputError(file_, line, where + ".id: " + std::to_string(spec.id) + " is not in " + spec.dictionary);
  }
  if (spec.position.size() != 2) ThrowInputError(file_, line, where + ".position needs 2 numbers");
  // Find the surface the marker is printed on.
  const Surface* surface = nullptr;
  for (const Surface& s : scene_->surfaces) {
    const bool match = spec.on == "floor" ? s.object == "floor"
                                          : s.object == spec.on && s.part == spec.part && s.face == spec.face;
    if (match) surface = &s;
  }
  if (surface == nullptr) {
    ThrowInputError(file_, line, where + ": no surface '" + spec.on +
                                     (spec.on == "floor" ? "" : "' part '" + spec.part + "' face '" + spec.face) + "'");
  }
  Marker marker;
  marker.id = spec.id;
  marker.dictionary = spec.dictionary;
  marker.surface = surface->label;
  marker.size = spec.size;
  const double a = spec.rotation_deg * kDegToRad;
  marker.axis_u = std::cos(a) * surface->axis_u + std::sin(a) * surface->axis_v;
  // Image rows run opposite to the surface's v axis so the marker reads upright from the normal side.
  marker.axis_v = -(-std::sin(a) * surface->axis_u + std::cos(a) * surface->axis_v);
  if (spec.on == "floor") {
    marker.center_world = {spec.position[0], spec.position[1], 0.0};
  } else {
    marker.center_world = surface->center_world + spec.position[0] * surface->axis_u + spec.position[1] * surface->axis_v;
  }
  const int modules = dictionary->markerSize + 2;  // with a one-module black border
  cv::Mat bits;
  cv::aruco::drawMarker(dictionary, spec.id, modules, bits, 1);
  marker.bits = Image<std::uint8_t>(modules, modules);
  for (int v = 0; v < modules; ++v) {
    for (int u = 0; u < modules; ++u) marker.bits.at(u, v) = bits.at<std::uint8_t>(v, u);
  }
  scene_->markers.push_back(std::move(marker));
}

}  // namespace

const SceneObject& Scene::object(const std::string& name) const {
  for (const SceneObject& o : objects) {
    if (o.name == name) return o;
  }
  throw std::out_of_range("scene '" + this->name + "' has no object '" + name + "'");
}

Scene LoadScene(const std::string& file) { return ParseScene(LoadYamlFile(file), file); }

Scene ParseScene(const YAML::Node& root, const std::string& file) {
  if (!root.IsMap()) ThrowInputError(file, config_detail::LineOf(root), "a scene file must be a map");
  ConfigReader reader(root, file);
  Scene scene;
  FloorSpec floor;
  reader("name", scene.name);
  reader("floor", floor);
  TaskSpec task;
  reader("task", task);
  const YAML::Node walls = reader.TakeList("walls");
  const YAML::Node objects = reader.TakeList("objects");
  const YAML::Node markers = reader.TakeList("markers");
  reader.RejectUnknownKeys();

  SceneBuilder builder(&scene, file);
  builder.AddFloor(floor, config_detail::LineOf(root["floor"]));
  for (size_t i = 0; walls && i < walls.size(); ++i) {
    const std::string where = "walls[" + std::to_string(i) + "]";
    builder.AddWall(ReadItem<WallSpec>(walls[i], file, where), config_detail::LineOf(walls[i]), where);
  }
  for (size_t i = 0; objects && i < objects.size(); ++i) {
    const std::string where = "objects[" + std::to_string(i) + "]";
    builder.AddObject(ReadItem<ObjectSpec>(objects[i], file, where), config_detail::LineOf(objects[i]), where);
  }
  for (size_t i = 0; markers && i < markers.size(); ++i) {
    const std::string where = "markers[" + std::to_string(i) + "]";
    builder.AddMarker(ReadItem<MarkerSpec>(markers[i], file, where), config_detail::LineOf(markers[i]), where);
  }
  if (!task.object.empty()) {
    const auto named = [&](const SceneObject& o) { return o.name == task.object; };
    const auto it = std::find_if(scene.objects.begin(), scene.objects.end(), named);
    if (it == scene.objects.end())
      ThrowInputError(file, config_detail::LineOf(root["task"]), "task.object: no object named '" + task.object + "'");
    if (it->type != "box")
      ThrowInputError(file, config_detail::LineOf(root["task"]),
                      "task.object: '" + task.object + "' is a " + it->type + "; the robot is sent for a box");
    scene.task_object = task.object;
  }
  return scene;
}

}  // namespace planemap::sim

namespace planemap::sim {
namespace {

YAML::Node Vector(const Eigen::VectorXd& v) {
  YAML::Node node(YAML::NodeType::Sequence);
  for (Eigen::Index i = 0; i < v.size(); ++i) node.push_back(v[i]);
  node.SetStyle(YAML::EmitterStyle::Flow);
  return node;
}

}  // namespace

std::vector<ObjectTruth> ObjectTruths(const Scene& scene) {
  std::vector<ObjectTruth> truths;
  for (const SceneObject& o : scene.objects) truths.push_back({o.name, o.type, o.T_world_object, o.dimensions});
  return truths;
}

YAML::Node SceneGroundTruth(const Scene& scene) {
  YAML::Node root;
  root["scene"] = scene.name;
  for (const SceneObject& o : scene.objects) {
    YAML::Node node;
    node["name"] = o.name;
    node["type"] = o.type;
    node["position"] = Vector(o.T_world_object.translation());
    const Eigen::Quaterniond q(o.T_world_object.linear());
    node["quaternion_xyzw"] = Vector(Eigen::Vector4d(q.x(), q.y(), q.z(), q.w()));
    node["dimensions"] = Vector(o.dimensions);
    root["objects"].push_back(node);
  }
  for (const Surface& s : scene.surfaces) {
    YAML::Node node;
    node["label"] = s.label;
    node["object"] = s.object;
    if (!s.part.empty()) node["part"] = s.part;
    if (!s.face.empty()) node["face"] = s.face;
    node["normal"] = Vector(s.plane_world.normal);
    node["offset"] = s.plane_world.offset;
    node["center"] = Vector(s.center_world);
    node["half_extents"] = Vector(Eigen::Vector2d(s.half_u, s.half_v));
    root["surfaces"].push_back(node);
  }
  return root;
}

}  // namespace planemap::sim
