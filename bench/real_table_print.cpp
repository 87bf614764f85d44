#include "real_table_print.h"

#include <algorithm>
#include <fstream>
#include <tuple>
#include <utility>

#include "planemap/core/error.h"

namespace planemap {
namespace {

constexpr double kCmPerM = 100.0;
constexpr double kMmPerM = 1000.0;
constexpr double kPrintedMm = 0.05;  // differences below this print as 0.0 mm: not "worse" [mm]
constexpr int kMethodWidth = 27;     // "planemap sliding window", "OpenCV RgbdICPOdometry" [characters]
constexpr int kFigureWidth = 10;     // [characters]

std::string Fixed(double value, int decimals = 2) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

// The figure cells of a row: error columns (ATE and RPE, or the first-to-last pair error), lost,
// time, frames; "-" where there is no figure.
struct Cells {
  std::string error[3];  // ATE [cm], RPE translation [cm], RPE rotation [deg]; pair: [cm], [deg], ""
  std::string lost, ms, frames;
};

Cells CellsOf(const TableGroup& group, const MethodRow& row) {
  Cells cells{{"-", "-", "-"}, "", Fixed(row.ms_per_frame, 1), std::to_string(row.frames)};
  const TrajectoryFigures& f = row.figures;
  if (group.HasAte() && f.ate_valid) {
    cells.error[0] = Fixed(kCmPerM * f.ate_rmse);
    if (f.rpe_valid) cells.error[1] = Fixed(kCmPerM * f.rpe.translation.rmse);
    if (f.rpe_valid) cells.error[2] = Fixed(f.rpe.rotation.rmse);
  } else if (group.HasPair() && f.pair) {
    cells.error[0] = Fixed(kCmPerM * f.pair->translation);
    cells.error[1] = Fixed(f.pair->rotation_deg);
    cells.error[2] = "";
  }
  cells.lost = std::to_string(row.lost) + "/" + (row.degraded ? std::to_string(*row.degraded) : "-");
  return cells;
}

// The error a row is judged by: ATE RMSE, or the pair's translation error [cm].
std::optional<double> HeadlineCm(const TableGroup& group, const MethodRow& row) {
  if (!row.failure.empty()) return std::nullopt;
  if (group.HasAte() && row.figures.ate_valid) return kCmPerM * row.figures.ate_rmse;
  if (group.HasPair() && row.figures.pair) return kCmPerM * row.figures.pair->translation;
  return std::nullopt;
}

const MethodRow* FindRow(const TableGroup& group, const std::string& method) {
  for (const MethodRow& row : group.rows) {
    if (row.method == method) return &row;
  }
  return nullptr;
}

std::string RpeText(const RpeChoice& rpe) {
  if (rpe.one_second) return "RPE over 1 s";
  return "RPE over " + Fixed(rpe.delta, 3) + " s = " + std::to_string(rpe.steps) + " frame step" +
         (rpe.steps > 1 ? "s" : "") + " (*)";
}

std::string PairText(const GroundTruthPairing& p) {
  if (!p.widened) return "2 frames with ground truth";
  return "2 frames with ground truth only within " + Fixed(p.max_gap, 2) + " s (a frame is " +
         Fixed(1000 * p.largest_offset, 0) + " ms from its nearest ground-truth pose)";
}

std::string GroupTitle(const TableGroup& g) {
  if (g.stride == 0) return g.sequence + ": not run: " + g.skipped;  // the sequence could not be opened
  std::string title = g.sequence + ", stride " + std::to_string(g.stride) + ": ";
  if (!g.skipped.empty()) return title + "skipped: " + g.skipped;
  title += std::to_string(g.strided_frames) + " of " + std::to_string(g.sequence_frames) + " frames, " +
           Fixed(g.step, 3) + " s apart; camera " + g.camera + "; ";
  if (g.HasAte()) return title + RpeText(g.rpe) + " (pairs within " + Fixed(g.rpe.tolerance, 3) + " s)";
  if (g.HasPair())
    return title + PairText(g.groundtruth) + ": PAIR = first-to-last relative pose error, no ATE / RPE";
  return title + "only " + std::to_string(g.groundtruth.frames) +
         " frame(s) with a ground-truth pose within " + Fixed(g.groundtruth.max_gap, 3) +
         " s: no error figures";
}

std::vector<std::string> Footnotes(const std::vector<TableGroup>& groups) {
  bool steps = false, span = false;
  for (const TableGroup& g : groups) {
    if (!g.skipped.empty() || !g.HasAte() || g.rpe.one_second) continue;
    (g.rpe.no_pair_within ? span : steps) = true;
  }
  std::vector<std::string> notes;
  if (steps) {
    notes.push_back(
        "(*) no whole number of frame steps at this stride comes within 5 % of 1 s: the RPE's delta is the "
        "whole "
        "number of steps nearest 1 s (1.5 steps rounds down; one step when frames are more than 1 s apart).");
  }
  if (span) notes.push_back("(*) no two frames are about 1 s apart: the RPE's delta is one frame step.");
  return notes;
}

// A group's summary cells: the best peer's error and name, tracking's, their ratio, refine's difference.
struct SummaryLine {
  std::string peer = "-", tracking = "-", ratio = "-", refine = "-";
};

SummaryLine Summarise(const TableGroup& g) {
  SummaryLine line;
  const MethodRow* best = nullptr;
  std::optional<double> best_cm;
  for (const MethodRow& row : g.rows) {
    const std::optional<double> cm = HeadlineCm(g, row);
    if (row.is_peer && cm && (!best_cm || *cm < *best_cm)) std::tie(best, best_cm) = std::make_pair(&row, cm);
  }
  const MethodRow* tracking = FindRow(g, "planemap tracking");
  const MethodRow* refine = FindRow(g, "planemap --refine");
  const std::optional<double> tracking_cm = tracking ? HeadlineCm(g, *tracking) : std::nullopt;
  const std::optional<double> refine_cm = refine ? HeadlineCm(g, *refine) : std::nullopt;
  if (best) line.peer = Fixed(*best_cm) + " (" + best->method.substr(best->method.find(' ') + 1) + ")";
  if (tracking_cm) line.tracking = Fixed(*tracking_cm);
  if (best && tracking_cm && *best_cm > 0.0) line.ratio = Fixed(*tracking_cm / *best_cm);
  if (tracking_cm && refine_cm) {
    const double mm = (*refine_cm - *tracking_cm) * kMmPerM / kCmPerM;
    if (mm >= kPrintedMm) {
      line.refine = "worse by " + Fixed(mm, 1) + " mm";
    } else {
      line.refine = mm <= -kPrintedMm ? "not worse (" + Fixed(-mm, 1) + " mm better)"
                                      : "not worse (the same to 0.1 mm)";
    }
  }
  return line;
}

std::string SummaryName(const TableGroup& g) { return g.sequence + (g.HasPair() ? " (PAIR)" : ""); }

void PrintTextRow(const TableGroup& group, const MethodRow& row, std::FILE* out) {
  if (!row.failure.empty()) {
    std::fprintf(out, "  %-*s FAILED: %s\n", kMethodWidth, row.method.c_str(), row.failure.c_str());
    return;
  }
  const Cells c = CellsOf(group, row);
  std::fprintf(out, "  %-*s %*s %*s %*s %*s %*s %*s\n", kMethodWidth, row.method.c_str(), kFigureWidth,
               c.error[0].c_str(), kFigureWidth, c.error[1].c_str(), kFigureWidth, c.error[2].c_str(),
               kFigureWidth, c.lost.c_str(), kFigureWidth, c.ms.c_str(), kFigureWidth, c.frames.c_str());
}

void PrintTextColumns(const TableGroup& g, std::FILE* out) {
  const char* e0 = g.HasPair() ? "PAIR cm" : "ATE cm";
  const char* e1 = g.HasPair() ? "PAIR deg" : "RPE cm";
  const char* e2 = g.HasPair() ? "" : "RPE deg";
  std::fprintf(out, "  %-*s %*s %*s %*s %*s %*s %*s\n", kMethodWidth, "method", kFigureWidth, e0,
               kFigureWidth, e1, kFigureWidth, e2, kFigureWidth, "lost/degr", kFigureWidth, "ms/frame",
               kFigureWidth, "frames");
}

std::string MarkdownErrorCell(const TableGroup& g, const std::string& cell, int column) {
  if (cell == "-" || cell.empty()) return cell.empty() ? "" : "-";
  if (g.HasPair()) return cell + " (pair)";
  return (column > 0 && !g.rpe.one_second) ? cell + " (*)" : cell;
}

}  // namespace

std::vector<std::string> TableHeaderLines(const std::string& data_dir, double max_time_gap) {
  return {
      "Real-data table (issue 54): planemap map --refine and OpenCV's rgbd odometry (frame to frame) on " +
          data_dir,
      "ATE: RMSE of the positions after a rigid alignment (TUM evaluate_ate). RPE: RMSE of the relative "
      "motion error over delta "
      "(TUM evaluate_rpe), delta = 1 s where a whole number of frame steps lies within 5 % of it (else see "
      "(*)), pose pairs "
      "within half a frame step of it. Poses pair with ground truth within " +
          Fixed(max_time_gap, 3) + " s.",
      "PAIR (fewer than 3 frames with ground truth): the error of the first-to-last relative pose, "
      "translation [cm] and "
      "rotation [deg].",
      "lost/degr: planemap: frames tracking.csv marks lost / degraded; OpenCV: frames compute() failed on "
      "(the previous pose "
      "kept) / -.",
      "ms/frame: median. planemap tracking: frontend + tracking; sliding window: + the window's update; "
      "refine: tracking's "
      "median + the batch's solve seconds (refine: line, covariances not counted) / frames. OpenCV: "
      "prepareFrameCache + "
      "compute, one thread (cv::setNumThreads(1)); planemap runs as a user runs it (its own threads).",
  };
}

void PrintTextTable(const std::vector<TableGroup>& groups, std::FILE* out) {
  for (const TableGroup& g : groups) {
    std::fprintf(out, "\n%s\n", GroupTitle(g).c_str());
    if (!g.skipped.empty()) continue;
    PrintTextColumns(g, out);
    for (const MethodRow& row : g.rows) PrintTextRow(g, row, out);
  }
  for (const std::string& note : Footnotes(groups)) std::fprintf(out, "%s\n", note.c_str());
}

void PrintMarkdownTable(const std::vector<TableGroup>& groups, std::FILE* out) {
  std::fprintf(out,
               "\n| sequence | stride | method | ATE [cm] | RPE [cm] | RPE [deg] | lost / degraded | ms / "
               "frame | frames |\n");
  std::fprintf(out, "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  for (const TableGroup& g : groups) {
    if (!g.skipped.empty()) {
      std::fprintf(out, "| %s | %d | skipped: %s | | | | | | |\n", g.sequence.c_str(), g.stride,
                   g.skipped.c_str());
      continue;
    }
    for (const MethodRow& row : g.rows) {
      if (!row.failure.empty()) {
        std::fprintf(out, "| %s | %d | %s | failed: %s | | | | | |\n", g.sequence.c_str(), g.stride,
                     row.method.c_str(), row.failure.c_str());
        continue;
      }
      const Cells c = CellsOf(g, row);
      // A pair's two errors go to the RPE columns: it is a relative pose error, and there is no ATE.
      const std::string ate = g.HasPair() ? "-" : MarkdownErrorCell(g, c.error[0], 0);
      const std::string rpe_t = MarkdownErrorCell(g, g.HasPair() ? c.error[0] : c.error[1], 1);
      const std::string rpe_r = MarkdownErrorCell(g, g.HasPair() ? c.error[1] : c.error[2], 2);
      std::fprintf(out, "| %s | %d | %s | %s | %s | %s | %s | %s | %s |\n", g.sequence.c_str(), g.stride,
                   row.method.c_str(), ate.c_str(), rpe_t.c_str(), rpe_r.c_str(), c.lost.c_str(),
                   c.ms.c_str(), c.frames.c_str());
    }
  }
  std::fprintf(
      out,
      "\n(pair): fewer than 3 frames with ground truth; the first-to-last relative pose error, no ATE.\n");
  for (const std::string& note : Footnotes(groups)) std::fprintf(out, "%s\n", note.c_str());
  std::fprintf(out, "\nFrames, cameras and RPE per run:\n");
  for (const TableGroup& g : groups) std::fprintf(out, "- %s\n", GroupTitle(g).c_str());
}

void PrintSummary(const std::vector<TableGroup>& groups, bool markdown, std::FILE* out) {
  std::fprintf(
      out,
      "\nSummary: error = ATE RMSE [cm] (PAIR: first-to-last translation error [cm]); ratio = planemap "
      "tracking / "
      "best OpenCV peer (below 1: planemap better); refine - tracking [mm] (above 0: refine worse)\n");
  int name_width = static_cast<int>(std::string("sequence").size());
  for (const TableGroup& g : groups)
    name_width = std::max(name_width, static_cast<int>(SummaryName(g).size()));
  if (markdown) {
    std::fprintf(out,
                 "\n| sequence | stride | best OpenCV peer [cm] | planemap tracking [cm] | ratio | refine - "
                 "tracking |\n");
    std::fprintf(out, "| --- | ---: | --- | ---: | ---: | --- |\n");
  } else {
    std::fprintf(out, "  %-*s %6s  %-30s %9s %7s  %s\n", name_width, "sequence", "stride", "best OpenCV peer",
                 "tracking", "ratio", "refine - tracking");
  }
  for (const TableGroup& g : groups) {
    if (!g.skipped.empty()) continue;
    const SummaryLine s = Summarise(g);
    if (markdown) {
      std::fprintf(out, "| %s | %d | %s | %s | %s | %s |\n", SummaryName(g).c_str(), g.stride, s.peer.c_str(),
                   s.tracking.c_str(), s.ratio.c_str(), s.refine.c_str());
    } else {
      std::fprintf(out, "  %-*s %6d  %-30s %9s %7s  %s\n", name_width, SummaryName(g).c_str(), g.stride,
                   s.peer.c_str(), s.tracking.c_str(), s.ratio.c_str(), s.refine.c_str());
    }
  }
}

void WriteTableCsv(const std::vector<TableGroup>& groups, const std::string& file) {
  std::ofstream csv(file);
  if (!csv) ThrowInputError(file, 0, "cannot write the CSV (--csv)");
  csv << "sequence,stride,method,metric,value,unit\n";
  for (const TableGroup& g : groups) {
    const auto put = [&](const std::string& method, const char* metric, double value, const char* unit) {
      csv << g.sequence << ',' << g.stride << ',' << method << ',' << metric << ',' << value << ',' << unit
          << '\n';
    };
    if (!g.skipped.empty()) put("-", "skipped", 1, "flag");
    for (const MethodRow& row : g.rows) {
      if (!row.failure.empty()) {
        put(row.method, "failed", 1, "flag");
        continue;
      }
      const TrajectoryFigures& f = row.figures;
      if (g.HasAte() && f.ate_valid) put(row.method, "ate_rmse", kCmPerM * f.ate_rmse, "cm");
      if (g.HasAte() && f.rpe_valid) {
        put(row.method, "rpe_translation_rmse", kCmPerM * f.rpe.translation.rmse, "cm");
        put(row.method, "rpe_rotation_rmse", f.rpe.rotation.rmse, "deg");
        put(row.method, "rpe_delta", f.rpe.delta, "s");
      }
      if (g.HasPair() && f.pair) {
        put(row.method, "pair_translation", kCmPerM * f.pair->translation, "cm");
        put(row.method, "pair_rotation", f.pair->rotation_deg, "deg");
      }
      put(row.method, "lost", row.lost, "frames");
      if (row.degraded) put(row.method, "degraded", *row.degraded, "frames");
      put(row.method, "ms_per_frame_median", row.ms_per_frame, "ms");
      put(row.method, "frames_used", row.frames, "frames");
    }
  }
  if (!csv) ThrowInputError(file, 0, "write failed");
}

}  // namespace planemap
