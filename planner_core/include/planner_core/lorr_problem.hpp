// A problem of the League of Robot Runners (LoRR, MAPF-Competition/Start-Kit), read as the league
// writes it: a JSON file naming a map (MovingAI layout, LoRR symbols), an agent file (a count, then
// one linearised location per line: row * width + column) and a task file (a count, then a task per
// line: one location in the 2023 rounds, several errands in order from 2024; lines starting with
// '#' are comments, as the 2026 files have), with the team size, how many tasks are revealed per
// agent (a pool of numTasksReveal x teamSize from 2024), the 2023 rounds' assignment strategy, and
// the 2026 rules' execution settings (agentCounter, agentSize, delayConfig). Paths are relative to
// the JSON file. Format: docs/FORMATS.md, "League of Robot Runners problems".
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "planner_core/graph.hpp"

namespace planner_core {

enum class TaskAssignment {
  kRoundRobin,  // task k goes to agent k mod teamSize, in the task file's order (2023 "roundrobin")
  // A pool of numTasksReveal x teamSize revealed tasks; an agent without a task takes the one whose
  // first errand is nearest (2023 "greedy").
  kGreedy,
  // No strategy named (2024 on): the system schedules a pool of numTasksReveal x teamSize revealed
  // tasks as it sees fit (task_board.hpp: TaskScheduler).
  kPool,
};

// How the league's 2026 simulator delays robots (delayConfig): at each tick every robot not delayed
// is delayed with probability p (bernoulli), or a Poisson number of events with rate teamSize x p
// falls on such robots (poisson); a delay lasts a number of ticks in [min_ticks, max_ticks], drawn
// uniformly or from a normal distribution (mean and spread as shares of that range), clamped.
struct LeagueDelays {
  enum class Events { kBernoulli, kPoisson };
  enum class Durations { kUniform, kGaussian };
  unsigned seed = 0;
  int min_ticks = 1;
  int max_ticks = 1;
  Events events = Events::kBernoulli;
  double probability = 0;           // pDelay
  Durations durations = Durations::kUniform;
  double gauss_mean_share = 0.5;    // gaussMeanRatio
  double gauss_spread_share = 0.2;  // gaussStdRatio
};

struct LorrProblem {
  std::string source;                         // the problem's JSON file
  std::shared_ptr<const Graph> graph;
  std::vector<Vertex> starts;                 // teamSize of them
  std::vector<std::vector<Vertex>> tasks;     // each task's errands, in order
  double tasks_revealed_per_agent = 1;        // numTasksReveal
  TaskAssignment assignment = TaskAssignment::kRoundRobin;
  std::string version;                        // "version" ("2026 LoRR"); "" in the 2023 files
  int ticks_per_action = 1;                   // agentCounter: ticks a forward move or a turn takes
  double agent_size = 1;                      // agentSize: the safety square's side, in cells
  std::optional<LeagueDelays> delays;         // delayConfig; none in the 2023 and 2024 files
};

// Throws InputError naming the file, and the line or the JSON key, of the first fault: a file that
// is missing or not a regular file, a count that does not match its lines, a location off the map
// or on a wall, two agents on one cell, fewer agents in the file than the team, a start or errand
// that cannot be reached from the first agent's start, a delayConfig key missing, of the wrong type
// or out of range (a negative delay, p outside [0, 1], an unknown model).
LorrProblem load_lorr_problem(const std::string& path);

// A delayConfig alone: a JSON file that is the object itself, or a problem holding one under
// "delayConfig" (its other keys not read). Throws InputError naming the file and key, as above.
LeagueDelays load_delay_config(const std::string& path);

}  // namespace planner_core
