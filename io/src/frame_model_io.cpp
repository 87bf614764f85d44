#include "planemap/io/frame_model_io.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "planemap/core/error.h"
#include "planemap/io/image_io.h"

namespace planemap {
namespace {

using nlohmann::json;

json Vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

// A distinct colour per index (golden-angle hues).
cv::Scalar Palette(int i) {
  const double hue = std::fmod(i * 137.508, 360.0) / 60.0;
  const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(hue)) {
    case 0: r = 1, g = x; break;
    case 1: r = x, g = 1; break;
    case 2: g = 1, b = x; break;
    case 3: g = x, b = 1; break;
    case 4: r = x, b = 1; break;
    default: r = 1, b = x; break;
  }
  return cv::Scalar(255 * b, 255 * g, 255 * r);  // BGR
}

}  // namespace

std::string FrameModelJson(const FrameModel& model, int indent) {
  json j;
  j["reason"] = model.reason;
  j["floor"] = model.floor;
  j["planes"] = json::array();
  for (const DetectedPlane& p : model.planes) {
    j["planes"].push_back({{"id", p.id}, {"normal", Vec(p.plane.normal)}, {"offset", p.plane.offset},
                           {"centroid", Vec(p.centroid)}, {"inliers", p.inliers.size()}, {"rms", p.rms},
                           {"strip", p.strip},
                           {"structure", p.id < static_cast<int>(model.structure.size()) && model.structure[p.id]}});
    // A piece of a face in pieces (FrameModel::face_of): the face (its lowest-id piece) and the
    // plane fitted to all its pieces.
    const bool known = p.id < static_cast<int>(model.face_of.size());
    const int face = known ? model.face_of[p.id] : p.id;
    j["planes"].back()["face"] = face;
    if (known && std::count(model.face_of.begin(), model.face_of.end(), face) > 1) {
      j["planes"].back()["face_normal"] = Vec(model.FacePlane(p.id).normal);
      j["planes"].back()["face_offset"] = model.FacePlane(p.id).offset;
    }
  }
  j["edges"] = json::array();
  for (const PlaneEdge& e : model.edges) {
    j["edges"].push_back({{"planes", {e.plane_a, e.plane_b}}, {"start", Vec(e.start)}, {"end", Vec(e.end)},
                          {"length", e.length}, {"length_eq6", e.length_eq6}, {"points", e.points},
                          {"start_cut", e.start_cut}, {"end_cut", e.end_cut}, {"convex", e.convex},
                          {"hidden", e.hidden}});
  }
  j["trihedral_angles"] = json::array();
  for (const TrihedralAngle& a : model.angles) {
    j["trihedral_angles"].push_back({{"planes", {a.planes[0], a.planes[1], a.planes[2]}}, {"corner", Vec(a.corner)}});
  }
  j["objects"] = json::array();
  for (const FrameObject& o : model.objects) {
    json object = {{"class", o.label},
                   {"planes", o.planes},
                   {"trihedral_angles", o.angles},
                   {"support", o.support},
                   {"dimensions", Vec(o.dimensions)},
                   {"dimension_complete", {o.dimension_complete[0], o.dimension_complete[1], o.dimension_complete[2]}},
                   {"height", o.height},
                   {"height_known", o.height_known},
                   {"center", Vec(o.center)},
                   {"axes", {Vec(o.axes.col(0)), Vec(o.axes.col(1)), Vec(o.axes.col(2))}},
                   {"grasp_sides", o.grasp_sides},
                   {"grasp_side", o.grasp_side}};
    object["grasp_axis"] = o.grasp_side >= 0 ? Vec(o.grasp_axis) : json(nullptr);
    j["objects"].push_back(object);
  }
  return j.dump(indent);
}

namespace {

struct PlyVertex {
  Eigen::Vector3f p;
  cv::Scalar bgr;
};

// Points and line segments (PLY "edge" elements) with colours, ASCII.
void WritePly(const std::string& file, const std::string& comment, const std::vector<PlyVertex>& vertices,
              const std::vector<std::pair<int, int>>& lines) {
  std::ofstream out(file);
  if (!out) ThrowInputError(file, 0, "cannot open file for writing");
  out << "ply\nformat ascii 1.0\ncomment " << comment << "\n"
      << "element vertex " << vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      << "element edge " << lines.size() << "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  for (const PlyVertex& v : vertices) {
    out << v.p.x() << ' ' << v.p.y() << ' ' << v.p.z() << ' ' << static_cast<int>(v.bgr[2]) << ' '
        << static_cast<int>(v.bgr[1]) << ' ' << static_cast<int>(v.bgr[0]) << '\n';
  }
  for (const auto& [a, b] : lines) out << a << ' ' << b << '\n';
  if (!out) ThrowInputError(file, 0, "write failed");
}

struct PlyBuilder {
  std::vector<PlyVertex> vertices;
  std::vector<std::pair<int, int>> lines;
  void Line(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const cv::Scalar& c) {
    vertices.push_back({a.cast<float>(), c});
    vertices.push_back({b.cast<float>(), c});
    lines.emplace_back(static_cast<int>(vertices.size()) - 2, static_cast<int>(vertices.size()) - 1);
  }
  void Cross(const Eigen::Vector3d& x, double half, const cv::Scalar& c) {
    for (int k = 0; k < 3; ++k) Line(x - half * Eigen::Vector3d::Unit(k), x + half * Eigen::Vector3d::Unit(k), c);
  }
};

}  // namespace

void WriteFrameModelPly(const std::string& file, const FrameModel& model, const std::vector<Eigen::Vector3f>& points) {
  PlyBuilder ply;
  for (const DetectedPlane& plane : model.planes) {
    const cv::Scalar c = Palette(plane.id);
    for (int i : plane.inliers) {
      if (std::isfinite(points[i].z())) ply.vertices.push_back({points[i], c});
    }
  }
  for (const PlaneEdge& e : model.edges) ply.Line(e.start, e.end, cv::Scalar(0, 0, 0));
  for (const TrihedralAngle& a : model.angles) ply.Cross(a.corner, 0.02, cv::Scalar(0, 128, 255));  // [m]
  for (const FrameObject& o : model.objects) {
    ply.Cross(o.center, 0.02, cv::Scalar(255, 0, 0));
    if (o.grasp_side >= 0) ply.Line(o.center, o.center + 0.3 * o.grasp_axis, cv::Scalar(0, 0, 255));
  }
  WritePly(file, "planemap frame model: planes (inliers), edges, corners, centres, grasp axes", ply.vertices, ply.lines);
}

void WritePlaneMapPly(const std::string& file, const PlaneMap& map) {
  PlyBuilder ply;
  for (const PlaneLandmark& l : map.landmarks) {
    for (const Eigen::Vector3f& p : l.points) ply.vertices.push_back({p, Palette(l.id)});
  }
  for (const MapEdge& e : map.edges) ply.Line(e.start, e.end, cv::Scalar(0, 0, 0));
  for (const MapObject& o : map.objects) {
    if (o.structure) continue;
    ply.Cross(o.center, 0.03, cv::Scalar(255, 0, 0));  // [m]
    for (int k = 0; k < 3; ++k) ply.Line(o.center, o.center + 0.5 * o.dimensions[k] * o.axes.col(k), cv::Scalar(255, 255, 0));
    if (o.has_grasp_axis) ply.Line(o.center, o.center + 0.3 * o.grasp_axis, cv::Scalar(0, 0, 255));
  }
  for (const Keyframe& k : map.keyframes) ply.Cross(k.T_world_camera.translation(), 0.02, cv::Scalar(0, 200, 0));
  WritePly(file, "planemap map: plane landmarks (voxel points), edges, object centres, axes and grasp axes, keyframes",
           ply.vertices, ply.lines);
}

void WriteOverlayPng(const std::string& file, const ColorImage& color, const FrameModel& model,
                     const CameraIntrinsics& camera) {
  cv::Mat image(camera.height, camera.width, CV_8UC3, cv::Scalar(40, 40, 40));
  if (color.width() == camera.width && color.height() == camera.height) {
    for (int v = 0; v < camera.height; ++v) {
      for (int u = 0; u < camera.width; ++u) {
        const Rgb8& c = color.at(u, v);
        image.at<cv::Vec3b>(v, u) = cv::Vec3b(c[2], c[1], c[0]);
      }
    }
  }
  for (const DetectedPlane& plane : model.planes) {
    const cv::Scalar c = Palette(plane.id);
    for (int i : plane.inliers) {
      cv::Vec3b& px = image.at<cv::Vec3b>(i / camera.width, i % camera.width);
      for (int k = 0; k < 3; ++k) px[k] = static_cast<std::uint8_t>(0.4 * px[k] + 0.6 * c[k]);
    }
  }
  auto pixel = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d uv = camera.Project(p);
    return cv::Point(static_cast<int>(std::lround(uv.x())), static_cast<int>(std::lround(uv.y())));
  };
  for (const PlaneEdge& e : model.edges) {
    if (e.start.z() > 0 && e.end.z() > 0) cv::line(image, pixel(e.start), pixel(e.end), cv::Scalar(0, 0, 0), 2, cv::LINE_AA);
  }
  for (const TrihedralAngle& a : model.angles) {
    if (a.corner.z() > 0) cv::circle(image, pixel(a.corner), 5, cv::Scalar(0, 140, 255), -1, cv::LINE_AA);
  }
  for (const FrameObject& o : model.objects) {
    if (o.center.z() <= 0) continue;
    cv::circle(image, pixel(o.center), 6, cv::Scalar(255, 80, 0), -1, cv::LINE_AA);
    if (o.grasp_side >= 0) {
      const Eigen::Vector3d tip = o.center + 0.3 * o.grasp_axis;
      if (tip.z() > 0) cv::arrowedLine(image, pixel(o.center), pixel(tip), cv::Scalar(0, 0, 0), 2, cv::LINE_AA, 0, 0.2);
    }
    cv::putText(image, o.label, pixel(o.center) + cv::Point(8, -8), cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(255, 255, 255), 2, cv::LINE_AA);
  }
  ColorImage out(camera.width, camera.height);
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const cv::Vec3b& px = image.at<cv::Vec3b>(v, u);
      out.at(u, v) = {px[2], px[1], px[0]};
    }
  }
  WriteColorPng(file, out);
}

}  // namespace planemap
