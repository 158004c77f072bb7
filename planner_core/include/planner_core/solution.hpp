// Solution: a joint plan as one configuration per timestep, its cost measures, and the text
// format of FORMATS.md (compatible with LaCAM / mapf-visualizer).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "planner_core/instance.hpp"

namespace planner_core {

using Solution = std::vector<Config>;  // solution[t][agent]; solution[0] = starts
// In the rotation model (action_model.hpp) a plan also says which way each agent faces:
// headings[t][agent]. Empty in the four-move model.
using HeadingPlan = std::vector<Headings>;

// T_j: the first timestep from which agent j stays on its goal to the end (last step if it
// does not end there).
std::vector<int> arrival_times(const Solution& solution, const Config& goals);
int64_t flowtime(const Solution& solution, const Config& goals);
int makespan(const Solution& solution, const Config& goals);
// Timesteps in which an agent is anywhere but resting on its goal (LaCAM's sum of loss).
int64_t sum_of_loss(const Solution& solution, const Config& goals);

// Drops trailing timesteps in which nobody moves.
void trim_idle_tail(Solution& solution);

struct SolutionFile {
  std::vector<std::pair<std::string, std::string>> header;  // key=value lines, in order
  Solution solution;
  HeadingPlan headings;  // only when the plan is in the rotation model
  std::string value(const std::string& key) const;  // "" when absent
};

// Writes header lines, then "solution=" and one "t:(x,y),..." line per timestep; "(x,y,E)" with a
// heading letter when the file has headings.
std::string format_solution(const Graph& graph, const SolutionFile& file);
void write_solution(const std::string& path, const Graph& graph, const SolutionFile& file);

// Reads the text format, with or without headings (all lines alike). A cell that is outside the map or blocked becomes kNoVertex (the
// validator reports it). Throws InputError naming the file and line for unreadable lines.
SolutionFile read_solution(const std::string& path, const Graph& graph);

}  // namespace planner_core
