#pragma once
// Plots of approach runs like the paper's Fig. 8, as SVG text: the estimated and the true position's
// distance to the reference path at each control point, and the scenario 3 approach from above.
#include <string>
#include <vector>

#include "planemap/apps/approach.h"

namespace planemap {

struct SvgPlot {
  std::string suffix;  // file name suffix, e.g. "_estimate.svg"
  std::string title;
  std::string svg;  // a whole <svg> element
};

// One series per run (its scenario's colour); the top view of the first scenario 3 run. A plot
// with nothing to draw is left out.
std::vector<SvgPlot> Fig8Plots(const std::vector<ApproachRun>& runs);

}  // namespace planemap
