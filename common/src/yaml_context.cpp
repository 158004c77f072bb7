#include "planner_core/yaml_context.hpp"

#include <yaml-cpp/depthguard.h>

#include <filesystem>
#include <limits>
#include <set>

#include "planner_core/input_file.hpp"

namespace planner_core {

std::string cut(const std::string& text, size_t at_most) {
  return text.size() <= at_most ? text : text.substr(0, at_most) + "... (" + std::to_string(text.size()) + " characters)";
}

void YamlContext::fail(const YAML::Node& node, const std::string& field, const std::string& problem) const {
  std::string message = file_;
  if (node.IsDefined() && node.Mark().line >= 0) message.append(":").append(std::to_string(node.Mark().line + 1));
  message.append(": ").append(field).append(": ").append(problem);
  throw InputError(message);
}

void YamlContext::only_keys(const YAML::Node& map, const std::set<std::string>& allowed,
                            const std::string& field) const {
  if (!map.IsMap()) fail(map, field, "expected a mapping");
  std::set<std::string> seen;
  for (const auto& item : map) {
    if (!item.first.IsScalar()) fail(item.first, field, "a key that is not a plain word (a list or a mapping)");
    const std::string key = item.first.Scalar();
    if (!allowed.count(key)) fail(item.first, field, "unknown key '" + cut(key) + "'");
    // YAML forbids it, yaml-cpp keeps the first silently: the second would be ignored without a word.
    if (!seen.insert(key).second) fail(item.first, field, "key '" + key + "' given twice");
  }
}

int YamlContext::integer(const YAML::Node& node, const std::string& field) const {
  if (!node.IsScalar()) fail(node, field, "expected an integer");
  try {
    const std::string text = node.Scalar();
    size_t used = 0;
    const long long value = std::stoll(text, &used);
    if (used != text.size()) throw std::invalid_argument(text);
    if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
      fail(node, field, "'" + cut(text) + "' is out of range (an integer from " +
                            std::to_string(std::numeric_limits<int>::min()) + " to " +
                            std::to_string(std::numeric_limits<int>::max()) + ")");
    }
    return static_cast<int>(value);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception&) {
    fail(node, field, "expected an integer, got '" + cut(node.Scalar()) + "'");
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
  } catch (const YAML::DeepRecursion& e) {  // yaml-cpp calls it "bad file"
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: nested more than " +
                     std::to_string(e.depth()) + " levels deep");
  } catch (const YAML::Exception& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
  }
}

}  // namespace planner_core
