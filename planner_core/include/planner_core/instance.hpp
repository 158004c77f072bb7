// Instance: a CTS-MAPF problem (grid, agents' starts and goals, tasks shared by agents) and its loaders.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "planner_core/action_model.hpp"
#include "planner_core/graph.hpp"

namespace planner_core {

struct Task {
  Vertex at = kNoVertex;
  std::vector<int> agents;  // every listed agent must stand on `at` at least once
};

struct Instance {
  std::shared_ptr<const Graph> graph;
  Config starts;
  Config goals;
  std::vector<Task> tasks;
  std::vector<std::vector<int>> tasks_of_agent;  // agent -> task ids, ascending
  std::string source;                            // file it came from, for messages
  // How agents move (action_model.hpp); a plan in the rotation model carries headings as well.
  ActionModel actions = ActionModel::kMove4;
  Headings start_headings;  // rotation model: each agent's heading at t = 0; empty = all east

  int start_heading(int agent) const { return start_headings.empty() ? 0 : start_headings[agent]; }

  int agent_count() const { return static_cast<int>(starts.size()); }
  int task_count() const { return static_cast<int>(tasks.size()); }
  void index_tasks();  // fills tasks_of_agent from tasks
};

// CTS-MAPF YAML of FORMATS.md. The map path is relative to the YAML file.
// Throws InputError naming the file and the field or line on any problem.
Instance load_instance_yaml(const std::string& path);

// MovingAI .scen: the first `agent_count` rows as an instance with no tasks.
// `map` may name the map file itself; otherwise the map the rows name is looked up beside the
// .scen file, then in the folder `map` when given. agent_count <= 0 takes every row.
Instance load_scen(const std::string& path, int agent_count, const std::string& map = "");

// Loads by extension: .yaml/.yml or .scen (`map` as for load_scen; only for .scen).
Instance load_instance(const std::string& path, int scen_agent_count = 0, const std::string& map = "");

// Checks that every agent's start, tasks and goal are in one connected piece of the
// map (so a single-agent tour exists); throws InputError naming agent and task.
void check_reachability(const Instance& instance);

// Writes an instance as FORMATS.md YAML (quoted where YAML needs it); `map_reference` is the `map:` value.
std::string instance_to_yaml(const Instance& instance, const std::string& map_reference,
                             const std::string& comment = "");

}  // namespace planner_core
