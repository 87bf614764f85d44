#pragma once
// Every setting of the planemap tool in one tree; configs/default.yaml mirrors its defaults.
#include <string>

#include "planemap/backend/backend_config.h"
#include "planemap/core/config.h"
#include "planemap/core/trajectory_eval.h"
#include "planemap/frontend/frontend.h"
#include "planemap/frontend/map_merge.h"
#include "planemap/frontend/tracker.h"
#include "planemap/io/tum_sequence.h"
#include "planemap/nav/grasp.h"
#include "planemap/nav/mission.h"
#include "planemap/nav/odometry_calibration.h"
#include "planemap/nav/planner.h"
#include "planemap/nav/search.h"
#include "planemap/nav/simulated_humanoid.h"
#include "planemap/pipeline/mapper.h"
#include "planemap/sim/virtual_camera.h"

namespace planemap {

struct AppConfig {
  DatasetConfig dataset;
  sim::RenderConfig render;
  FrontendConfig frontend;
  TrackingConfig tracking;
  MapMergeConfig merge;
  BackendConfig backend;
  EvalConfig eval;
  nav::HumanoidConfig humanoid;  // the simulated robot of `planemap approach`
  nav::PlannerConfig planner;
  nav::GraspConfig grasp;
  nav::MissionConfig mission;
  nav::SearchConfig search;  // looking again when the target is not mapped
  nav::OdometryCalibrationConfig odometry_calibration;  // the gait's bias, learnt while walking

  template <class V>
  void VisitFields(V&& v) {
    v("dataset", dataset);
    v("render", render);
    v("frontend", frontend);
    v("tracking", tracking);
    v("merge", merge);
    v("backend", backend);
    v("eval", eval);
    v("humanoid", humanoid);
    v("planner", planner);
    v("grasp", grasp);
    v("mission", mission);
    v("search", search);
    v("odometry_calibration", odometry_calibration);
  }

  // The live pipeline's sections.
  MapperConfig mapper() const { return {frontend, tracking, backend, merge}; }
};

// The folder holding the files the tool ships (configs/, web/): <prefix>/share/planemap beside an
// installed tool (<prefix>/bin/planemap), else the source tree the tool was built from.
std::string ShippedDataDir();

// Finds a file shipped in configs/: `path` itself when it exists, else the same path under the
// shipped configs/ (so the tool runs from any folder). Returns `path` unchanged if neither.
std::string ResolveConfigPath(const std::string& path);

}  // namespace planemap
