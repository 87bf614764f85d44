#pragma once
// A run as one self-contained HTML page, opened from disk with no server and no network: an
// interactive 3-D view of the plane map (plane outlines coloured by object, edges, trihedral
// corners, object centres and grasp axes) with the run's trajectories and paths, a summary, a
// table of the map's objects and the run's plots. The page (web/report.html), its viewer
// (web/report.js) and three.js (web/node_modules, installed by scripts/setup.sh) are inlined.
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "planemap/core/plane_map.h"
#include "planemap/core/tum_format.h"

namespace planemap {

// A camera trajectory, drawn through its positions.
struct ReportTrajectory {
  std::string name;
  std::string color;  // CSS colour, e.g. "#1f5fbf"
  Trajectory poses;   // world
};

// A path on the floor (z = 0 in the world): a robot's base path, footsteps, control points.
struct ReportPath {
  std::string name;
  std::string color;                    // CSS colour
  std::vector<Eigen::Vector2d> points;  // world x, y [m]
  bool dots = false;                    // markers at the points instead of a line through them ...
  double dot_size = 8.0;                // ... this wide on screen [px]
};

struct ReportPlot {
  std::string title;
  std::string svg;  // a whole <svg> element, put in the page as it is
};

struct ReportData {
  std::string title;
  std::vector<std::string> summary;  // plain text, one line each
  const PlaneMap* map = nullptr;     // none: no planes, edges or objects
  // Each landmark's outline (index: landmark id; empty: not drawn) and the map graph's trihedral
  // corners, world [m]: the frontend computes them (PlaneOutline, MapCorners).
  std::vector<std::vector<Eigen::Vector3d>> plane_outlines;
  std::vector<Eigen::Vector3d> corners;
  std::vector<ReportTrajectory> trajectories;
  std::vector<ReportPath> paths;
  std::vector<ReportPlot> plots;
};

// The files every report inlines, read once.
struct ReportAssets {
  std::string page;                                          // web/report.html
  std::vector<std::pair<std::string, std::string>> modules;  // (module name, source), dependencies first
};

// Reads the page, the viewer and three.js from `web_dir`. Throws InputError naming the first
// missing file (three.js missing: run scripts/setup.sh).
ReportAssets LoadReportAssets(const std::string& web_dir);

// Throws InputError naming `file` when it cannot be written (checked before a long run); leaves
// no file behind.
void CheckReportWritable(const std::string& file);

// Writes the page to `file`. Throws InputError naming the file when it cannot be written.
void WriteHtmlReport(const std::string& file, const ReportData& data, const ReportAssets& assets);

}  // namespace planemap
