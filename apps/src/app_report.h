#pragma once
// What `planemap map` and `planemap approach` share for --report: the page's files, the map's
// part of a report, and lines both printed and put in the report.
#include <string>

#include "planemap/core/plane_map.h"
#include "planemap/frontend/plane_graph.h"
#include "planemap/report/html_report.h"

namespace planemap {

// printf into a string.
std::string Printf(const char* format, ...) __attribute__((format(printf, 1, 2)));

// Before a run, so a long one does not fail at its end: the page's files from the source tree's
// web/ (three.js installed there by scripts/setup.sh) and `file` writable. Throws InputError
// naming the missing or unwritable file.
ReportAssets PrepareReport(const std::string& file);

// The map in the report: its landmarks' outlines and the trihedral corners of its graph.
void AddMapToReport(const PlaneMap& map, const PlaneGraphConfig& graph, ReportData* report);

}  // namespace planemap
