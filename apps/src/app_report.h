#pragma once
// What the commands share: --report's page files and the map's part of a report, lines both
// printed and put in the report, and whole-file reads and writes.
#include <string>

#include "planemap/core/plane_map.h"
#include "planemap/frontend/plane_graph.h"
#include "planemap/report/html_report.h"

namespace planemap {

// A file's whole text; throws InputError naming an unreadable file.
std::string ReadText(const std::string& file);

// Writes `text` to `file` through a temporary beside it and a rename: a reader sees the old file
// or the new one, never half of it. Throws InputError naming the file.
void WriteFileAtomically(const std::string& file, const std::string& text);

// printf into a string.
std::string Printf(const char* format, ...) __attribute__((format(printf, 1, 2)));

// Before a run, so a long one does not fail at its end: the page's files from the source tree's
// web/ (three.js installed there by scripts/setup.sh) and `file` writable. Throws InputError
// naming the missing or unwritable file.
ReportAssets PrepareReport(const std::string& file);

// The map in the report: its landmarks' outlines and the trihedral corners of its graph.
void AddMapToReport(const PlaneMap& map, const PlaneGraphConfig& graph, ReportData* report);

}  // namespace planemap
