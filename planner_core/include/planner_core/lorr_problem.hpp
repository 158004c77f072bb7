// A problem of the League of Robot Runners (LoRR, MAPF-Competition/Start-Kit), read as the league
// writes it: a JSON file naming a map (MovingAI layout, LoRR symbols), an agent file (a count, then
// one linearised location per line: row * width + column) and a task file (a count, then a task per
// line: one location in the 2023 rounds, several errands in order from 2024), with the team size,
// how many tasks are revealed per agent and the 2023 rounds' assignment strategy. Paths are relative
// to the JSON file. Format: docs/FORMATS.md, "League of Robot Runners problems".
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "planner_core/graph.hpp"

namespace planner_core {

enum class TaskAssignment {
  kRoundRobin,  // task k goes to agent k mod teamSize, in the task file's order (2023 "roundrobin")
  kGreedy,      // a revealed task goes to the nearest free agent (2023 "greedy")
};

struct LorrProblem {
  std::string source;                         // the problem's JSON file
  std::shared_ptr<const Graph> graph;
  std::vector<Vertex> starts;                 // teamSize of them
  std::vector<std::vector<Vertex>> tasks;     // each task's errands, in order
  double tasks_revealed_per_agent = 1;        // numTasksReveal
  TaskAssignment assignment = TaskAssignment::kRoundRobin;
};

// Throws InputError naming the file, and the line or the JSON key, of the first fault: a file that
// is missing or not a regular file, a count that does not match its lines, a location off the map
// or on a wall, two agents on one cell, fewer agents in the file than the team, a start or errand
// that cannot be reached from the first agent's start.
LorrProblem load_lorr_problem(const std::string& path);

}  // namespace planner_core
