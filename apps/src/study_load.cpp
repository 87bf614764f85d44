// A study file read and checked (LoadStudy), its runs and scaled scenes: what `planemap study`
// reads before any run. Apart from the runs themselves (study.cpp), so that the study file's fuzz
// target builds with the readers alone (fuzz/).
#include "planemap/apps/study.h"

#include <cmath>
#include <cstdio>
#include <map>

#include "planemap/apps/app_config.h"
#include "planemap/core/error.h"
#include "study_internal.h"

namespace planemap {
namespace study_internal {

constexpr double kDegToRad = M_PI / 180.0;

std::string Number(double value, const char* format) {
  if (std::isnan(value)) return "";
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

std::string Short(double value) { return Number(value, "%.10g"); }

// Camera position of frame `k` of a run: on a circle around the object at the run's distance.
Eigen::Vector3d Eye(const StudyConfig& study, const StudyRun& run, const sim::SceneObject& object, int k) {
  const Eigen::Vector3d x_axis = object.T_world_object.linear().col(0);
  double bearing = std::atan2(x_axis.y(), x_axis.x()) - run.viewing_angle_deg * kDegToRad;
  if (study.frames > 1) bearing += study.path_length / run.distance * (static_cast<double>(k) / (study.frames - 1) - 0.5);
  const Eigen::Vector3d c = object.Center();
  return {c.x() + run.distance * std::cos(bearing), c.y() + run.distance * std::sin(bearing), study.camera_height};
}

}  // namespace study_internal

namespace {

// Frames one study may render (runs x frames): the default study renders 600, the 10,000 runs of
// docs/cluster.md 50,000; a million takes a 32-core node days.
constexpr double kMaxStudyFrames = 1e6;

using study_internal::Eye;
using study_internal::Number;
using study_internal::Short;

// The scene file with the studied object's dimensions scaled by `scale`, its bottom kept where it
// was (on the floor). Markers printed on it keep their size and place on its faces.
sim::Scene ScaledScene(const std::string& file, const std::string& object, double scale) {
  YAML::Node root = LoadYamlFile(file);
  if (scale != 1.0 && root["objects"] && root["objects"].IsSequence()) {
    for (YAML::Node item : root["objects"]) {
      if (!item.IsMap() || !item["name"] || item["name"].as<std::string>() != object) continue;
      if (!item["dimensions"] || !item["position"]) break;  // ParseScene names what is missing
      std::vector<double> dims = item["dimensions"].as<std::vector<double>>();
      std::vector<double> position = item["position"].as<std::vector<double>>();
      if (dims.size() != 3 || position.size() != 3) break;
      position[2] += 0.5 * dims[2] * (scale - 1.0);
      for (double& d : dims) d *= scale;
      item["dimensions"] = dims;
      item["position"] = position;
    }
  }
  return sim::ParseScene(root, file);
}

// Where a viewpoint is impossible: outside the floor or inside a solid; empty if it is fine.
std::string ViewpointProblem(const sim::Scene& scene, const Eigen::Vector3d& eye) {
  for (size_t i : scene.flat_surfaces) {
    const sim::Surface& s = scene.surfaces[i];
    if (s.object != "floor") continue;
    const Eigen::Vector3d d = eye - s.center_world;
    if (std::abs(d.dot(s.axis_u)) > s.half_u || std::abs(d.dot(s.axis_v)) > s.half_v) return "outside the floor";
  }
  for (const sim::Cuboid& c : scene.cuboids) {
    const Eigen::Vector3d p = c.T_world_box.inverse() * eye;
    if ((p.cwiseAbs() - 0.5 * c.dimensions).maxCoeff() < 0.0) return "inside an object";
  }
  return "";
}

}  // namespace

sim::Scene StudyScene(const StudyConfig& study, double object_scale) {
  return ScaledScene(ResolveConfigPath(study.scene), study.object, object_scale);
}

StudyConfig LoadStudy(const std::string& file) {
  StudyConfig study = LoadConfigFile<StudyConfig>(file);
  const StudySweep& s = study.sweep;
  auto require = [&](bool ok, const std::string& what) {
    if (!ok) ThrowInputError(file, 0, what);
  };
  require(!s.distance.empty() && !s.viewing_angle_deg.empty() && !s.noise.empty() && !s.object_scale.empty() &&
              !s.segmenter.empty(),
          "every sweep list needs at least one value");
  for (const std::string& m : s.segmenter) {
    require(m == "organized" || m == "msac", "sweep.segmenter: unknown segmenter '" + m + "' (organized, msac)");
  }
  const sim::Scene scene = sim::LoadScene(ResolveConfigPath(study.scene));
  try {
    scene.object(study.object);
  } catch (const std::out_of_range&) {
    require(false, "object: scene '" + scene.name + "' has no object '" + study.object + "'");
  }
  LoadConfigFile<AppConfig>(ResolveConfigPath(study.config));  // a bad pipeline file fails now
  // A study too large to run fails now, not after hours (or all the memory) spent listing and
  // checking its viewpoints: a fuzzed seeds: 100000000 hung here. Runs x frames bounds both.
  const double runs = static_cast<double>(s.distance.size()) * s.viewing_angle_deg.size() * s.noise.size() *
                      s.object_scale.size() * s.segmenter.size() * study.seeds;
  require(runs * study.frames <= kMaxStudyFrames, "the sweep's " + Short(runs) + " runs of " + std::to_string(study.frames) +
                                                      " frames are more than the " + Short(kMaxStudyFrames) +
                                                      " frames one study may render; split it");
  // Every viewpoint of the first seed, the scene scaled once per object_scale (not once per run).
  std::map<double, sim::Scene> scaled;
  for (const StudyRun& run : StudyRuns(study)) {
    if (run.seed != 1) continue;
    auto it = scaled.find(run.object_scale);
    if (it == scaled.end()) it = scaled.emplace(run.object_scale, StudyScene(study, run.object_scale)).first;
    for (int k = 0; k < study.frames; ++k) {
      const Eigen::Vector3d eye = Eye(study, run, it->second.object(study.object), k);
      const std::string problem = ViewpointProblem(it->second, eye);
      require(problem.empty(), "distance " + Short(run.distance) + " m at viewing angle " + Short(run.viewing_angle_deg) +
                                   " deg puts the camera at (" + Number(eye.x(), "%.2f") + ", " + Number(eye.y(), "%.2f") +
                                   ") m, " + problem + " of scene '" + scene.name + "'");
    }
  }
  return study;
}

std::vector<StudyRun> StudyRuns(const StudyConfig& study) {
  std::vector<StudyRun> runs;
  const StudySweep& s = study.sweep;
  for (double distance : s.distance) {
    for (double angle : s.viewing_angle_deg) {
      for (double noise : s.noise) {
        for (double scale : s.object_scale) {
          for (const std::string& segmenter : s.segmenter) {
            for (int seed = 1; seed <= study.seeds; ++seed) {
              StudyRun run{static_cast<int>(runs.size()), distance, angle, noise, scale, segmenter, seed};
              runs.push_back(run);
            }
          }
        }
      }
    }
  }
  return runs;
}

}  // namespace planemap
