#include "app_report.h"

#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "planemap/apps/app_config.h"
#include "planemap/core/error.h"
#include "planemap/frontend/map_merge.h"
#include "planemap/frontend/plane_outline.h"

namespace planemap {

std::string ReadText(const std::string& file) {
  std::ifstream in = OpenInputFile(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void WriteFileAtomically(const std::string& file, const std::string& text) {
  const std::string temporary = file + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary);
    out << text;
    out.close();
    if (!out) ThrowInputError(temporary, 0, "cannot write");
  }
  std::error_code ec;
  std::filesystem::rename(temporary, file, ec);
  if (ec) ThrowInputError(file, 0, "cannot replace: " + ec.message());
}

std::string Printf(const char* format, ...) {
  va_list args, copy;
  va_start(args, format);
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  std::string text(n > 0 ? n : 0, '\0');
  if (n > 0) std::vsnprintf(text.data(), text.size() + 1, format, args);
  va_end(args);
  return text;
}

ReportAssets PrepareReport(const std::string& file) {
  CheckReportWritable(file);
  return LoadReportAssets(ShippedDataDir() + "/web");
}

void AddMapToReport(const PlaneMap& map, const PlaneGraphConfig& graph, ReportData* report) {
  report->map = &map;
  report->plane_outlines.clear();
  for (const PlaneLandmark& l : map.landmarks) report->plane_outlines.push_back(PlaneOutline(l));
  report->corners = MapCorners(map, graph);
}

}  // namespace planemap
