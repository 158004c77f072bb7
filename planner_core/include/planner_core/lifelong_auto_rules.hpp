// What a lifelong run takes where a setting is "auto" (lifelong_config.hpp). Every rule reads the
// measurable properties of the map and the fleet in FleetOnMap (free cells, agents per free cell,
// the map's shorter side, the number of agents), each threshold is a named constant below, and
// each is stated once, here, with the figure that chose it; docs/ARCHITECTURE.md ("Lifelong
// settings: the auto rules") lists them as a table. Figures: errands finished (docs/RESULTS.md,
// docs/results/HISTORY.md), 1 s steps unless "work counted" (--lns-rounds).
#pragma once

#include <cstddef>

#include "planner_core/pibt_lifelong.hpp"

namespace planner_core {

// The properties of a map and a fleet the rules read.
struct FleetOnMap {
  size_t agents = 0;
  int free_cells = 0;
  int shorter_side = 0;  // the map's width or height, whichever is less
  double fill() const { return free_cells > 0 ? static_cast<double>(agents) / free_cells : 1.0; }
};
FleetOnMap measure_fleet_on_map(const Graph& graph, size_t agents);

// Agents few: at most a quarter of the free cells. There window LNS plans around the few meetings
// for less than one-way lanes' detours cost (shortest paths), and long windows kept from step to
// step pay. random-32-32-20, 200 steps, shortest paths against lanes with LNS: 100 agents 812 / 734
// errands (four moves), 608 / 563 (rotation); 200 agents 989 / 989; 400 agents 636 / 913.
inline constexpr double kFewAgentsFill = 0.25;
// Shortest paths also need the agents few in number: LNS's budget per step is the same however
// many there are, and with thousands it reaches few of the meetings; lanes keep streams apart
// whatever the count. Rotation model, LNS, 1,000 steps of 0.3 s, fill under 0.15 in each, shortest
// paths against lanes: CITY-01 (1,500 agents) 10,262 / 10,327 errands, CITY-02 (3,000) 14,014 /
// 17,289, warehouse_large_5000 14,490 / 18,730.
inline constexpr size_t kMostAgentsOnShortestPaths = 2000;
// Crowded: more than 90% of the free cells taken (random_800: 98%). There the 2023 winner's
// crowded-map habits pay: parking agents whose errand is a dead end, holding plans always, 8-step
// rollouts, and no window LNS. Parking, random_800 (rotation, plans held always, 500 steps, seeds
// 0 / 1 / 2): 950 / 972 / 993 against 914 / 921 / 948 without; random_600 (73%) 720 against 772.
// Plans held always there: 950 / 972 / 993 against 958 / 942 / 950 held in half the rollouts,
// MR23-I-08 4,453 against 4,337; at random_400 holding always costs (1,139 against 1,454).
inline constexpr double kCrowdedFill = 0.9;
// The ring road (Guidance::kRing, lanes cheaper near the map's edge) only on maps whose shorter
// side is at most 3 kRingDepth: on those it helped (32 and 33 cells across) its bands cover all
// but the middle; on warehouse_large (140 by 500 cells, 10,000 agents, 200 steps) it drew paths
// round the edge, 2,455 errands against 4,599 with lanes.
inline constexpr int kRingRoadShorterSideAtMost = 3 * GuidedDistances::kRingDepth;
// Long windows (16 steps, kept) for at most this many agents, where agents are few: warehouse_large
// 2,000 and 4,000 agents +2.6% and +3.8% (200 steps), but 8,000 -2.6%, where LNS reached a third
// of the agents a step.
inline constexpr size_t kMostAgentsForLongWindows = 4000;
// How far ahead rollouts look where plans are held always (crowded, rotation model, no LNS): held
// plans take up to three steps to carry out and 3 steps ahead see only the first. random_800 (500
// steps, seeds 0-11): 1,028 errands on the mean against 981 with 3 steps (+4.8%, every seed).
constexpr int kRolloutStepsWhereHeld = 8;

// Steps an agent stands still before it is drawn ahead of the others (pibt_lifelong.hpp):
// kStuckSteps while free cells are at least as many as agents, more the fewer they are.
int stuck_steps_for(const Graph& graph, size_t agents);

// Window LNS: on in the rotation model unless crowded. Rotation model, 300 steps against the 2023
// winner on three held-out maps: with LNS 1.13 / 1.49 / 1.01 of its errands, without 0.58 / 0.87 /
// 1.01. Crowded, rollouts with plans held always win: random_800 (200 steps) 275 errands against
// 203-226 with LNS. In four moves LNS stays off: its gain there was not measured against the
// rollouts' default.
bool lifelong_lns(const Graph& graph, size_t agents, ActionModel actions);
// Guidance: shortest paths with LNS where agents are few (by fill and by count); else one-way
// lanes, with a ring road in the rotation model with LNS on maps narrow enough
// (kRingRoadShorterSideAtMost). The ring road, 200 steps: random_400 1,197 / 1,181 errands against
// 1,012 / 971 with lanes (seeds 0 / 1), random_600 757 against 585, warehouse_small_800 1,674
// against 1,343; in four moves it cost (1,752 against 1,899), and without LNS (random_800: 242
// against 275).
Guidance lifelong_guidance(const Graph& graph, size_t agents, bool lns, ActionModel actions);
// A wait's or a quarter turn's cost in the guidance: 3 (a move against the lane) in the rotation
// model on lanes with LNS (random_400 +28% over 500 steps, random_800 +11% over 200), else 1
// (without LNS it cost 9% at random_800; in four moves with LNS 2% at random_400).
int lifelong_stay_cost(Guidance guidance, bool lns, ActionModel actions);
bool lifelong_parks_dead_ends(const Graph& graph, size_t agents);
PlanHolding lifelong_plan_holding(const Graph& graph, size_t agents);
// Rollouts' look-ahead without LNS: kRolloutStepsWhereHeld where plans are held always (rotation
// model, crowded), else kRolloutSteps (less crowded and in four moves 8 steps lost: random_800 in
// four moves 3,015 / 3,145 against more with 3).
int lifelong_rollout_steps(const Graph& graph, size_t agents, ActionModel actions);
// Traffic costs (traffic_costs.hpp): on with the ring road, where a jam grew without them
// (random_400, 500 steps, 12 seeds, work counted: +9.3%). A cell costs more once taken more than
// 60% of the time, or 10 points above the fleet's fill where that is more (random_600: from 83%).
TrafficSettings lifelong_traffic(const Graph& graph, size_t agents, Guidance guidance);
// Window LNS's window: in four moves 8 steps planned afresh (kept: random_400 4,874 errands
// against 4,867, seeds 0-3, work counted). In the rotation model, kept from step to step: 16 steps
// where agents are few (up to kMostAgentsForLongWindows; random_100 +1.7% over 8 afresh, every
// seed of 0-3; random_200 +3.7%; warehouse_small_200 +10.6%), with paths of equal cost kept
// (random_100 +0.4%, seeds 0-5; at random_400 it cost 1%); 8 steps elsewhere (random_400 +2.0%
// over 8 afresh, seeds 0-3). Wherever the window is kept, LNS picks its agents by adaptive
// neighbourhoods (random_100 +0.8% on six seeds, random_400 +2.1% on three, every seed).
struct LifelongWindow {
  int steps;
  bool kept;
  bool equal_cost_kept = false;
  bool adaptive_neighbourhoods = false;
};
LifelongWindow lifelong_window(const Graph& graph, size_t agents, ActionModel actions);

}  // namespace planner_core
