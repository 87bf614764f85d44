// import planemap: the library from Python. Camera intrinsics; a frame's model (planes, objects
// with dimensions, centre, axes) from numpy depth and colour arrays; the live pipeline frame by
// frame (planemap::Mapper); a TUM-layout sequence's map and trajectory; the ATE; the simulator's
// rendered frames and true objects, for evaluations against ground truth.
//
// Conventions: poses are 4x4 float64 arrays T_world_camera (p_world = T p_camera), metres and
// seconds; depth is (height, width) uint16 in the camera's depth_scale units or float32/float64
// in metres, 0 where there is no measurement; colour is (height, width, 3) uint8 RGB. Wrong input
// raises TypeError or ValueError naming what is wrong; the library's errors arrive as
// planemap.InputError (bad files and settings) or ValueError, with their message.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "planemap/core/config.h"
#include "planemap/core/error.h"
#include "planemap/core/intrinsics.h"
#include "planemap/core/object_eval.h"
#include "planemap/core/trajectory_eval.h"
#include "planemap/io/tum_sequence.h"
#include "planemap/pipeline/mapper.h"
#include "planemap/sim/scene.h"
#include "planemap/sim/virtual_camera.h"

namespace py = pybind11;

namespace planemap {
namespace {

const std::string kConfigs = PLANEMAP_CONFIGS_DIR;

using Matrix4 = Eigen::Matrix4d;

Matrix4 ToMatrix(const Pose3& pose) { return pose.matrix(); }

// A 4x4 rigid transform from Python; anything else (shape, a non-rotation, NaN) is named.
Pose3 ToPose(const Matrix4& m, const char* what) {
  if (!m.allFinite()) throw py::value_error(std::string(what) + ": the matrix holds NaN or infinity");
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0.0 ||
      (m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) {
    throw py::value_error(std::string(what) + ": not a rigid transform (a rotation, a translation and a last row 0 0 0 1)");
  }
  Pose3 pose = Pose3::Identity();
  pose.linear() = R;
  pose.translation() = m.topRightCorner<3, 1>();
  return pose;
}

std::string Shape(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string DtypeName(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

// Element (r, c[, k]) of any strides (views, slices and transposes read as numpy shows them).
template <typename T>
T At(const py::array& a, py::ssize_t r, py::ssize_t c, py::ssize_t k = 0) {
  const char* p = static_cast<const char*>(a.data()) + r * a.strides(0) + c * a.strides(1) + (a.ndim() > 2 ? k * a.strides(2) : 0);
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

void CheckCamera(const CameraIntrinsics& camera) {
  ValidateConfig(camera, "camera.");  // InputError naming the setting
}

DepthImage DepthFromArray(const py::array& depth, const CameraIntrinsics& camera) {
  if (depth.ndim() != 2) throw py::value_error("depth: expected a 2-D array (height, width), got shape " + Shape(depth));
  if (depth.shape(0) != camera.height || depth.shape(1) != camera.width) {
    throw py::value_error("depth: shape " + Shape(depth) + " does not match the camera's intrinsics (" + std::to_string(camera.height) +
                          ", " + std::to_string(camera.width) + ") (height, width)");
  }
  DepthImage image(camera.width, camera.height);
  const py::dtype dtype = depth.dtype();
  const auto bad_value = [&](py::ssize_t r, py::ssize_t c, double value) {
    throw py::value_error("depth[" + std::to_string(r) + ", " + std::to_string(c) + "] is " + std::to_string(value) +
                          ": depth must be finite and not negative (0 where there is no measurement)");
  };
  if (dtype.equal(py::dtype::of<std::uint16_t>())) {
    const double scale = 1.0 / camera.depth_scale;
    for (py::ssize_t r = 0; r < depth.shape(0); ++r)
      for (py::ssize_t c = 0; c < depth.shape(1); ++c) image.at(c, r) = static_cast<float>(At<std::uint16_t>(depth, r, c) * scale);
  } else if (dtype.equal(py::dtype::of<float>()) || dtype.equal(py::dtype::of<double>())) {
    const bool single = dtype.equal(py::dtype::of<float>());
    for (py::ssize_t r = 0; r < depth.shape(0); ++r) {
      for (py::ssize_t c = 0; c < depth.shape(1); ++c) {
        const double z = single ? At<float>(depth, r, c) : At<double>(depth, r, c);
        if (!std::isfinite(z) || z < 0.0) bad_value(r, c, z);
        image.at(c, r) = static_cast<float>(z);
      }
    }
  } else {
    throw py::type_error("depth: dtype " + DtypeName(depth) +
                         "; expected uint16 (sensor units, divided by the camera's depth_scale) or float32/float64 (metres), native byte order");
  }
  return image;
}

ColorImage ColorFromArray(const py::array& color, const CameraIntrinsics& camera) {
  if (color.ndim() != 3 || color.shape(2) != 3) throw py::value_error("color: expected shape (height, width, 3), got " + Shape(color));
  if (color.shape(0) != camera.height || color.shape(1) != camera.width) {
    throw py::value_error("color: shape " + Shape(color) + " does not match the camera's intrinsics (" + std::to_string(camera.height) +
                          ", " + std::to_string(camera.width) + ", 3)");
  }
  if (!color.dtype().equal(py::dtype::of<std::uint8_t>())) throw py::type_error("color: dtype " + DtypeName(color) + "; expected uint8 RGB");
  ColorImage image(camera.width, camera.height);
  for (py::ssize_t r = 0; r < color.shape(0); ++r)
    for (py::ssize_t c = 0; c < color.shape(1); ++c)
      for (int k = 0; k < 3; ++k) image.at(c, r)[k] = At<std::uint8_t>(color, r, c, k);
  return image;
}

RgbdFrame FrameFromArrays(const py::array& depth, const std::optional<py::array>& color, double stamp, const CameraIntrinsics& camera) {
  if (!std::isfinite(stamp)) throw py::value_error("stamp: must be finite");
  RgbdFrame frame;
  frame.stamp = frame.color_stamp = stamp;
  frame.depth = DepthFromArray(depth, camera);
  if (color) frame.color = ColorFromArray(*color, camera);
  return frame;
}

py::array_t<float> DepthToArray(const DepthImage& depth) {
  py::array_t<float> a({depth.height(), depth.width()});
  std::memcpy(a.mutable_data(), depth.data(), depth.size() * sizeof(float));
  return a;
}

py::array_t<std::uint8_t> ColorToArray(const ColorImage& color) {
  py::array_t<std::uint8_t> a({color.height(), color.width(), 3});
  std::memcpy(a.mutable_data(), color.data(), color.size() * 3);
  return a;
}

PatternsConfig Patterns(const std::optional<std::string>& file) { return LoadPatterns(file ? *file : kConfigs + "/patterns.yaml"); }

MapperConfig Config(const std::optional<MapperConfig>& config) { return config ? *config : MapperConfig{}; }

py::list TrajectoryList(const Trajectory& trajectory) {
  py::list out;
  for (const StampedPose& p : trajectory) out.append(py::make_tuple(p.stamp, ToMatrix(p.T_world_camera)));
  return out;
}

Trajectory TrajectoryFromList(const std::vector<std::pair<double, Matrix4>>& poses, const char* what) {
  Trajectory t;
  for (const auto& [stamp, m] : poses) t.push_back({stamp, ToPose(m, what)});
  return t;
}

std::optional<Eigen::Vector3d> GraspAxis(const FrameObject& o) {
  if (o.grasp_side < 0) return std::nullopt;
  return o.grasp_axis;
}

// A frontend and the camera its frames must match.
struct PyFrontend {
  CameraIntrinsics camera;
  Frontend frontend;
};

// The map's outputs as Python reads them: plain fields, the internal bookkeeping left out.
struct PyFinalMap {
  PlaneMap map;
  Trajectory refined;
  bool refine_asked = false, refine_usable = false;
  std::string refine_termination;
  int fused_planes = 0, fused_objects = 0;
};

PyFinalMap ToPy(const FinalMap& f, const std::vector<FrameObservations>& frames) {
  PyFinalMap out;
  out.map = f.map;
  out.refine_asked = f.refine_asked;
  out.refine_usable = f.refine_asked && f.refine.usable;
  out.refine_termination = f.refine.termination;
  out.fused_planes = f.fused_planes;
  out.fused_objects = f.fused_objects;
  for (size_t k = 0; k < f.refined_poses.size() && k < frames.size(); ++k) out.refined.push_back({frames[k].stamp, f.refined_poses[k]});
  return out;
}

}  // namespace
}  // namespace planemap

PYBIND11_MODULE(planemap, m) {
  using namespace planemap;
  m.doc() = "planemap: plane-based object maps and camera poses from RGB-D frames";
  py::register_exception<InputError>(m, "InputError", PyExc_RuntimeError);

  py::class_<CameraIntrinsics>(m, "CameraIntrinsics", "Pinhole intrinsics [px] and the depth units per metre")
      .def(py::init([](double fx, double fy, double cx, double cy, int width, int height, double depth_scale) {
             CameraIntrinsics c{fx, fy, cx, cy, width, height, depth_scale};
             CheckCamera(c);
             return c;
           }),
           py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"), py::arg("width") = 640, py::arg("height") = 480,
           py::arg("depth_scale") = 5000.0)
      .def_readonly("fx", &CameraIntrinsics::fx)
      .def_readonly("fy", &CameraIntrinsics::fy)
      .def_readonly("cx", &CameraIntrinsics::cx)
      .def_readonly("cy", &CameraIntrinsics::cy)
      .def_readonly("width", &CameraIntrinsics::width)
      .def_readonly("height", &CameraIntrinsics::height)
      .def_readonly("depth_scale", &CameraIntrinsics::depth_scale)
      .def("__repr__", [](const CameraIntrinsics& c) {
        return "CameraIntrinsics(fx=" + std::to_string(c.fx) + ", fy=" + std::to_string(c.fy) + ", cx=" + std::to_string(c.cx) +
               ", cy=" + std::to_string(c.cy) + ", width=" + std::to_string(c.width) + ", height=" + std::to_string(c.height) +
               ", depth_scale=" + std::to_string(c.depth_scale) + ")";
      });
  m.def("load_camera", &LoadCameraIntrinsics, py::arg("file"), "Camera intrinsics from a YAML file (configs/cameras/)");

  py::class_<MapperConfig>(m, "MapperConfig", "The pipeline's settings (frontend, tracking, backend, merge)")
      .def(py::init<>())
      .def("to_yaml", [](const MapperConfig& c) { return YAML::Dump(ConfigToYaml(c)); });
  m.def("load_config", &LoadMapperConfig, py::arg("file"),
        "The pipeline's sections of a planemap config file (e.g. configs/default.yaml); other sections are left alone");
  m.attr("configs_dir") = kConfigs;

  py::class_<DetectedPlane>(m, "Plane", "A plane of one frame, camera frame: normal . x + offset = 0")
      .def_readonly("id", &DetectedPlane::id)
      .def_property_readonly("normal", [](const DetectedPlane& p) { return p.plane.normal; })
      .def_property_readonly("offset", [](const DetectedPlane& p) { return p.plane.offset; })
      .def_readonly("centroid", &DetectedPlane::centroid)
      .def_property_readonly("inliers", [](const DetectedPlane& p) { return p.inliers.size(); })
      .def_readonly("rms", &DetectedPlane::rms);
  py::class_<FrameObject>(m, "FrameObject", "An object of one frame, camera frame; axes are columns x, y, z (z up)")
      .def_readonly("label", &FrameObject::label)
      .def_readonly("planes", &FrameObject::planes)
      .def_readonly("support", &FrameObject::support)
      .def_readonly("dimensions", &FrameObject::dimensions)
      .def_readonly("dimension_complete", &FrameObject::dimension_complete)
      .def_readonly("center", &FrameObject::center)
      .def_readonly("axes", &FrameObject::axes)
      .def_property_readonly("grasp_axis", &GraspAxis);
  py::class_<FrameModel>(m, "FrameModel", "What one frame shows: planes, edges and objects (camera frame)")
      .def_readonly("planes", &FrameModel::planes)
      .def_readonly("objects", &FrameModel::objects)
      .def_readonly("floor", &FrameModel::floor)
      .def_property_readonly("edges", [](const FrameModel& f) { return f.edges.size(); })
      .def_readonly("reason", &FrameModel::reason);

  py::class_<PyFrontend>(m, "Frontend", "A frame's model from its depth (and colour)")
      .def(py::init([](const CameraIntrinsics& camera, const std::optional<MapperConfig>& config, const std::optional<std::string>& patterns) {
             CheckCamera(camera);
             return std::make_unique<PyFrontend>(PyFrontend{camera, Frontend(camera, Config(config).frontend, Patterns(patterns))});
           }),
           py::arg("camera"), py::arg("config") = py::none(), py::arg("patterns") = py::none())
      .def_readonly("camera", &PyFrontend::camera)
      .def(
          "process",
          [](const PyFrontend& f, const py::array& depth, const std::optional<py::array>& color) {
            const RgbdFrame frame = FrameFromArrays(depth, color, 0.0, f.camera);
            py::gil_scoped_release release;
            return f.frontend.Process(frame);
          },
          py::arg("depth"), py::arg("color") = py::none(), "The frame's model (camera frame)");

  py::class_<PlaneLandmark>(m, "Landmark", "A mapped plane, world frame")
      .def_readonly("id", &PlaneLandmark::id)
      .def_property_readonly("normal", [](const PlaneLandmark& l) { return l.plane.normal; })
      .def_property_readonly("offset", [](const PlaneLandmark& l) { return l.plane.offset; })
      .def_readonly("observations", &PlaneLandmark::observations);
  py::class_<MapObject>(m, "MapObject", "A mapped object, world frame; axes are columns x, y, z (z up)")
      .def_readonly("id", &MapObject::id)
      .def_readonly("label", &MapObject::label)
      .def_readonly("landmarks", &MapObject::landmarks)
      .def_readonly("dimensions", &MapObject::dimensions)
      .def_readonly("dimension_complete", &MapObject::dimension_complete)
      .def_readonly("center", &MapObject::center)
      .def_readonly("axes", &MapObject::axes)
      .def_property_readonly("grasp_axis",
                             [](const MapObject& o) -> std::optional<Eigen::Vector3d> {
                               if (!o.has_grasp_axis) return std::nullopt;
                               return o.grasp_axis;
                             })
      .def_readonly("observations", &MapObject::observations)
      .def_readonly("structure", &MapObject::structure,
                    "True: a wall's piece taken for an object before the map knew the wall; no object");
  py::class_<PlaneMap>(m, "Map", "The map: plane landmarks and objects, world frame")
      .def_readonly("planes", &PlaneMap::landmarks)
      .def_readonly("objects", &PlaneMap::objects);

  py::class_<MapperStep>(m, "Step", "One frame through the pipeline")
      .def_property_readonly("status", [](const MapperStep& s) { return std::string(ToString(s.track.status)); })
      .def_property_readonly("T_world_camera", [](const MapperStep& s) { return ToMatrix(s.track.T_world_camera); })
      .def_property_readonly("T_world_camera_smoothed", [](const MapperStep& s) { return ToMatrix(s.T_world_camera_smoothed); })
      .def_property_readonly("planes", [](const MapperStep& s) { return s.track.planes; })
      .def_property_readonly("matched", [](const MapperStep& s) { return s.track.matched; })
      .def_property_readonly("added", [](const MapperStep& s) { return s.track.added; })
      .def_property_readonly("reason", [](const MapperStep& s) { return s.track.reason; })
      .def_readonly("tracking_ms", &MapperStep::tracking_ms)
      .def_readonly("window_ms", &MapperStep::window_ms);
  py::class_<PyFinalMap>(m, "FinalMap", "The map kept at the end of a run")
      .def_readonly("map", &PyFinalMap::map)
      .def_property_readonly("refined_trajectory", [](const PyFinalMap& f) { return TrajectoryList(f.refined); })
      .def_readonly("refine_asked", &PyFinalMap::refine_asked)
      .def_readonly("refine_usable", &PyFinalMap::refine_usable)
      .def_readonly("refine_termination", &PyFinalMap::refine_termination)
      .def_readonly("fused_planes", &PyFinalMap::fused_planes)
      .def_readonly("fused_objects", &PyFinalMap::fused_objects);

  py::class_<Mapper>(m, "Mapper", "The live pipeline: frames in order; tracked and smoothed poses and the map out")
      .def(py::init([](const CameraIntrinsics& camera, const std::optional<MapperConfig>& config, const std::optional<std::string>& patterns,
                       const std::optional<Matrix4>& T_world_first, bool smoothing) {
             CheckCamera(camera);
             const Pose3 first = T_world_first ? ToPose(*T_world_first, "T_world_first") : Pose3::Identity();
             return std::make_unique<Mapper>(camera, Config(config), Patterns(patterns), first, smoothing);
           }),
           py::arg("camera"), py::arg("config") = py::none(), py::arg("patterns") = py::none(), py::arg("T_world_first") = py::none(),
           py::arg("smoothing") = true)
      .def(
          "add",
          [](Mapper& mapper, const py::array& depth, const std::optional<py::array>& color, double stamp,
             const std::optional<Matrix4>& T_odometry_camera) {
            const RgbdFrame frame = FrameFromArrays(depth, color, stamp, mapper.camera());
            if (!mapper.observations().empty() && stamp <= mapper.observations().back().stamp) {
              throw py::value_error("stamp " + std::to_string(stamp) + " is not after the last frame's " +
                                    std::to_string(mapper.observations().back().stamp) + ": frames go in time order");
            }
            std::optional<Pose3> odometry;
            if (T_odometry_camera) odometry = ToPose(*T_odometry_camera, "T_odometry_camera");
            py::gil_scoped_release release;
            return mapper.Add(frame, odometry);
          },
          py::arg("depth"), py::arg("color") = py::none(), py::arg("stamp"), py::arg("T_odometry_camera") = py::none())
      .def_property_readonly("map", &Mapper::map, py::return_value_policy::copy)
      .def_property_readonly("trajectory",
                             [](const Mapper& mapper) {
                               Trajectory t;
                               for (const FrameObservations& f : mapper.observations()) t.push_back({f.stamp, f.T_world_camera});
                               return TrajectoryList(t);
                             })
      .def(
          "finish",
          [](const Mapper& mapper, bool refine) {
            py::gil_scoped_release release;
            return ToPy(mapper.Finish(refine), mapper.observations());
          },
          py::arg("refine") = false, "The map to keep: refined by the batch back end when asked, duplicates fused");

  py::class_<TumSequence>(m, "Sequence", "A TUM-layout RGB-D sequence (rgb.txt, depth.txt, groundtruth.txt)")
      .def(py::init([](const std::string& dir, const CameraIntrinsics& camera) {
             CheckCamera(camera);
             return TumSequence::Open(dir, camera);
           }),
           py::arg("dir"), py::arg("camera"))
      .def("__len__", &TumSequence::size)
      .def(
          "frame",
          [](const TumSequence& s, py::ssize_t i) {
            if (i < 0 || static_cast<size_t>(i) >= s.size())
              throw py::index_error("frame " + std::to_string(i) + " of a sequence of " + std::to_string(s.size()));
            const RgbdFrame f = s.LoadFrame(static_cast<size_t>(i));
            py::dict d;
            d["stamp"] = f.stamp;
            d["depth"] = DepthToArray(f.depth);
            d["color"] = f.color.empty() ? py::object(py::none()) : py::object(ColorToArray(f.color));
            d["T_world_camera"] = s.entry(i).T_world_camera ? py::object(py::cast(ToMatrix(*s.entry(i).T_world_camera))) : py::object(py::none());
            return d;
          },
          py::arg("index"), "dict: stamp, depth (float32 metres), color (uint8 RGB or None), T_world_camera (ground truth or None)")
      .def_property_readonly("groundtruth", [](const TumSequence& s) {
        Trajectory t;
        for (size_t i = 0; i < s.size(); ++i)
          if (s.entry(i).T_world_camera) t.push_back({s.entry(i).depth.stamp, *s.entry(i).T_world_camera});
        return TrajectoryList(t);
      });

  m.def(
      "ate",
      [](const std::vector<std::pair<double, Matrix4>>& groundtruth, const std::vector<std::pair<double, Matrix4>>& estimate,
         double max_time_gap) {
        const AteResult ate = ComputeAte(AssociatePoses(TrajectoryFromList(groundtruth, "groundtruth"),
                                                        TrajectoryFromList(estimate, "estimate"), max_time_gap));
        if (ate.translation.count == 0) throw py::value_error("ate: fewer than 3 poses pair up in time");
        return ate.translation.rmse;
      },
      py::arg("groundtruth"), py::arg("estimate"), py::arg("max_time_gap") = 0.02,
      "ATE RMSE [m] (TUM's definition: poses paired by stamp, rigidly aligned), of lists of (stamp, 4x4)");

  m.def(
      "render",
      [](const std::string& scene_file, const CameraIntrinsics& camera, const Matrix4& T_world_camera, std::uint64_t seed, bool noise) {
        CheckCamera(camera);
        const sim::Scene scene = sim::LoadScene(scene_file);
        sim::RenderConfig render;
        render.add_noise = noise;
        const sim::VirtualCamera sensor(scene, camera, render);
        const Pose3 pose = ToPose(T_world_camera, "T_world_camera");
        sim::RenderedFrame frame;
        {
          py::gil_scoped_release release;
          frame = sensor.Render(pose, seed);
        }
        return py::make_tuple(DepthToArray(frame.depth), ColorToArray(frame.color));
      },
      py::arg("scene"), py::arg("camera"), py::arg("T_world_camera"), py::arg("seed") = 1, py::arg("noise") = true,
      "The simulator's (depth [m] float32, colour uint8) of a scene file seen from T_world_camera");
  m.def(
      "scene_objects",
      [](const std::string& scene_file) {
        py::list out;
        for (const ObjectTruth& t : sim::ObjectTruths(sim::LoadScene(scene_file))) {
          py::dict d;
          d["name"] = t.name;
          d["type"] = t.type;
          d["T_world_object"] = ToMatrix(t.T_world_object);
          d["dimensions"] = t.dimensions;
          out.append(d);
        }
        return out;
      },
      py::arg("scene"), "A scene file's true objects: name, type, T_world_object (centre, axes along the edges), dimensions [m]");
  m.def("look_at", [](const Eigen::Vector3d& eye, const Eigen::Vector3d& target) { return ToMatrix(LookAt(eye, target)); },
        py::arg("eye"), py::arg("target"), "T_world_camera of a camera at `eye` looking at `target` (world z up)");
}
