#include "planemap/core/tum_format.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <tuple>

#include "planemap/core/error.h"

namespace planemap {
namespace {

// Splits a line into whitespace-separated tokens; empty for blank and '#' comment lines.
std::vector<std::string> Tokens(const std::string& line) {
  std::vector<std::string> tokens;
  std::istringstream in(line);
  std::string token;
  while (in >> token) {
    if (tokens.empty() && token[0] == '#') return {};
    tokens.push_back(token);
  }
  return tokens;
}

bool ParseDouble(const std::string& token, double* value) {
  errno = 0;
  char* end = nullptr;
  *value = std::strtod(token.c_str(), &end);
  return errno == 0 && end == token.c_str() + token.size() && std::isfinite(*value);
}

std::ofstream CreateOrThrow(const std::string& file) {
  std::ofstream out(file);
  if (!out) ThrowInputError(file, 0, "cannot open file for writing");
  out.precision(17);
  return out;
}

}  // namespace

std::string FormatStamp(double stamp) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6f", stamp);
  return buffer;
}

std::string FormatTumPose(const StampedPose& pose) {
  const Eigen::Vector3d& t = pose.T_world_camera.translation();
  const Eigen::Quaterniond q(pose.T_world_camera.linear());
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), "%s %.9f %.9f %.9f %.9f %.9f %.9f %.9f", FormatStamp(pose.stamp).c_str(),
                t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  return buffer;
}

std::vector<StampedFile> ReadFileList(const std::string& file) {
  std::ifstream in = OpenInputFile(file);
  std::vector<StampedFile> entries;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const std::vector<std::string> tokens = Tokens(line);
    if (tokens.empty()) continue;
    StampedFile entry;
    entry.line = line_no;
    if (tokens.size() != 2 || !ParseDouble(tokens[0], &entry.stamp)) {
      ThrowInputError(file, line_no, "expected 'timestamp filename', got '" + line + "'");
    }
    if (!entries.empty() && entry.stamp < entries.back().stamp) {
      ThrowInputError(file, line_no, "timestamp " + tokens[0] + " goes back in time");
    }
    entry.path = tokens[1];
    entries.push_back(std::move(entry));
  }
  return entries;
}

void WriteFileList(const std::string& file, const std::string& header,
                   const std::vector<StampedFile>& entries) {
  std::ofstream out = CreateOrThrow(file);
  out << header;
  for (const StampedFile& entry : entries) out << FormatStamp(entry.stamp) << ' ' << entry.path << '\n';
  if (!out) ThrowInputError(file, 0, "write failed");
}

Trajectory ReadTumTrajectory(const std::string& file) {
  std::ifstream in = OpenInputFile(file);
  Trajectory trajectory;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const std::vector<std::string> tokens = Tokens(line);
    if (tokens.empty()) continue;
    double v[8];
    bool ok = tokens.size() == 8;
    for (size_t i = 0; ok && i < 8; ++i) ok = ParseDouble(tokens[i], &v[i]);
    if (!ok) {
      ThrowInputError(file, line_no,
                      "expected 8 finite numbers 'timestamp tx ty tz qx qy qz qw', got '" + line + "'");
    }
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3) {
      ThrowInputError(file, line_no, "quaternion norm " + std::to_string(q.norm()) + " is not 1");
    }
    if (!trajectory.empty() && v[0] < trajectory.back().stamp) {
      ThrowInputError(file, line_no, "timestamp " + tokens[0] + " goes back in time");
    }
    trajectory.push_back({v[0], MakePose(q, Eigen::Vector3d(v[1], v[2], v[3]))});
  }
  return trajectory;
}

void WriteTumTrajectory(const std::string& file, const Trajectory& trajectory) {
  std::ofstream out = CreateOrThrow(file);
  out << "# timestamp tx ty tz qx qy qz qw\n";
  for (const StampedPose& pose : trajectory) out << FormatTumPose(pose) << '\n';
  if (!out) ThrowInputError(file, 0, "write failed");
}

std::vector<std::pair<size_t, size_t>> AssociateStamps(const std::vector<double>& a,
                                                       const std::vector<double>& b, double max_gap) {
  // Candidates: every pair within max_gap (b is scanned from the first stamp >= a_i - max_gap).
  std::vector<std::tuple<double, size_t, size_t>> candidates;
  std::vector<size_t> b_order(b.size());
  for (size_t j = 0; j < b.size(); ++j) b_order[j] = j;
  std::sort(b_order.begin(), b_order.end(), [&](size_t x, size_t y) { return b[x] < b[y]; });
  for (size_t i = 0; i < a.size(); ++i) {
    auto first = std::lower_bound(b_order.begin(), b_order.end(), a[i] - max_gap,
                                  [&](size_t j, double value) { return b[j] < value; });
    for (auto it = first; it != b_order.end() && b[*it] <= a[i] + max_gap; ++it) {
      const double gap = std::abs(a[i] - b[*it]);
      if (gap < max_gap) candidates.emplace_back(gap, i, *it);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> a_used(a.size(), false), b_used(b.size(), false);
  std::vector<std::pair<size_t, size_t>> pairs;
  for (const auto& [gap, i, j] : candidates) {
    if (a_used[i] || b_used[j]) continue;
    a_used[i] = b_used[j] = true;
    pairs.emplace_back(i, j);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::optional<Pose3> PoseAt(const Trajectory& trajectory, double stamp, double max_gap) {
  if (trajectory.empty()) return std::nullopt;
  auto after = std::lower_bound(trajectory.begin(), trajectory.end(), stamp,
                                [](const StampedPose& p, double s) { return p.stamp < s; });
  if (after != trajectory.end() && after->stamp == stamp) return after->T_world_camera;
  if (after != trajectory.begin() && after != trajectory.end()) {
    const StampedPose& before = *(after - 1);
    const double s = (stamp - before.stamp) / (after->stamp - before.stamp);
    // Interpolate only across a gap short enough that the motion between the two is smooth.
    if (after->stamp - before.stamp <= 2.0 * max_gap) {
      return Interpolate(before.T_world_camera, after->T_world_camera, s);
    }
  }
  const StampedPose* nearest = nullptr;
  if (after != trajectory.end()) nearest = &*after;
  if (after != trajectory.begin() &&
      (nearest == nullptr || stamp - (after - 1)->stamp < nearest->stamp - stamp)) {
    nearest = &*(after - 1);
  }
  if (std::abs(nearest->stamp - stamp) <= max_gap) return nearest->T_world_camera;
  return std::nullopt;
}

}  // namespace planemap
