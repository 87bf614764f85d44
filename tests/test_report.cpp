// The HTML report's parts: plane outlines and the map's trihedral corners (frontend), and the page
// writer (report/): what it inlines, how it escapes text into HTML and JSON, and its errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "planemap/frontend/map_merge.h"
#include "planemap/frontend/plane_outline.h"
#include "planemap/report/html_report.h"
#include "test_support.h"

namespace planemap {
namespace {

using testing::TempDir;
using testing::ThrowsWith;

std::string ReadAll(const std::string& file) {
  std::ifstream in(file);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A 30 x 40 cm top at z = 0.3 m sampled every 5 cm, its points 2 mm above and below the plane.
PlaneLandmark NoisyTop() {
  PlaneLandmark l;
  l.plane = Plane::FromPointNormal(Eigen::Vector3d(0.0, 0.0, 0.3), Eigen::Vector3d::UnitZ());
  for (int i = 0; i <= 6; ++i) {
    for (int j = 0; j <= 8; ++j)
      l.points.emplace_back(1.0f + 0.05f * i, 0.05f * j, (i + j) % 2 ? 0.302f : 0.298f);
  }
  return l;
}

TEST(PlaneOutline, IsTheHullOfThePointsOnThePlaneCounterClockwise) {
  const std::vector<Eigen::Vector3d> outline = PlaneOutline(NoisyTop());
  ASSERT_EQ(outline.size(), 4u);  // the corners; points on the sides are not hull vertices
  for (const Eigen::Vector3d& corner : {Eigen::Vector3d(1.0, 0.0, 0.3), Eigen::Vector3d(1.3, 0.0, 0.3),
                                        Eigen::Vector3d(1.3, 0.4, 0.3), Eigen::Vector3d(1.0, 0.4, 0.3)}) {
    double nearest = 1.0;
    for (const Eigen::Vector3d& p : outline) nearest = std::min(nearest, (p - corner).norm());
    EXPECT_LT(nearest, 1e-5) << corner.transpose();
  }
  for (size_t k = 0; k < 4; ++k) {
    const Eigen::Vector3d a = outline[k], b = outline[(k + 1) % 4], c = outline[(k + 2) % 4];
    EXPECT_GT((b - a).cross(c - b).z(), 0.0) << "turns clockwise at vertex " << k + 1;
  }
}

TEST(PlaneOutline, IsEmptyForTooFewPointsOrALine) {
  PlaneLandmark l = NoisyTop();
  l.points.resize(2);
  EXPECT_TRUE(PlaneOutline(l).empty());
  l.points = {{0.0f, 0.0f, 0.3f}, {0.1f, 0.0f, 0.3f}, {0.2f, 0.0f, 0.3f}};
  EXPECT_TRUE(PlaneOutline(l).empty());
}

TEST(MapCorners, FindsTheBoxsCornersOfTheSyntheticRoom) {
  const std::vector<Eigen::Vector3d> corners = MapCorners(testing::SyntheticRoom(), PlaneGraphConfig());
  for (const Eigen::Vector3d& expected : {Eigen::Vector3d(1.35, 0.1, 0.3), Eigen::Vector3d(1.35, 0.1, 0.0)}) {
    double nearest = 1.0;
    for (const Eigen::Vector3d& c : corners) nearest = std::min(nearest, (c - expected).norm());
    EXPECT_LT(nearest, 0.001) << expected.transpose();
  }
}

// A web/ folder with a template that shows every part, and modules that need escaping.
class FakeWeb {
 public:
  FakeWeb() {
    dir_.Write("report.html",
               "<title><!--planemap:title--></title><pre><!--planemap:summary--></"
               "pre><table><!--planemap:objects--></table>"
               "<!--planemap:plots--><script type=\"application/json\" "
               "id=\"report-data\"><!--planemap:data--></script>"
               "<!--planemap:modules--><!--planemap:unknown-->");
    std::filesystem::create_directories(dir_.File("node_modules/three/build"));
    std::filesystem::create_directories(dir_.File("node_modules/three/examples/jsm/controls"));
    dir_.Write("node_modules/three/build/three.core.js", "export const tag = '</SCRIPT>';\n");
    dir_.Write("node_modules/three/build/three.module.js", "export * from './three.core.js';\n");
    dir_.Write("node_modules/three/examples/jsm/controls/OrbitControls.js",
               "export class OrbitControls {}\n");
    dir_.Write("report.js", "import * as THREE from 'three';\n");
  }
  const TempDir& dir() const { return dir_; }

 private:
  TempDir dir_;
};

TEST(HtmlReport, InlinesTheModulesAndEscapesTextIntoHtmlAndJson) {
  FakeWeb web;
  PlaneMap map = testing::SyntheticRoom();
  MapObject box = testing::BoxObject({1.5, 0.3, 0.15}, 0.0, {0.3, 0.4, 0.3}, 1.0);
  box.id = 0;
  box.label = "box</script><b>";
  box.landmarks = {testing::kBoxX, testing::kBoxY, testing::kBoxTop};
  map.objects = {box};
  ReportData data;
  data.title = "a < b";
  data.summary = {"x </script> y"};
  data.map = &map;
  for (const PlaneLandmark& l : map.landmarks) data.plane_outlines.push_back(PlaneOutline(l));
  data.paths.push_back({"path", "#000", {{0.0, 0.0}, {1.0, 0.5}}, false});
  data.plots.push_back({"a plot", "<svg xmlns='http://www.w3.org/2000/svg'></svg>"});
  const std::string file = web.dir().File("page.html");
  WriteHtmlReport(file, data, LoadReportAssets(web.dir().path()));
  const std::string page = ReadAll(file);

  EXPECT_NE(page.find("<title>a &lt; b</title>"), std::string::npos);
  EXPECT_NE(page.find("x &lt;/script&gt; y"), std::string::npos);
  EXPECT_NE(page.find("<tr data-object-id=\"0\" data-class=\"box&lt;/script&gt;&lt;b&gt;\" "
                      "data-dimensions-cm=\"30.0 40.0 30.0\""),
            std::string::npos)
      << page;
  EXPECT_NE(page.find("<figure><svg"), std::string::npos);
  EXPECT_NE(page.find("export const tag = '<\\/SCRIPT>';"),
            std::string::npos);                                        // the same string to JavaScript
  EXPECT_NE(page.find("<!--planemap:unknown-->"), std::string::npos);  // unknown parts stay
  // Only the 5 script elements end a script: the data's and the 4 modules'.
  size_t ends = 0;
  for (size_t at = page.find("</script"); at != std::string::npos; at = page.find("</script", at + 1)) ++ends;
  EXPECT_EQ(ends, 5u);
  // The data reads back as JSON, the label as it was; the path lies 1 cm above the floor.
  const std::string open = "id=\"report-data\">";
  const size_t from = page.find(open) + open.size();
  const nlohmann::json view = nlohmann::json::parse(page.substr(from, page.find("</script>", from) - from));
  EXPECT_EQ(view["objects"][0]["label"], "box</script><b>");
  EXPECT_EQ(view["planes"].size(), map.landmarks.size());
  EXPECT_EQ(view["planes"][testing::kBoxTop]["object"], 0);
  EXPECT_EQ(view["planes"][testing::kFloor]["object"], -1);
  EXPECT_DOUBLE_EQ(view["series"][0]["points"][1][2].get<double>(), 0.01);
}

TEST(HtmlReport, ErrorsNameTheFile) {
  TempDir empty;
  EXPECT_TRUE(ThrowsWith([&] { LoadReportAssets(empty.path()); }, {empty.File("report.html"), "missing"}));
  FakeWeb web;
  std::filesystem::remove(web.dir().File("node_modules/three/build/three.core.js"));
  EXPECT_TRUE(ThrowsWith([&] { LoadReportAssets(web.dir().path()); },
                         {web.dir().File("node_modules/three/build/three.core.js"), "run scripts/setup.sh"}));

  FakeWeb commented;
  commented.dir().Write("report.js", "<!-- -->\n");
  const ReportAssets assets = LoadReportAssets(commented.dir().path());
  EXPECT_TRUE(ThrowsWith([&] { WriteHtmlReport(commented.dir().File("page.html"), ReportData(), assets); },
                         {"planemap/report.js", "cannot be inlined"}));

  const std::string unwritable = empty.File("no_such_folder/page.html");
  EXPECT_TRUE(ThrowsWith([&] { CheckReportWritable(unwritable); }, {unwritable, "cannot write the report"}));
  EXPECT_TRUE(ThrowsWith([&] { WriteHtmlReport(unwritable, ReportData(), ReportAssets()); },
                         {unwritable, "cannot write"}));
  // A writable path is checked without leaving a file behind.
  CheckReportWritable(empty.File("page.html"));
  EXPECT_FALSE(std::filesystem::exists(empty.File("page.html")));
}

}  // namespace
}  // namespace planemap
