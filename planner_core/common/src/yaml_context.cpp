#include "planner_core/yaml_context.hpp"

#include <filesystem>

#include "planner_core/input_file.hpp"

namespace planner_core {

void YamlContext::fail(const YAML::Node& node, const std::string& field, const std::string& problem) const {
  std::string message = file_;
  if (node.IsDefined() && node.Mark().line >= 0) message.append(":").append(std::to_string(node.Mark().line + 1));
  message.append(": ").append(field).append(": ").append(problem);
  throw InputError(message);
}

void YamlContext::only_keys(const YAML::Node& map, const std::set<std::string>& allowed,
                            const std::string& field) const {
  if (!map.IsMap()) fail(map, field, "expected a mapping");
  for (const auto& item : map) {
    const std::string key = item.first.as<std::string>();
    if (!allowed.count(key)) fail(item.first, field, "unknown key '" + key + "'");
  }
}

int YamlContext::integer(const YAML::Node& node, const std::string& field) const {
  if (!node.IsScalar()) fail(node, field, "expected an integer");
  try {
    const std::string text = node.Scalar();
    size_t used = 0;
    const long value = std::stol(text, &used);
    if (used != text.size()) throw std::invalid_argument(text);
    return static_cast<int>(value);
  } catch (const std::exception&) {
    fail(node, field, "expected an integer, got '" + node.Scalar() + "'");
  }
}

Cell YamlContext::cell(const YAML::Node& node, const std::string& field) const {
  if (!node.IsSequence() || node.size() != 2) fail(node, field, "expected [x, y]");
  return {integer(node[0], field + "[0]"), integer(node[1], field + "[1]")};
}

YAML::Node load_yaml_file(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path + ": no such file");
  require_regular_file(path, "file");
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
  }
}

}  // namespace planner_core
