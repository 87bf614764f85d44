#pragma once
// What study.cpp (the runs) and study_load.cpp (the study file) share.
#include <string>

#include <Eigen/Core>

#include "planemap/apps/study.h"

namespace planemap::study_internal {

// `value` printed with `format`; empty for NaN.
std::string Number(double value, const char* format = "%.4f");
// `value` in up to 10 significant digits, as the CSV holds swept values.
std::string Short(double value);

// Camera position of frame `k` of a run: on a circle around the object at the run's distance.
Eigen::Vector3d Eye(const StudyConfig& study, const StudyRun& run, const sim::SceneObject& object, int k);

}  // namespace planemap::study_internal
