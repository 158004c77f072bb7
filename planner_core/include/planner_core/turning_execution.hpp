// A four-way plan carried out by robots that turn (action_model.hpp): each agent follows its own
// path cell by cell, turning a quarter per step to face the next cell, and enters a cell only
// after every agent that passes through it earlier in the plan has left it (the Action
// Dependency Graph's rule, docs/PLATFORM-NOTES). The plan's order of passage through every cell
// is kept, so no two agents meet, and each visits its tasks and ends on its goal as before.
//
// This is how any solver plans in the rotation model (the solver plans four-way moves, this adds
// the turns and the waits they cause), and what a fleet does with a plan that ignores turns.
#pragma once

#include <optional>

#include "planner_core/solution.hpp"

namespace planner_core {

struct TurningPlan {
  Solution cells;
  HeadingPlan headings;
};

// `plan` must be valid in the four-way model. Agents that move in a cycle within one step of it
// (three or more, each into the cell the next one leaves) wait on each other: with
// `allow_cycles` they move together once all of them face their next cells; without it (plans for
// robots, which cannot) such a plan gives nullopt. Headings start at the instance's start headings.
std::optional<TurningPlan> execute_with_turns(const Instance& instance, const Solution& plan, bool allow_cycles);

}  // namespace planner_core
