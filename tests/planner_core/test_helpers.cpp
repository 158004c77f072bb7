#include "test_helpers.hpp"

#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace planner_core::testing {

std::string data_path(const std::string& relative) {
  return (std::filesystem::path(CTSFLEET_TEST_DATA) / relative).string();  // no chained + (GCC 12's -Warray-bounds)
}

std::shared_ptr<const Graph> grid_from_rows(const std::vector<std::string>& rows) {
  return std::make_shared<const Graph>(static_cast<int>(rows[0].size()), static_cast<int>(rows.size()), rows);
}

Instance make_instance(const std::vector<std::string>& rows, const std::vector<AgentSpec>& agents,
                       const std::vector<TaskSpec>& tasks) {
  Instance instance;
  instance.graph = grid_from_rows(rows);
  instance.source = "test";
  for (const AgentSpec& agent : agents) {
    instance.starts.push_back(instance.graph->vertex_at(agent.start));
    instance.goals.push_back(instance.graph->vertex_at(agent.goal));
  }
  for (const TaskSpec& task : tasks) instance.tasks.push_back({instance.graph->vertex_at(task.at), task.agents});
  instance.index_tasks();
  return instance;
}

namespace {

// This process's temporary folder, removed when the test program ends.
struct TemporaryFolder {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("ctsfleet-test-" + std::to_string(::getpid()));
  ~TemporaryFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

}  // namespace

std::string write_temp_file(const std::string& name, const std::string& text) {
  static TemporaryFolder folder;
  const auto& dir = folder.path;
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
  return path.string();
}

}  // namespace planner_core::testing
