#pragma once
// YAML <-> config structs, in one place (STYLE.md habit 1).
//
// A config struct lists its fields once, with a range check:
//
//   struct CameraIntrinsics {
//     double fx = 525.0;  // [px]
//     template <class V> void VisitFields(V&& v) { v("fx", fx, Check::kPositive); }
//   };
//
// and that single list drives reading (unknown keys, wrong types, NaN and out-of-range values are
// errors naming the file, line and key), writing and validation of structs built in code.
// Supported field types: double, int, bool, std::string, std::vector<double>,
// std::vector<std::string>, nested structs
// that have VisitFields themselves, and std::vector of such structs (a YAML list of maps).
#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "planemap/core/error.h"

namespace planemap {

// Parses a YAML file; throws InputError naming the file (and line, for syntax errors).
YAML::Node LoadYamlFile(const std::string& file);

// Writes YAML to a file; throws InputError when the file cannot be written.
void SaveYamlFile(const YAML::Node& node, const std::string& file);

enum class Check { kAny, kPositive, kNonNegative, kProbability };

// The values a string setting may take, e.g. v("type", type, OneOf{{"huber", "cauchy"}}): reading
// another is an error naming the file, line and key and listing these.
struct OneOf {
  std::initializer_list<const char*> values;
  bool Allows(const std::string& value) const;
  std::string Describe() const;  // "huber, cauchy or none"
};

namespace config_detail {

template <typename T, typename = void>
struct IsConfigStruct : std::false_type {};
template <typename T>
struct IsConfigStruct<T, std::void_t<decltype(std::declval<T&>().VisitFields(
                             std::declval<void (*)(const char*, double&, Check)>()))>>
    : std::true_type {};

// "fx must be > 0" or an empty string when `value` passes `check`.
std::string CheckValue(double value, Check check);
int LineOf(const YAML::Node& node);

// A number as YAML would show it ("7", "0.25"), for CrossCheck messages.
std::string ShortNumber(double value);

// A config struct may also check its fields together: `std::string CrossCheck() const` returns
// what is wrong ("min_depth 7 must be below max_depth 6") or "" (ConfigReader and ConfigValidator
// call it after the fields).
template <typename T, typename = void>
struct HasCrossCheck : std::false_type {};
template <typename T>
struct HasCrossCheck<T, std::void_t<decltype(std::declval<const T&>().CrossCheck())>> : std::true_type {};

template <typename T>
struct IsStructList : std::false_type {};
template <typename T>
struct IsStructList<std::vector<T>> : IsConfigStruct<T> {};

}  // namespace config_detail

// Reads one YAML map into a config struct; keys left out keep their defaults.
class ConfigReader {
 public:
  // `file` and `prefix` (e.g. "render.noise.") only go into error messages.
  ConfigReader(const YAML::Node& map, std::string file, std::string prefix = "");

  template <typename T>
  void operator()(const char* key, T& value, Check check = Check::kAny) {
    const YAML::Node node = map_[key];
    used_.emplace_back(key);
    if (!node) return;
    if constexpr (config_detail::IsConfigStruct<T>::value) {
      if (!node.IsMap()) Fail(node, key, "expects a map of settings");
      ConfigReader child(node, file_, prefix_ + key + ".");
      value.VisitFields(child);
      child.RejectUnknownKeys();
      if constexpr (config_detail::HasCrossCheck<T>::value) {
        const std::string problem = value.CrossCheck();
        if (!problem.empty()) Fail(node, key, "is inconsistent: " + problem);
      }
    } else if constexpr (config_detail::IsStructList<T>::value) {
      if (!node.IsSequence()) Fail(node, key, "expects a list of maps");
      T items;
      for (size_t i = 0; i < node.size(); ++i) {
        if (!node[i].IsMap()) Fail(node[i], key, "expects a list of maps");
        ConfigReader child(node[i], file_, prefix_ + key + "[" + std::to_string(i) + "].");
        items.emplace_back();
        items.back().VisitFields(child);
        child.RejectUnknownKeys();
        if constexpr (config_detail::HasCrossCheck<typename T::value_type>::value) {
          const std::string problem = items.back().CrossCheck();
          if (!problem.empty()) Fail(node[i], (std::string(key) + "[" + std::to_string(i) + "]").c_str(), "is inconsistent: " + problem);
        }
      }
      value = std::move(items);
    } else {
      ReadScalar(node, key, &value, check);
    }
  }

  void operator()(const char* key, std::string& value, const OneOf& choices) {
    (*this)(key, value);
    if (!choices.Allows(value)) Fail(map_[key], key, "must be " + choices.Describe() + ", not '" + value + "'");
  }

  // A list-valued key (e.g. the objects of a scene); an empty node when absent. Throws InputError
  // when present but not a list.
  YAML::Node TakeList(const char* key);

  // Throws InputError naming the file, line and key; for checks the caller makes itself.
  [[noreturn]] void Fail(const YAML::Node& node, const char* key, const std::string& what) const;

  const std::string& file() const { return file_; }

  // Throws InputError naming the first key of the map that no field asked for.
  void RejectUnknownKeys() const;

 private:
  void ReadScalar(const YAML::Node& node, const char* key, double* value, Check check);
  void ReadScalar(const YAML::Node& node, const char* key, int* value, Check check);
  void ReadScalar(const YAML::Node& node, const char* key, bool* value, Check check);
  void ReadScalar(const YAML::Node& node, const char* key, std::string* value, Check check);
  void ReadScalar(const YAML::Node& node, const char* key, std::vector<double>* value, Check check);
  void ReadScalar(const YAML::Node& node, const char* key, std::vector<std::string>* value, Check check);

  YAML::Node map_;
  std::string file_;
  std::string prefix_;
  std::vector<std::string> used_;
};

// Writes a config struct as a YAML map.
class ConfigWriter {
 public:
  template <typename T>
  void operator()(const char* key, const T& value, Check = Check::kAny) {
    if constexpr (config_detail::IsConfigStruct<T>::value) {
      ConfigWriter child;
      T copy = value;
      copy.VisitFields(child);
      node_[key] = child.node();
    } else if constexpr (config_detail::IsStructList<T>::value) {
      YAML::Node list(YAML::NodeType::Sequence);
      for (const auto& item : value) {
        ConfigWriter child;
        child("item", item);
        list.push_back(child.node()["item"]);
      }
      node_[key] = list;
    } else {
      node_[key] = value;
    }
  }
  void operator()(const char* key, const std::string& value, const OneOf&) { (*this)(key, value); }
  const YAML::Node& node() const { return node_; }

 private:
  YAML::Node node_{YAML::NodeType::Map};
};

// Checks the ranges of a struct built in code; throws std::invalid_argument naming the field.
class ConfigValidator {
 public:
  explicit ConfigValidator(std::string prefix = "") : prefix_(std::move(prefix)) {}

  template <typename T>
  void operator()(const char* key, const T& value, Check check = Check::kAny) {
    if constexpr (config_detail::IsConfigStruct<T>::value) {
      ConfigValidator child(prefix_ + key + ".");
      T copy = value;
      copy.VisitFields(child);
      if constexpr (config_detail::HasCrossCheck<T>::value) Report(key, Inconsistent(value.CrossCheck()));
    } else if constexpr (config_detail::IsStructList<T>::value) {
      for (size_t i = 0; i < value.size(); ++i) {
        ConfigValidator child(prefix_ + key + "[" + std::to_string(i) + "].");
        auto copy = value[i];
        copy.VisitFields(child);
        if constexpr (config_detail::HasCrossCheck<typename T::value_type>::value) {
          Report((std::string(key) + "[" + std::to_string(i) + "]").c_str(), Inconsistent(value[i].CrossCheck()));
        }
      }
    } else if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      Report(key, config_detail::CheckValue(static_cast<double>(value), check));
    } else if constexpr (std::is_same_v<T, std::vector<double>>) {
      for (double x : value) Report(key, config_detail::CheckValue(x, check));
    }
  }

  void operator()(const char* key, const std::string& value, const OneOf& choices) {
    if (!choices.Allows(value)) Report(key, "must be " + choices.Describe() + ", not '" + value + "'");
  }

  // The struct's own CrossCheck, at the top level (ValidateConfig).
  template <typename T>
  void CrossCheck(const T& value) const {
    if constexpr (config_detail::HasCrossCheck<T>::value) {
      const std::string problem = value.CrossCheck();
      std::string name = prefix_;  // "render.noise." -> "render.noise "
      if (!name.empty()) name.back() = ' ';
      if (!problem.empty()) throw std::invalid_argument(name + "is inconsistent: " + problem);
    }
  }

 private:
  static std::string Inconsistent(const std::string& problem) { return problem.empty() ? "" : "is inconsistent: " + problem; }
  void Report(const char* key, const std::string& problem) const;
  std::string prefix_;
};

// Reads an already parsed YAML document into a config struct; `file` names it in errors.
template <typename Config>
Config LoadConfigNode(const YAML::Node& root, const std::string& file) {
  Config config;
  if (root.IsNull()) return config;
  if (!root.IsMap()) ThrowInputError(file, config_detail::LineOf(root), "expected a map of settings");
  ConfigReader reader(root, file);
  config.VisitFields(reader);
  reader.RejectUnknownKeys();
  if constexpr (config_detail::HasCrossCheck<Config>::value) {
    const std::string problem = config.CrossCheck();
    if (!problem.empty()) ThrowInputError(file, 0, problem);
  }
  return config;
}

// Loads a whole YAML file into a config struct (the file's top level is the struct).
template <typename Config>
Config LoadConfigFile(const std::string& file) {
  return LoadConfigNode<Config>(LoadYamlFile(file), file);
}

template <typename Config>
void ValidateConfig(const Config& config, const std::string& prefix = "") {
  ConfigValidator validator(prefix);
  Config copy = config;
  copy.VisitFields(validator);
  validator.CrossCheck(config);
}

template <typename Config>
YAML::Node ConfigToYaml(const Config& config) {
  ConfigWriter writer;
  Config copy = config;
  copy.VisitFields(writer);
  return writer.node();
}

}  // namespace planemap
