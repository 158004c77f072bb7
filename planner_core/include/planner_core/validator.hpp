// Validator: checks a joint plan against an instance by every rule of FORMATS.md and reports
// every violation with its timestep and agents. The one checker used by the CLI, the
// benchmarks, the tests and (later) the coordinator before a plan goes to robots.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "planner_core/solution.hpp"

namespace planner_core {

struct Violation {
  enum class Kind {
    kEmpty,           // no timesteps at all
    kAgentCount,      // a timestep lists the wrong number of agents
    kWrongStart,      // t = 0 is not the agent's start
    kBlockedCell,     // outside the map or on a blocked cell
    kJump,            // a move to a cell that is not a neighbour
    kVertexConflict,  // two agents on one cell
    kSwapConflict,    // two agents swap cells in one step
    kNotOnGoal,       // the agent does not end on its goal
    kTaskMissed,      // a task not visited by one of its agents before it settles on its goal
    kRotation,        // agents moving in a cycle in one step (only with ValidationOptions::forbid_rotations)
    kHeading,         // rotation model: a heading missing, not 0..3, or not the start heading at t = 0
    kAction,          // rotation model: a step that is not forward, a quarter turn or a wait
  };
  Kind kind;
  int time = -1;
  int agent = -1;
  int other = -1;  // second agent of a conflict, or the task id of kTaskMissed
  std::string message;
};

std::string to_string(Violation::Kind kind);

struct ValidationReport {
  std::vector<Violation> violations;
  int64_t flowtime = 0;
  int makespan = 0;
  bool ok() const { return violations.empty(); }
  bool has(Violation::Kind kind) const;
  std::string summary(size_t max_lines = 10) const;
};

struct ValidationOptions {
  // FORMATS.md allows three or more agents to rotate in one step; robots executing a plan one
  // move at a time cannot, so the coordinator forbids it.
  bool forbid_rotations = false;
  // The plan's first stretch only (a lifelong fleet's plan grows as it is carried out): every
  // rule but ending on the goals and visiting the tasks.
  bool first_stretch = false;
};

// In the rotation model (instance.actions) `headings` must hold every agent's heading at every
// timestep; each step is then a move to the cell ahead keeping the heading, a quarter turn in
// place, or a wait.
ValidationReport validate(const Instance& instance, const Solution& solution, const ValidationOptions& options = {},
                          const HeadingPlan& headings = {});

}  // namespace planner_core
