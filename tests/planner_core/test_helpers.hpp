// Helpers shared by the planner_core tests: tiny instances from strings and test data paths.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "planner_core/instance.hpp"

namespace planner_core::testing {

std::string data_path(const std::string& relative);
std::shared_ptr<const Graph> grid_from_rows(const std::vector<std::string>& rows);

struct AgentSpec {
  Cell start;
  Cell goal;
};
struct TaskSpec {
  Cell at;
  std::vector<int> agents;
};
Instance make_instance(const std::vector<std::string>& rows, const std::vector<AgentSpec>& agents,
                       const std::vector<TaskSpec>& tasks = {});

// Writes `text` to a fresh file under the test temp dir and returns its path.
std::string write_temp_file(const std::string& name, const std::string& text);

}  // namespace planner_core::testing
