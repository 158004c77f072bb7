// Whether a step of a lifelong run (one configuration to the next) is one the league accepts: moves
// to neighbouring cells only, never two agents on one cell, never two swapping; in the rotation
// model forward, a quarter turn or a wait. And whether agents move in a cycle, which robots moving
// one at a time (an Action Dependency Graph) cannot carry out.
#pragma once

#include <string>

#include "planner_core/action_model.hpp"
#include "planner_core/graph.hpp"
#include "planner_core/instance.hpp"

namespace planner_core {

// Why `next` is no valid step from `positions` on `graph` ("" when it is one).
struct StepFault {
  int agent1 = -1;
  int agent2 = -1;  // -1 when one agent is at fault
  std::string what;  // "" when the step is valid
};
StepFault find_step_fault(const Graph& graph, const Config& positions, const Config& next);
std::string invalid_step(const Graph& graph, const Config& positions, const Config& next);
// Why `next` is no valid step from `now` in `model`: as find_step_fault, and in the rotation
// model each agent either moves to the cell ahead keeping its heading, or stays and turns a
// quarter either way or not at all.
StepFault find_pose_fault(const Graph& graph, ActionModel model, const Poses& now, const Poses& next);
// Agents of a valid step that move in a cycle (each into the cell the next one leaves), which
// robots moving one at a time cannot do; empty `what` when there is none.
StepFault find_rotation(const Config& positions, const Config& next);

}  // namespace planner_core
