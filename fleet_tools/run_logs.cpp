#include "run_logs.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace coordinator {

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

nlohmann::json read_summary(const std::string& path) {
  const nlohmann::json summary = nlohmann::json::parse(read_file(path), nullptr, /*allow_exceptions=*/false);
  return summary.is_object() ? summary : nlohmann::json::object();
}

std::string monitor_overlaps(const std::string& monitor_log_text) {
  const std::string label = "overlaps ";
  const size_t at = monitor_log_text.find(label);
  return at == std::string::npos ? "-" : std::to_string(std::atoi(monitor_log_text.c_str() + at + label.size()));
}

}  // namespace coordinator
