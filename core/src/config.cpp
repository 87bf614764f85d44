#include "planemap/core/config.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace planemap {
namespace config_detail {

std::string CheckValue(double value, Check check) {
  if (!std::isfinite(value)) return "must be a finite number";
  switch (check) {
    case Check::kAny:
      return "";
    case Check::kPositive:
      return value > 0.0 ? "" : "must be > 0";
    case Check::kNonNegative:
      return value >= 0.0 ? "" : "must be >= 0";
    case Check::kProbability:
      return value >= 0.0 && value <= 1.0 ? "" : "must be in [0, 1]";
  }
  return "";
}

std::string ShortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", value);
  return text;
}

int LineOf(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? 0 : mark.line + 1;
}

}  // namespace config_detail

using config_detail::LineOf;

bool OneOf::Allows(const std::string& value) const {
  return std::any_of(values.begin(), values.end(), [&](const char* v) { return value == v; });
}

std::string OneOf::Describe() const {
  std::string text;
  size_t i = 0;
  for (const char* v : values) {
    text += (i == 0 ? "" : i + 1 == values.size() ? " or " : ", ") + std::string(v);
    ++i;
  }
  return text;
}

YAML::Node LoadYamlFile(const std::string& file) {
  std::ifstream in = OpenInputFile(file);
  try {
    return YAML::Load(in);
  } catch (const YAML::Exception& e) {
    ThrowInputError(file, e.mark.is_null() ? 0 : e.mark.line + 1, "YAML syntax error: " + e.msg);
  }
}

void SaveYamlFile(const YAML::Node& node, const std::string& file) {
  std::ofstream out(file);
  if (!out) ThrowInputError(file, 0, "cannot open file for writing");
  YAML::Emitter emitter;
  emitter.SetDoublePrecision(15);
  emitter << node;
  out << emitter.c_str() << "\n";
  if (!out) ThrowInputError(file, 0, "write failed");
}

ConfigReader::ConfigReader(const YAML::Node& map, std::string file, std::string prefix)
    : map_(map), file_(std::move(file)), prefix_(std::move(prefix)) {}

void ConfigReader::RejectUnknownKeys() const {
  for (const auto& entry : map_) {
    // A key that is a list, a map or nothing names no setting (as<std::string> would throw an
    // error naming no file).
    if (!entry.first.IsScalar()) {
      const std::string where = prefix_.empty() ? "" : " in '" + prefix_.substr(0, prefix_.size() - 1) + "'";
      ThrowInputError(file_, LineOf(entry.first), "a key" + where + " is not a name (a list, a map or empty)");
    }
    const std::string key = entry.first.Scalar();
    if (std::find(used_.begin(), used_.end(), key) != used_.end()) continue;
    std::ostringstream known;
    for (size_t i = 0; i < used_.size(); ++i) known << (i ? ", " : "") << used_[i];
    ThrowInputError(file_, LineOf(entry.first),
                    "unknown key '" + prefix_ + key + "' (known keys: " + known.str() + ")");
  }
}

YAML::Node ConfigReader::TakeList(const char* key) {
  used_.emplace_back(key);
  const YAML::Node node = map_[key];
  if (node && !node.IsSequence()) Fail(node, key, "expects a list");
  return node;
}

void ConfigReader::Fail(const YAML::Node& node, const char* key, const std::string& what) const {
  ThrowInputError(file_, LineOf(node), "key '" + prefix_ + key + "' " + what);
}

void ConfigReader::ReadScalar(const YAML::Node& node, const char* key, double* value, Check check) {
  if (!node.IsScalar()) Fail(node, key, "expects a number");
  try {
    *value = node.as<double>();
  } catch (const YAML::Exception&) {
    Fail(node, key, "expects a number, got '" + node.Scalar() + "'");
  }
  const std::string problem = config_detail::CheckValue(*value, check);
  if (!problem.empty()) Fail(node, key, problem + ", got " + node.Scalar());
}

void ConfigReader::ReadScalar(const YAML::Node& node, const char* key, int* value, Check check) {
  if (!node.IsScalar()) Fail(node, key, "expects an integer");
  try {
    *value = node.as<int>();
  } catch (const YAML::Exception&) {
    Fail(node, key, "expects an integer, got '" + node.Scalar() + "'");
  }
  const std::string problem = config_detail::CheckValue(*value, check);
  if (!problem.empty()) Fail(node, key, problem + ", got " + node.Scalar());
}

void ConfigReader::ReadScalar(const YAML::Node& node, const char* key, bool* value, Check) {
  try {
    *value = node.as<bool>();
  } catch (const YAML::Exception&) {
    Fail(node, key, "expects true or false, got '" + (node.IsScalar() ? node.Scalar() : "?") + "'");
  }
}

void ConfigReader::ReadScalar(const YAML::Node& node, const char* key, std::string* value, Check) {
  if (!node.IsScalar()) Fail(node, key, "expects a string");
  *value = node.Scalar();
}

void ConfigReader::ReadScalar(const YAML::Node& node, const char* key, std::vector<double>* value,
                              Check check) {
  if (!node.IsSequence()) Fail(node, key, "expects a list of numbers");
  std::vector<double> values;
  for (const auto& item : node) {
    double x = 0.0;
    ReadScalar(item, key, &x, check);
    values.push_back(x);
  }
  *value = std::move(values);
}

void ConfigReader::ReadScalar(const YAML::Node& node, const char* key, std::vector<std::string>* value,
                              Check check) {
  if (!node.IsSequence()) Fail(node, key, "expects a list of strings");
  std::vector<std::string> values;
  for (const auto& item : node) {
    std::string x;
    ReadScalar(item, key, &x, check);
    values.push_back(x);
  }
  *value = std::move(values);
}

void ConfigValidator::Report(const char* key, const std::string& problem) const {
  if (!problem.empty()) throw std::invalid_argument(prefix_ + key + " " + problem);
}

}  // namespace planemap
