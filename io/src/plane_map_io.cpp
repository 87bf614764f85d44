#include "planemap/io/plane_map_io.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "planemap/core/error.h"

namespace planemap {
namespace {

using nlohmann::json;

json Vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

// Standard deviations as the back end estimated them; -1 (a dimension only bounded from below,
// no grasp axis) is written as null.
json Std(double x) { return x < 0.0 ? json(nullptr) : json(x); }
json UncertaintyJson(const MapObject::Uncertainty& u) {
  const auto upper = [](const Eigen::Matrix3d& C) { return json::array({C(0, 0), C(0, 1), C(0, 2), C(1, 1), C(1, 2), C(2, 2)}); };
  return {{"dimension_std", {Std(u.dimension_std.x()), Std(u.dimension_std.y()), Std(u.dimension_std.z())}},
          {"center_std", Vec(u.center_covariance.diagonal().cwiseMax(0.0).cwiseSqrt())},
          {"axes_std_deg", Vec(u.axes_std_deg)},
          {"grasp_axis_std_deg", Std(u.grasp_axis_std_deg)},
          {"dimension_covariance", upper(u.dimension_covariance)},
          {"center_covariance", upper(u.center_covariance)}};
}

// Voxel points to 0.1 mm: enough for a 5 cm voxel sample, and a third of the text.
double Round(float x) { return std::round(static_cast<double>(x) * 1e4) / 1e4; }

// Reads fields of one JSON node; every error names the file and the field's path.
class Node {
 public:
  Node(const json& node, const std::string& file, std::string where) : node_(node), file_(file), where_(std::move(where)) {}

  bool Has(const std::string& key) const { return node_.contains(key) && !node_[key].is_null(); }
  Node operator[](const std::string& key) const {
    if (!node_.contains(key)) Fail(key, "missing");
    return Node(node_[key], file_, Path(key));
  }
  Node operator[](size_t i) const { return Node(node_[i], file_, where_ + "[" + std::to_string(i) + "]"); }
  size_t Size() const { return node_.size(); }
  const json& raw() const { return node_; }

  // The list under `key` (absent: empty).
  std::vector<Node> List(const std::string& key) const {
    std::vector<Node> items;
    if (!Has(key)) return items;
    if (!node_[key].is_array()) Fail(key, "expected a list");
    for (size_t i = 0; i < node_[key].size(); ++i) items.emplace_back(node_[key][i], file_, Path(key) + "[" + std::to_string(i) + "]");
    return items;
  }
  double Number() const {
    if (!node_.is_number() || !std::isfinite(node_.get<double>())) Fail("", "expected a finite number, got " + node_.dump());
    return node_.get<double>();
  }
  int Int() const {
    if (!node_.is_number_integer()) Fail("", "expected an integer, got " + node_.dump());
    // get<int> wraps what does not fit (4294967296 read as 0): out of range is an error.
    const bool fits = node_.is_number_unsigned() ? node_.get<std::uint64_t>() <= std::numeric_limits<int>::max()
                                                 : node_.get<std::int64_t>() >= std::numeric_limits<int>::min() &&
                                                       node_.get<std::int64_t>() <= std::numeric_limits<int>::max();
    if (!fits) Fail("", "expected an integer that fits in 32 bits, got " + node_.dump());
    return node_.get<int>();
  }
  bool Bool() const {
    if (!node_.is_boolean()) Fail("", "expected true or false, got " + node_.dump());
    return node_.get<bool>();
  }
  std::string String() const {
    if (!node_.is_string()) Fail("", "expected a string, got " + node_.dump());
    return node_.get<std::string>();
  }
  // A list of n finite numbers.
  std::vector<double> Numbers(size_t n) const {
    bool ok = node_.is_array() && (n == 0 || node_.size() == n);
    for (size_t k = 0; ok && k < node_.size(); ++k) ok = node_[k].is_number() && std::isfinite(node_[k].get<double>());
    if (!ok) Fail("", "expected " + (n == 0 ? std::string("a list of") : std::to_string(n)) + " finite numbers, got " + Short());
    return node_.get<std::vector<double>>();
  }
  Eigen::Vector3d Vector() const {
    const std::vector<double> v = Numbers(3);
    return Eigen::Vector3d(v[0], v[1], v[2]);
  }
  [[noreturn]] void Fail(const std::string& key, const std::string& what) const {
    ThrowInputError(file_, 0, (key.empty() ? where_ : Path(key)) + ": " + what);
  }

 private:
  std::string Path(const std::string& key) const { return where_.empty() ? key : where_ + "." + key; }
  std::string Short() const {
    const std::string s = node_.dump();
    return s.size() > 60 ? s.substr(0, 57) + "..." : s;
  }
  const json& node_;
  const std::string& file_;
  std::string where_;
};

}  // namespace

std::string PlaneMapJson(const PlaneMap& map, int indent) {
  json j;
  j["frame"] = "world";
  j["units"] = "metres";
  j["planes"] = json::array();
  for (const PlaneLandmark& l : map.landmarks) {
    json points = json::array();
    for (const Eigen::Vector3f& p : l.points) points.insert(points.end(), {Round(p.x()), Round(p.y()), Round(p.z())});
    const Eigen::Matrix3d& S = l.moments.sum_outer;
    j["planes"].push_back({{"id", l.id},
                           {"normal", Vec(l.plane.normal)},
                           {"offset", l.plane.offset},
                           {"extent_low", Vec(l.low)},
                           {"extent_high", Vec(l.high)},
                           {"observations", l.observations},
                           {"floor_votes", l.floor_votes},
                           {"first_frame", l.first_frame},
                           {"last_frame", l.last_frame},
                           {"moments", {{"n", l.moments.n}, {"w", l.moments.w}, {"sum", Vec(l.moments.sum)},
                                        {"sum_outer", {S(0, 0), S(0, 1), S(0, 2), S(1, 1), S(1, 2), S(2, 2)}}}},
                           {"points_xyz", points}});
  }
  j["floor"] = map.Floor();
  j["edges"] = json::array();
  for (const MapEdge& e : map.edges) {
    j["edges"].push_back({{"planes", {e.landmark_a, e.landmark_b}}, {"start", Vec(e.start)}, {"end", Vec(e.end)},
                          {"length", e.length}, {"complete", e.complete}, {"observations", e.observations},
                          {"convex_views", e.convex_views}, {"concave_views", e.concave_views}});
  }
  j["objects"] = json::array();
  for (const MapObject& o : map.objects) {
    json labels = json::object(), grasp = json::array();
    for (const auto& [label, n] : o.label_votes) labels[label] = n;
    for (const auto& [landmark, n] : o.grasp_votes) grasp.push_back({landmark, n});
    json object = {{"id", o.id},
                   {"label", o.label},
                   {"planes", o.landmarks},
                   {"dimensions", Vec(o.dimensions)},
                   {"dimension_complete", {o.dimension_complete[0], o.dimension_complete[1], o.dimension_complete[2]}},
                   {"center", Vec(o.center)},
                   {"axes", {Vec(o.axes.col(0)), Vec(o.axes.col(1)), Vec(o.axes.col(2))}},
                   {"grasp_axis", o.has_grasp_axis ? Vec(o.grasp_axis) : json(nullptr)},
                   {"observations", o.observations},
                   {"structure", o.structure},
                   {"uncertainty", o.uncertainty.known ? UncertaintyJson(o.uncertainty) : json(nullptr)},
                   // What the estimates are made of, so a merge can go on averaging them.
                   {"evidence", {{"complete_count", o.complete_count},
                                 {"complete_sum", Vec(o.complete_sum)},
                                 {"center_count", o.center_count},
                                 {"center_sum", Vec(o.center_sum)},
                                 {"partial_center_count", o.partial_center_count},
                                 {"partial_center_sum", Vec(o.partial_center_sum)},
                                 {"label_votes", labels},
                                 {"grasp_votes", grasp},
                                 {"grasp_plane", o.grasp_landmark},
                                 {"x_plane", o.x_landmark}}}};
    j["objects"].push_back(object);
  }
  j["keyframes"] = json::array();
  for (const Keyframe& k : map.keyframes) {
    const Eigen::Quaterniond q(k.T_world_camera.linear());
    j["keyframes"].push_back({{"frame", k.frame}, {"stamp", k.stamp}, {"position", Vec(k.T_world_camera.translation())},
                              {"quaternion_xyzw", {q.x(), q.y(), q.z(), q.w()}}});
  }
  j["memory_bytes"] = map.MemoryBytes();
  return j.dump(indent);
}

PlaneMap ReadPlaneMapJson(const std::string& file) {
  std::ifstream in = OpenInputFile(file);
  json root;
  try {
    root = json::parse(in);
  } catch (const json::exception& e) {
    ThrowInputError(file, 0, std::string("not valid JSON: ") + e.what());
  }
  if (!root.is_object()) ThrowInputError(file, 0, "expected a map (a JSON object with planes, edges, objects)");
  const Node top(root, file, "");
  PlaneMap map;
  // Planes: the equation is required; the rest (written by planemap map) is optional.
  for (const Node& p : top.List("planes")) {
    PlaneLandmark l;
    l.id = static_cast<int>(map.landmarks.size());
    if (p.Has("id") && p["id"].Int() != l.id) p["id"].Fail("", "expected " + std::to_string(l.id) + ": planes are listed by id");
    l.plane.normal = p["normal"].Vector();
    if (std::abs(l.plane.normal.norm() - 1.0) > 1e-3) p["normal"].Fail("", "expected a unit vector");
    l.plane.normal.normalize();
    l.plane.offset = p["offset"].Number();
    if (p.Has("extent_low")) l.low = p["extent_low"].Vector();
    if (p.Has("extent_high")) l.high = p["extent_high"].Vector();
    if (p.Has("observations")) l.observations = p["observations"].Int();
    if (p.Has("floor_votes")) l.floor_votes = p["floor_votes"].Int();
    if (p.Has("first_frame")) l.first_frame = p["first_frame"].Int();
    if (p.Has("last_frame")) l.last_frame = p["last_frame"].Int();
    if (p.Has("moments")) {
      const Node m = p["moments"];
      l.moments.n = m["n"].Number();
      l.moments.w = m["w"].Number();
      l.moments.sum = m["sum"].Vector();
      const std::vector<double> s = m["sum_outer"].Numbers(6);
      l.moments.sum_outer << s[0], s[1], s[2], s[1], s[3], s[4], s[2], s[4], s[5];
      if (l.moments.w < 0.0) m["w"].Fail("", "expected a sum of weights >= 0");
    }
    if (p.Has("points_xyz")) {
      const std::vector<double> xyz = p["points_xyz"].Numbers(0);
      if (xyz.size() % 3 != 0) p["points_xyz"].Fail("", "expected x y z triples, got " + std::to_string(xyz.size()) + " numbers");
      for (size_t k = 0; k < xyz.size(); k += 3) l.points.emplace_back(xyz[k], xyz[k + 1], xyz[k + 2]);
    }
    map.landmarks.push_back(std::move(l));
  }
  const int planes = static_cast<int>(map.landmarks.size());
  const auto plane_id = [&](const Node& n) {
    const int id = n.Int();
    if (id < -1 || id >= planes) n.Fail("", "no plane " + std::to_string(id) + " (the map has " + std::to_string(planes) + ")");
    return id;
  };
  for (const Node& e : top.List("edges")) {
    MapEdge m;
    const Node ends = e["planes"];
    if (!ends.raw().is_array() || ends.Size() != 2) ends.Fail("", "expected two plane ids");
    m.landmark_a = plane_id(ends[0]);
    m.landmark_b = plane_id(ends[1]);
    if (m.landmark_a < 0 || m.landmark_b < 0 || m.landmark_a == m.landmark_b) ends.Fail("", "expected two different planes");
    if (m.landmark_a > m.landmark_b) std::swap(m.landmark_a, m.landmark_b);
    m.start = e["start"].Vector();
    m.end = e["end"].Vector();
    m.length = e.Has("length") ? e["length"].Number() : (m.end - m.start).norm();
    if (e.Has("complete")) m.complete = e["complete"].Bool();
    if (e.Has("observations")) m.observations = e["observations"].Int();
    if (e.Has("convex_views")) m.convex_views = e["convex_views"].Int();
    if (e.Has("concave_views")) m.concave_views = e["concave_views"].Int();
    map.edges.push_back(m);
  }
  for (const Node& o : top.List("objects")) {
    MapObject m;
    m.id = static_cast<int>(map.objects.size());
    m.label = o["label"].String();
    for (const Node& p : o.List("planes")) m.landmarks.push_back(plane_id(p));
    m.dimensions = o["dimensions"].Vector();
    if (m.dimensions.minCoeff() < 0.0) o["dimensions"].Fail("", "expected sizes >= 0 [m]");
    const Node complete = o["dimension_complete"];
    if (!complete.raw().is_array() || complete.Size() != 3) complete.Fail("", "expected 3 booleans, got " + complete.raw().dump());
    for (size_t k = 0; k < 3; ++k) m.dimension_complete[k] = complete[k].Bool();
    m.center = o["center"].Vector();
    const Node axes = o["axes"];
    if (!axes.raw().is_array() || axes.Size() != 3) axes.Fail("", "expected 3 vectors");
    for (size_t k = 0; k < 3; ++k) {
      m.axes.col(k) = axes[k].Vector();
      if (std::abs(m.axes.col(k).norm() - 1.0) > 1e-3) axes[k].Fail("", "expected a unit vector");
    }
    // A rotation's columns: |det| 1 only when the three are also mutually perpendicular.
    if (std::abs(std::abs(m.axes.determinant()) - 1.0) > 1e-3) axes.Fail("", "expected three perpendicular unit vectors");
    if (o.Has("grasp_axis")) {
      m.grasp_axis = o["grasp_axis"].Vector();
      if (std::abs(m.grasp_axis.norm() - 1.0) > 1e-3) o["grasp_axis"].Fail("", "expected a unit vector");
      m.has_grasp_axis = true;
    }
    if (o.Has("observations")) m.observations = o["observations"].Int();
    if (o.Has("structure")) m.structure = o["structure"].Bool();
    if (o.Has("uncertainty")) {
      const Node u = o["uncertainty"];
      MapObject::Uncertainty& x = m.uncertainty;
      x.known = true;
      const Node dims = u["dimension_std"];
      if (!dims.raw().is_array() || dims.Size() != 3) dims.Fail("", "expected 3 standard deviations (or null)");
      for (size_t k = 0; k < 3; ++k) x.dimension_std[k] = dims[k].raw().is_null() ? -1.0 : dims[k].Number();
      x.axes_std_deg = u["axes_std_deg"].Vector();
      x.grasp_axis_std_deg = u.Has("grasp_axis_std_deg") ? u["grasp_axis_std_deg"].Number() : -1.0;
      const auto symmetric = [](const Node& n) {
        const std::vector<double> c = n.Numbers(6);
        Eigen::Matrix3d C;
        C << c[0], c[1], c[2], c[1], c[3], c[4], c[2], c[4], c[5];
        return C;
      };
      x.dimension_covariance = symmetric(u["dimension_covariance"]);
      x.center_covariance = symmetric(u["center_covariance"]);
    }
    if (o.Has("evidence")) {
      const Node e = o["evidence"];
      // Counts as integers: a number beyond int's range cast to int is undefined behaviour.
      const Node counts = e["complete_count"];
      if (!counts.raw().is_array() || counts.Size() != 3) counts.Fail("", "expected 3 counts, got " + counts.raw().dump());
      for (size_t k = 0; k < 3; ++k) m.complete_count[k] = counts[k].Int();
      m.complete_sum = e["complete_sum"].Vector();
      m.center_count = e["center_count"].Int();
      m.center_sum = e["center_sum"].Vector();
      m.partial_center_count = e["partial_center_count"].Int();
      m.partial_center_sum = e["partial_center_sum"].Vector();
      const Node labels = e["label_votes"];
      if (!labels.raw().is_object()) labels.Fail("", "expected {class: votes}");
      for (const auto& [label, n] : labels.raw().items()) m.label_votes.emplace_back(label, labels[label].Int());
      for (const Node& v : e.List("grasp_votes")) {
        if (!v.raw().is_array() || v.Size() != 2) v.Fail("", "expected [plane, votes]");
        m.grasp_votes.emplace_back(plane_id(v[0]), v[1].Int());
      }
      m.grasp_landmark = plane_id(e["grasp_plane"]);
      m.x_landmark = plane_id(e["x_plane"]);
    }
    map.objects.push_back(std::move(m));
  }
  for (const Node& k : top.List("keyframes")) {
    Keyframe f;
    f.frame = k["frame"].Int();
    f.stamp = k["stamp"].Number();
    const std::vector<double> q = k["quaternion_xyzw"].Numbers(4);
    const Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
    if (std::abs(rotation.norm() - 1.0) > 1e-3) k["quaternion_xyzw"].Fail("", "expected a unit quaternion");
    f.T_world_camera = MakePose(rotation.normalized(), k["position"].Vector());
    map.keyframes.push_back(f);
  }
  return map;
}

}  // namespace planemap
