#include "planemap/apps/svg_plot.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "planemap/core/error.h"

namespace planemap {
namespace {

std::string Escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

std::string Tick(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

}  // namespace

std::string PlotSvg(const Plot& plot) {
  Eigen::Vector2d low = Eigen::Vector2d::Constant(1e300), high = Eigen::Vector2d::Constant(-1e300);
  for (const PlotSeries& s : plot.series) {
    for (const Eigen::Vector2d& p : s.points) {
      low = low.cwiseMin(p);
      high = high.cwiseMax(p);
    }
  }
  if (low.x() > high.x()) return "";
  if (!plot.equal_axes && plot.y_from_zero) low.y() = std::min(low.y(), 0.0);
  const Eigen::Vector2d span = (high - low).cwiseMax(1e-6);
  const double W = 560, H = 380, L = 64, B = 50, T = 30, R = 190;  // size and margins [px]
  double sx = (W - L - R) / span.x(), sy = (H - T - B) / span.y();
  if (plot.equal_axes) sx = sy = std::min(sx, sy);
  auto X = [&](double x) { return L + (x - low.x()) * sx; };
  auto Y = [&](double y) { return H - B - (y - low.y()) * sy; };

  std::ostringstream out;
  out << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H
      << "' font-family='sans-serif' font-size='12'>\n"
      << "<rect width='100%' height='100%' fill='white'/>\n<text x='" << L << "' y='18'>" << Escaped(plot.title) << "</text>\n"
      << "<line x1='" << L << "' y1='" << H - B << "' x2='" << W - R << "' y2='" << H - B << "' stroke='black'/>\n"
      << "<line x1='" << L << "' y1='" << T << "' x2='" << L << "' y2='" << H - B << "' stroke='black'/>\n"
      << "<text x='" << (L + W - R) / 2 << "' y='" << H - 12 << "' text-anchor='middle'>" << Escaped(plot.x_label) << "</text>\n"
      << "<text x='14' y='" << (T + H - B) / 2 << "' transform='rotate(-90 14 " << (T + H - B) / 2
      << ")' text-anchor='middle'>" << Escaped(plot.y_label) << "</text>\n";
  for (int i = 0; i <= 4; ++i) {
    const double vx = low.x() + span.x() * i / 4, vy = low.y() + span.y() * i / 4;
    out << "<text x='" << X(vx) << "' y='" << H - B + 16 << "' text-anchor='middle'>" << Tick(vx) << "</text>\n"
        << "<text x='" << L - 6 << "' y='" << Y(vy) + 4 << "' text-anchor='end'>" << Tick(vy) << "</text>\n";
  }
  int legend_lines = 0;
  for (const PlotSeries& s : plot.series) {
    if (s.line) {
      out << "<polyline fill='none' stroke='" << s.color << "' stroke-width='2'" << (s.dashed ? " stroke-dasharray='6 4'" : "")
          << " points='";
      for (const Eigen::Vector2d& p : s.points) out << X(p.x()) << ',' << Y(p.y()) << ' ';
      out << "'/>\n";
    }
    if (s.dots) {
      for (const Eigen::Vector2d& p : s.points) {
        out << "<circle cx='" << X(p.x()) << "' cy='" << Y(p.y()) << "' r='3' fill='" << s.color << "'/>\n";
      }
    }
    if (s.label.empty()) continue;
    out << "<text x='" << W - R + 10 << "' y='" << T + 16 * ++legend_lines << "' fill='" << s.color << "'>" << Escaped(s.label)
        << "</text>\n";
  }
  out << "</svg>\n";
  return out.str();
}

void WritePlotSvg(const std::string& file, const Plot& plot) {
  const std::string svg = PlotSvg(plot);
  if (svg.empty()) return;
  std::ofstream out(file);
  out << svg;
  out.close();
  if (!out) ThrowInputError(file, 0, "cannot write the plot");
}

}  // namespace planemap
