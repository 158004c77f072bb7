// YamlContext: reading user YAML with errors that name the file, the line and the field
// ("file:line: field: problem"), shared by every loader of the project.
#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>

#include "planner_core/cell.hpp"
#include "planner_core/input_error.hpp"

namespace planner_core {

class YamlContext {
 public:
  explicit YamlContext(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& field, const std::string& problem) const;
  void only_keys(const YAML::Node& map, const std::set<std::string>& allowed, const std::string& field) const;
  int integer(const YAML::Node& node, const std::string& field) const;
  Cell cell(const YAML::Node& node, const std::string& field) const;  // [x, y]

  // map[key] converted to T into `out` when present; a wrong type fails naming field.key.
  template <typename T>
  void read(const YAML::Node& map, const std::string& key, const std::string& field, T& out) const {
    const YAML::Node node = map[key];
    if (!node) return;
    try {
      out = node.as<T>();
    } catch (const YAML::Exception&) {
      fail(node, field + "." + key, "wrong type");
    }
  }

 private:
  std::string file_;
};

// `text` as an error message may echo it: at most `at_most` characters, then how long it was.
std::string cut(const std::string& text, size_t at_most = 80);

// Parses a YAML file; a syntax error becomes an InputError naming file and line.
YAML::Node load_yaml_file(const std::string& path);

}  // namespace planner_core
