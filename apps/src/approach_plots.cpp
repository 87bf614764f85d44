#include "approach_plots.h"

#include <algorithm>

#include "planemap/apps/svg_plot.h"

namespace planemap {

std::vector<SvgPlot> Fig8Plots(const std::vector<ApproachRun>& runs) {
  const char* colors[] = {"", "red", "green", "blue"};
  std::vector<PlotSeries> left, middle;
  for (const ApproachRun& r : runs) {
    PlotSeries e{colors[r.scenario], "scenario " + std::to_string(r.scenario), {}, false, true}, t = e;
    for (size_t i = 0; i < r.stops.size(); ++i) {
      e.points.emplace_back(i + 1, 100 * r.stops[i].record.distance_to_path);
      t.points.emplace_back(i + 1, 100 * r.stops[i].truth_to_path);
    }
    left.push_back(e);
    middle.push_back(t);
  }
  std::vector<SvgPlot> plots;
  const auto add = [&](const std::string& suffix, const std::string& title, const std::string& x_label,
                       const std::string& y_label, const std::vector<PlotSeries>& series, bool equal_axes) {
    std::string svg = PlotSvg({title, x_label, y_label, series, equal_axes});
    if (!svg.empty()) plots.push_back({suffix, title, std::move(svg)});
  };
  add("_estimate.svg", "Estimated position to the reference path (Fig. 8 left)", "control point",
      "distance [cm]", left, false);
  add("_truth.svg", "True position to the reference path (Fig. 8 middle)", "control point", "distance [cm]",
      middle, false);
  const auto third =
      std::find_if(runs.begin(), runs.end(), [](const ApproachRun& r) { return r.scenario == 3; });
  if (third != runs.end()) {
    PlotSeries ref{"gray", "reference path", {}}, truth{"blue", "true path", {}}, est{"orange", "estimated path", {}};
    for (const nav::Pose2& p : third->reference) ref.points.push_back(p.Position());
    for (const nav::Pose2& p : third->truth_path) truth.points.push_back(p.Position());
    for (const nav::Pose2& p : third->estimate_path) est.points.push_back(p.Position());
    PlotSeries goal{"black", "true pre-grasp pose", {third->pregrasp_true.Position()}, false, true};
    add("_approach.svg", "Scenario 3 approach, seen from above (Fig. 8 right)", "x [m]", "y [m]",
        {ref, truth, est, goal}, true);
  }
  return plots;
}

}  // namespace planemap
