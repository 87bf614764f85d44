#include "planemap/report/html_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "planemap/core/error.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace planemap {
namespace {

// Objects take these colours in map order, in the 3-D view and the table alike.
const char* const kObjectColors[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                     "#9467bd", "#8c564b", "#e377c2", "#17becf"};

// The modules the page links, dependencies first (web/report.html's loader runs the last one):
// (name the imports resolve to, file under web/).
const std::pair<const char*, const char*> kModules[] = {
    {"three/build/three.core.js", "node_modules/three/build/three.core.js"},
    {"three/build/three.module.js", "node_modules/three/build/three.module.js"},
    {"three/examples/jsm/controls/OrbitControls.js",
     "node_modules/three/examples/jsm/controls/OrbitControls.js"},
    {"planemap/report.js", "report.js"},
};

std::string ReadText(const fs::path& file, const std::string& hint) {
  std::ifstream in(file, std::ios::binary);
  if (!in) ThrowInputError(file.string(), 0, "missing; " + hint);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// Paths on the floor are drawn this far above it, so the floor's outline does not cover them [m].
constexpr double kFloorLift = 0.01;

// Coordinates to the millimetre (directions to 1e-3): the page's size is mostly numbers.
double Mm(double x) { return std::round(x * 1e3) / 1e3; }
json Point(const Eigen::Vector3d& p) { return json::array({Mm(p.x()), Mm(p.y()), Mm(p.z())}); }

std::string Format(const char* format, double a, double b, double c) {
  char text[96];
  std::snprintf(text, sizeof(text), format, a, b, c);
  return text;
}

// The object each landmark is a face of (the first listing it), or -1.
std::map<int, int> OwnerOfLandmarks(const PlaneMap& map) {
  std::map<int, int> owner;
  for (const MapObject& o : map.objects) {
    if (o.structure) continue;
    for (int l : o.landmarks) owner.emplace(l, o.id);
  }
  return owner;
}

std::string ObjectColor(size_t index) { return kObjectColors[index % std::size(kObjectColors)]; }

// What the viewer draws (web/report.js reads it), world frame [m].
json ViewData(const ReportData& data) {
  json view = {{"planes", json::array()},
               {"edges", json::array()},
               {"corners", json::array()},
               {"objects", json::array()},
               {"series", json::array()}};
  if (data.map) {
    const std::map<int, int> owner = OwnerOfLandmarks(*data.map);
    for (size_t id = 0; id < data.plane_outlines.size(); ++id) {
      if (data.plane_outlines[id].size() < 3) continue;
      json outline = json::array();
      for (const Eigen::Vector3d& p : data.plane_outlines[id]) outline.push_back(Point(p));
      const auto it = owner.find(static_cast<int>(id));
      view["planes"].push_back(
          {{"id", id}, {"object", it == owner.end() ? -1 : it->second}, {"outline", outline}});
    }
    for (const MapEdge& e : data.map->edges)
      view["edges"].push_back({{"start", Point(e.start)}, {"end", Point(e.end)}});
    for (size_t k = 0; k < data.map->objects.size(); ++k) {
      const MapObject& o = data.map->objects[k];
      view["objects"].push_back({{"id", o.id},
                                 {"label", o.label},
                                 {"color", ObjectColor(k)},
                                 {"center", Point(o.center)},
                                 {"dimensions", Point(o.dimensions)},
                                 {"grasp_axis", o.has_grasp_axis ? Point(o.grasp_axis) : json(nullptr)}});
    }
  }
  for (const Eigen::Vector3d& c : data.corners) view["corners"].push_back(Point(c));
  for (const ReportTrajectory& t : data.trajectories) {
    json points = json::array();
    for (const StampedPose& p : t.poses) points.push_back(Point(p.T_world_camera.translation()));
    view["series"].push_back({{"name", t.name}, {"color", t.color}, {"style", "line"}, {"points", points}});
  }
  for (const ReportPath& path : data.paths) {
    json points = json::array();
    for (const Eigen::Vector2d& p : path.points)
      points.push_back(Point(Eigen::Vector3d(p.x(), p.y(), kFloorLift)));
    view["series"].push_back({{"name", path.name},
                              {"color", path.color},
                              {"style", path.dots ? "points" : "line"},
                              {"size", path.dot_size},
                              {"points", points}});
  }
  return view;
}

// One row per map object; data-* attributes are the page's stable hooks (the browser test reads
// them). A dimension only bounded from below is marked with >=.
std::string ObjectRows(const PlaneMap* map) {
  if (!map) return "";
  std::string rows;
  for (size_t k = 0; k < map->objects.size(); ++k) {
    const MapObject& o = map->objects[k];
    const Eigen::Vector3d cm = 100.0 * o.dimensions;
    std::string shown, complete;
    for (int i = 0; i < 3; ++i) {
      complete += std::string(i ? " " : "") + (o.dimension_complete[i] ? "1" : "0");
      char text[32];
      std::snprintf(text, sizeof(text), "%s%s%.1f", i ? " &times; " : "",
                    o.dimension_complete[i] ? "" : "&ge;", cm[i]);
      shown += text;
    }
    const std::string axis =
        o.has_grasp_axis ? Format("%.2f, %.2f, %.2f", o.grasp_axis.x(), o.grasp_axis.y(), o.grasp_axis.z())
                         : "none";
    rows += "<tr data-object-id=\"" + std::to_string(o.id) + "\" data-class=\"" + Escape(o.label) +
            "\" data-dimensions-cm=\"" + Format("%.1f %.1f %.1f", cm.x(), cm.y(), cm.z()) +
            "\" data-complete=\"" + complete + "\">" + "<td>" + std::to_string(o.id) +
            "</td><td><span class=\"swatch\" style=\"background:" + ObjectColor(k) + "\"></span> " +
            Escape(o.label) + "</td><td>" + shown + "</td><td>" +
            Format("%.3f, %.3f, %.3f", o.center.x(), o.center.y(), o.center.z()) + "</td><td>" + axis +
            "</td><td>" + std::to_string(o.observations) + "</td></tr>\n";
  }
  return rows;
}

std::string Plots(const std::vector<ReportPlot>& plots) {
  if (plots.empty()) return "";
  std::string html = "<h2>Plots</h2>\n<div class=\"plots\">\n";
  for (const ReportPlot& p : plots)
    html += "<figure>" + p.svg + "<figcaption>" + Escape(p.title) + "</figcaption></figure>\n";
  return html + "</div>";
}

// A module's source as the text of a <script type="text/plain">: the HTML parser ends that
// element at "</script" whatever the JavaScript means, so it is written "<\/script" (the same
// text in a JavaScript string, regular expression or comment). "<!--" would change how the
// parser reads the rest, and no module we ship has one: refuse rather than guess.
std::string ModuleScript(const std::string& name, const std::string& source) {
  std::string lower = source;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower.find("<!--") != std::string::npos)
    ThrowInputError(name, 0, "contains '<!--': cannot be inlined into a report");
  std::string escaped;
  size_t from = 0;
  for (size_t at = lower.find("</script"); at != std::string::npos; at = lower.find("</script", at + 1)) {
    escaped += source.substr(from, at + 1 - from) + "\\";
    from = at + 1;
  }
  escaped += source.substr(from);
  return "<script type=\"text/plain\" data-module=\"" + name + "\">" + escaped + "</script>\n";
}

// The page with each <!--planemap:NAME--> replaced by parts[NAME].
std::string Fill(const std::string& page, const std::map<std::string, std::string>& parts) {
  const std::string open = "<!--planemap:", close = "-->";
  std::string out;
  size_t from = 0;
  for (size_t at = page.find(open); at != std::string::npos; at = page.find(open, from)) {
    const size_t end = page.find(close, at);
    const auto part = end == std::string::npos
                          ? parts.end()
                          : parts.find(page.substr(at + open.size(), end - at - open.size()));
    if (part == parts.end()) {
      out += page.substr(from, at + open.size() - from);
      from = at + open.size();
      continue;
    }
    out += page.substr(from, at - from) + part->second;
    from = end + close.size();
  }
  return out + page.substr(from);
}

}  // namespace

ReportAssets LoadReportAssets(const std::string& web_dir) {
  const fs::path web(web_dir);
  ReportAssets assets;
  assets.page = ReadText(web / "report.html", "the report page ships in the source tree's web/");
  for (const auto& [name, file] : kModules) {
    const bool ours = std::string(file).rfind("node_modules/", 0) != 0;
    assets.modules.emplace_back(
        name,
        ReadText(web / file, ours ? "the report viewer ships in the source tree's web/"
                                  : "three.js is not installed: run scripts/setup.sh (npm ci in web/)"));
  }
  return assets;
}

void CheckReportWritable(const std::string& file) { CheckWritableFile(file, "the report"); }

void WriteHtmlReport(const std::string& file, const ReportData& data, const ReportAssets& assets) {
  std::string summary;
  for (const std::string& line : data.summary) summary += Escape(line) + "\n";
  // JSON inside <script>: "<" only occurs in strings, where \u003c means the same.
  std::string view;
  for (char c : ViewData(data).dump()) view += c == '<' ? std::string("\\u003c") : std::string(1, c);
  std::string modules;
  for (const auto& [name, source] : assets.modules) modules += ModuleScript(name, source);
  const std::string page = Fill(assets.page, {{"title", Escape(data.title)},
                                              {"summary", summary},
                                              {"objects", ObjectRows(data.map)},
                                              {"plots", Plots(data.plots)},
                                              {"data", view},
                                              {"modules", modules}});
  std::ofstream out(file, std::ios::binary);
  if (!out) ThrowInputError(file, 0, "cannot write the report (does its folder exist, may it be written?)");
  out << page;
  out.close();
  if (!out) ThrowInputError(file, 0, "cannot write the report (disk full?)");
}

}  // namespace planemap
