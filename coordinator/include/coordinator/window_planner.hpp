// WindowPlanner (lifelong mode): the next stretch of a plan that never ends. From the
// configuration the plan in execution ends on, each agent's errands (task cells still to visit,
// in any order) and its parking cell, up to `steps` more configurations, decided one step at a
// time by PIBT (planner_core/pibt_lifelong.hpp) without rotations, so that the Action Dependency Graph
// can carry them out. Each agent heads for the nearest of its errands, then the nearest of the
// rest, then parks. Every step is checked (moves to neighbours only, no two agents on one cell, no
// swap, no cycle) before the window is handed back. No DDS, no clock beyond the deadline. In the
// rotation model (robots that turn) each step is forward, a quarter turn or a wait, and the window
// carries every agent's heading at every step.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "planner_core/deadline.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/lifelong_config.hpp"
#include "planner_core/pibt_lifelong.hpp"
#include "planner_core/solution.hpp"

namespace coordinator {

struct WindowAgent {
  std::vector<planner_core::Vertex> errands;  // cells to visit, in any order (repeats allowed)
  planner_core::Vertex park = planner_core::kNoVertex;  // where it waits once it has none
  // A robot that is out (lost mid-plan): it stands where the window starts, and its cells are
  // walls of the planner's map, so nobody else comes near; errands and park are ignored.
  bool held = false;
};

struct PlanWindow {
  planner_core::Solution steps;  // steps[0] is the configuration it starts from; 1 row: nothing to do
  planner_core::HeadingPlan headings;  // rotation model: each step's headings (steps' rows); empty otherwise
  // Per agent, the errands it reaches within the window, in order (one entry per errand of the
  // request it settles, so a repeated cell reached once settles each repeat in turn).
  std::vector<std::vector<planner_core::Vertex>> reached;
  int unreachable = 0;  // errands and parking cells no path leads to from the agent (left alone)
  // Agents that came no nearer the cell they head for in the last kStalledSteps steps (over this
  // window and the ones before): PIBT may lock (two agents head-on in a dead end); the way out is
  // a whole replan with the complete solver.
  std::vector<int> stalled;
};

// The window planner's PIBT settings: a lifelong settings file (config/lifelong.yaml) settled for
// the map and the robots, or plain PIBT (one rollout, shortest paths) without one. Never window
// LNS: its windows move agents in cycles, which robots moving one at a time cannot carry out.
planner_core::PibtLifelongSettings window_settings(const std::optional<planner_core::LifelongConfig>& settings,
                                                   const planner_core::Graph& graph, size_t robots,
                                                   planner_core::ActionModel actions);

class WindowPlanner {
 public:
  static constexpr int kStalledSteps = 100;

  // `pibt`: from window_settings; its actions and forbid_rotations are set here.
  WindowPlanner(std::shared_ptr<const planner_core::Graph> graph, uint32_t seed,
                planner_core::ActionModel actions = planner_core::ActionModel::kMove4,
                planner_core::PibtLifelongSettings pibt = {});

  // Stops early once every agent is parked with no errand left, or after the step in which the
  // deadline passed; goes on past `steps` while nobody has moved or turned yet (a window of waits
  // only would add nothing), up to kStalledSteps. `from` is where the last window
  // ended (the same agents, in the same order; in the rotation model with their headings). Throws
  // std::logic_error when a step fails its check (a bug: nothing of it may be sent). Held agents
  // stand still through the window and are left out of the search; the planner's map must have
  // their cells walled, and no other agent may start on a wall (else std::logic_error).
  PlanWindow plan(const planner_core::Poses& from, const std::vector<WindowAgent>& agents, int steps,
                  const planner_core::Deadline& deadline);

 private:
  // plan() for agents none of which is held.
  PlanWindow plan_all(const planner_core::Poses& from, const std::vector<WindowAgent>& agents, int steps,
                      const planner_core::Deadline& deadline);
  // Counts, per agent, the steps since it last came nearer its goal.
  void note_gains(const planner_core::Config& at, const planner_core::Config& goals);

  std::shared_ptr<const planner_core::Graph> graph_;
  planner_core::ActionModel actions_;
  planner_core::PibtLifelong pibt_;
  planner_core::DistTable distances_;  // to errands and parking cells
  // Per agent, across windows: the cell it heads for, the nearest it came, steps since it did.
  planner_core::Config heading_for_;
  std::vector<int> nearest_;
  std::vector<int> steps_without_gain_;
};

}  // namespace coordinator
