#pragma once
// Line and scatter plots as standalone SVG text, for the commands' figures (no plotting library
// on Debian does SVG from C++; the format is a few lines of text).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace planemap {

struct PlotSeries {
  std::string color;   // any SVG colour
  std::string label;   // legend text; empty: not in the legend
  std::vector<Eigen::Vector2d> points;
  bool line = true;    // join the points
  bool dots = false;   // mark each point
  bool dashed = false;
};

struct Plot {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  bool equal_axes = false;  // one unit is as long on both axes (maps seen from above)
  bool y_from_zero = true;  // the y axis starts at 0 (errors); ignored with equal_axes
};

// The plot as an SVG document; empty when no series has a point.
std::string PlotSvg(const Plot& plot);

// Writes PlotSvg to `file`; throws InputError naming the file when it cannot. Nothing is written
// for an empty plot.
void WritePlotSvg(const std::string& file, const Plot& plot);

}  // namespace planemap
