#include "planner_core/lifelong_auto_rules.hpp"

#include <algorithm>
#include <cstdint>

namespace planner_core {

FleetOnMap measure_fleet_on_map(const Graph& graph, size_t agents) {
  return {.agents = agents, .free_cells = graph.vertex_count(), .shorter_side = std::min(graph.width(), graph.height())};
}

namespace {
bool agents_are_few(const FleetOnMap& fleet) { return fleet.fill() <= kFewAgentsFill; }
bool crowded(const FleetOnMap& fleet) { return fleet.fill() > kCrowdedFill; }
}  // namespace

bool lifelong_lns(const Graph& graph, size_t agents, ActionModel actions) {
  return actions == ActionModel::kRotate && !crowded(measure_fleet_on_map(graph, agents));
}

Guidance lifelong_guidance(const Graph& graph, size_t agents, bool lns, ActionModel actions) {
  const FleetOnMap fleet = measure_fleet_on_map(graph, agents);
  if (lns && agents_are_few(fleet) && agents <= kMostAgentsOnShortestPaths) return Guidance::kNone;
  const bool ring_covers_the_map = fleet.shorter_side <= kRingRoadShorterSideAtMost;
  return lns && actions == ActionModel::kRotate && ring_covers_the_map ? Guidance::kRing : Guidance::kLanes;
}

LifelongWindow lifelong_window(const Graph& graph, size_t agents, ActionModel actions) {
  if (actions != ActionModel::kRotate) return {.steps = 8, .kept = false};
  if (!agents_are_few(measure_fleet_on_map(graph, agents))) {
    return {.steps = 8, .kept = true, .adaptive_neighbourhoods = true};
  }
  if (agents <= kMostAgentsForLongWindows) {
    return {.steps = 16, .kept = true, .equal_cost_kept = true, .adaptive_neighbourhoods = true};
  }
  return {.steps = 8, .kept = false};
}

bool lifelong_parks_dead_ends(const Graph& graph, size_t agents) { return crowded(measure_fleet_on_map(graph, agents)); }

PlanHolding lifelong_plan_holding(const Graph& graph, size_t agents) {
  return crowded(measure_fleet_on_map(graph, agents)) ? PlanHolding::kAlways : PlanHolding::kInHalfTheRollouts;
}

int lifelong_rollout_steps(const Graph& graph, size_t agents, ActionModel actions) {
  const bool held_always = actions == ActionModel::kRotate && lifelong_plan_holding(graph, agents) == PlanHolding::kAlways;
  return held_always ? kRolloutStepsWhereHeld : kRolloutSteps;
}

int stuck_steps_for(const Graph& graph, size_t agents) {
  const int64_t cells = graph.vertex_count();
  const int64_t free = std::max<int64_t>(1, cells - static_cast<int64_t>(agents));
  const int64_t stretched = kStuckSteps * static_cast<int64_t>(agents) / free;
  return static_cast<int>(std::min<int64_t>(1'000'000, std::max<int64_t>(kStuckSteps, stretched)));
}

int lifelong_stay_cost(Guidance guidance, bool lns, ActionModel actions) {
  return lns && guidance != Guidance::kNone && actions == ActionModel::kRotate ? 3 : 1;
}

TrafficSettings lifelong_traffic(const Graph& graph, size_t agents, Guidance guidance) {
  TrafficSettings traffic;
  traffic.on = guidance == Guidance::kRing;
  const double fill = measure_fleet_on_map(graph, agents).fill();
  traffic.threshold = std::min(0.95, std::max(traffic.threshold, fill + 0.1));
  return traffic;
}

}  // namespace planner_core
