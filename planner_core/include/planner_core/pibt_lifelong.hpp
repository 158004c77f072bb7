// The lifelong planner: PIBT one step at a time, with rollouts, held plans, dead-end parking,
// window LNS and traffic costs (each in a file of its own under src/, named after it).
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <random>
#include <string>
#include <vector>

#include "planner_core/guide_paths.hpp"
#include "planner_core/guided_distances.hpp"
#include "planner_core/lifelong.hpp"
#include "planner_core/traffic_costs.hpp"
#include "planner_core/window_lns.hpp"

namespace planner_core {

// PIBT (Okumura et al., 2022), one step at a time: agents decide in the order of their priority,
// the nearest their goals first; an agent takes the free neighbouring cell nearest its goal and
// pushes the agent standing there to decide next (priority inheritance), or stays. Never two
// agents on one cell, never a swap.
//
// In the rotation model PIBT still picks cells, each neighbour costed with the turns needed to
// face it (distances per heading); an agent then moves forward if its cell is the one ahead, else
// stays and turns a quarter towards it. An agent that meant to move onto the cell of one that
// stays (turning, or kept there) waits as well, and so on back along the chain.
//
// Such a step leaves agents short of the cells PIBT chose for them (their targets): turned towards
// it, or queued behind one that turned. Decided afresh next step they may well choose another cell
// and turn away again. Two remedies, both rotation model only (PibtLifelongSettings):
// - keep_targets: an agent short of its target decides before those that are not (stuck ones
//   aside) and tries its target first.
// - hold_plans: the step's targets are carried out as a plan, turning and moving agents while
//   the others wait, until every agent stands on its target (at most kMaxHeldSteps: two quarter
//   turns and a move), as the 2023 winner's executor does. The whole fleet waits on its slowest
//   agent, which pays where a turning agent holds up a queue (crowded maps) and costs where it
//   does not; with rollouts, half of them may hold and half decide afresh, and the look-ahead
//   picks. Figures: docs/RESULTS.md, "Turning agents keep their targets".
//
// Plain PIBT can lock for ever off a biconnected map: an agent at the end of a dead end whose way
// out is the cell of an agent that wants the dead end, the latter ahead in priority at every step
// (with priorities by waiting time both grow alike; by distance the order is as fixed). So an
// agent that has stood still for `stuck_steps` steps while it has somewhere to go is put ahead of
// every other, in a random order among such agents drawn afresh after each `stuck_steps` it stays
// stuck, and it keeps that place until its goal changes: the one in the dead end, once drawn
// first, pushes the other aside and keeps going (a place it lost at its first move would send it
// straight back in).
// `stuck_steps` is kStuckSteps stretched by how crowded the map is: 8 n / (V - n) for n agents on
// V free cells, at least 8 (stuck_steps_for). Where agents outnumber free cells, standing still a
// while is no lock, and boosting every agent that did turns the priorities into a lottery:
// random_800 (800 agents on 819 cells; rotation model, plans held always, 500 steps, seed 0)
// finished 840 errands boosting after 8 steps, 863 after 20, 945 after 50, 902 never; now 336.
//
// On such a map the 2023 winner also parks agents whose errand is a dead end (a cell with one
// neighbour), and so may this planner (park_dead_end_errands): the agent plans as if its errand
// were the cell it stands on and decides after every other agent, so it only moves to make way.
// It gives that errand up (it finishes it only if pushed onto it), but never walks into a dead end
// that another agent's way out depends on. A parked agent may itself be pushed into a dead end and
// stand on another's errand with no way out but through that agent; when that one has been stuck
// for `stuck_steps`, the parked agent is let go for its own errand until that changes.
// Measured in docs/RESULTS.md ("Crowded maps").
//
inline constexpr int kStuckSteps = 8;

// How far ahead rollouts look unless told otherwise (lifelong_rollout_steps says where more).
inline constexpr int kRolloutSteps = 3;

// Rotation model (above): when PIBT's cells are held as a plan until every agent stands on its own.
enum class PlanHolding {
  kNever,               // PIBT decides every step afresh
  kInHalfTheRollouts,   // every second rollout holds; with one rollout (plain PIBT), none does
  kAlways,
};

// "never", "half" or "always"; throws InputError naming `what` and the choices.
PlanHolding parse_plan_holding(const std::string& text, const std::string& what);
std::string to_string(PlanHolding holding);

// Distances to each goal are searched on every core when the goal is first seen (preprocessing
// covers the first goals), and a goal's table is freed once nobody heads there and more than
// `distance_bytes` (PibtLifelongSettings) of tables are held: 10,000 agents on a 54,000-cell map touch 32,000 goals in
// 5,000 steps, 3.4 GB had every table been kept.
struct PibtLifelongSettings {
  Guidance guidance = Guidance::kNone;
  int stay_cost = 1;  // GuidedDistances: a wait's (and a quarter turn's) cost in the guidance
  ActionModel actions = ActionModel::kMove4;
  // Rollouts: each step, PIBT is run `rollouts` times `rollout_steps` steps ahead, each run with its
  // own tie-breaks (the first with the planner's own), and the first step of the run whose agents
  // end nearest their goals is taken (steps to the goal if reached, else rollout_steps plus the
  // cost left). Runs stop early once they would take more than `rollout_share` of the step's
  // budget, so on a slow machine fewer are tried. 1: plain PIBT.
  int rollouts = 1;
  int rollout_steps = kRolloutSteps;
  double rollout_share = 0.5;
  size_t distance_bytes = size_t{1} << 30;  // 1 GiB of distance tables, beyond which unneeded ones go
  // No rotations: never move into the cell of an agent that is itself waiting (through priority
  // inheritance) for this agent to make way, which would close a cycle of agents moving in one
  // step. Robots executing the plan one move at a time (an Action Dependency Graph) need this: a
  // cycle's moves each wait for the next, for ever. The league allows cycles.
  bool forbid_rotations = false;
  // Rotation model: what a pushed agent counts against going on straight ahead of its pusher, in
  // cost units (GuidedDistances::cost_unit): 4 moves over lanes or shortest paths, 0.4 of a move
  // with the ring road (10 units a move). Measured both ways with the ring road (random_400, 6
  // seeds, docs/RESULTS.md): 4 moves finished 0.9% fewer errands, so the units stay as they are.
  int straight_push_cost = 4;
  // Window LNS (window_lns.hpp): the best rollout's rollout_steps steps are improved by Large
  // Neighbourhood Search; rollouts then take half of rollout_share, LNS the rest.
  bool lns = false;
  // Window LNS: the window improved at the last step, one step on and with the agents that have a
  // new errand planned again, is improved instead of the best rollout when it costs less (the
  // 2023 winner keeps its plan from step to step likewise). lifelong_window says where it pays.
  bool keep_window = false;
  // Window LNS: a round whose new paths cost the same as the old keeps them (WindowLns::keep_equal_cost).
  bool lns_keeps_equal_cost = false;
  // Window LNS: how a round picks the agents it plans again (WindowLns::neighbourhoods).
  WindowLns::Neighbourhoods lns_neighbourhoods = WindowLns::Neighbourhoods::kNearest;
  // Window LNS: 0, the rollouts and LNS rounds that fit in the step's budget. Set, every step runs
  // all `rollouts` rollouts and exactly this many LNS rounds (fewer only once no agent is late),
  // whatever the clock: a run is then the same on every run and machine (with
  // LifelongSettings::late_steps_taken), however long its steps take.
  int64_t lns_rounds = 0;
  // Rotation model: an agent short of the cell PIBT chose for it goes first and tries it first.
  // Off by default: it slows two agents meeting head on in a corridor (tested).
  bool keep_targets = false;
  // Rotation model: when the step's targets are carried out as a plan until all are reached.
  PlanHolding hold_plans = PlanHolding::kInHalfTheRollouts;
  // An agent whose errand is a dead end is parked: it stays unless pushed, and gives that errand up
  // (above). For maps nearly full of agents (lifelong_parks_dead_ends).
  bool park_dead_end_errands = false;
  // Traffic costs (traffic_costs.hpp): cells crowded lately cost more in the guidance, counted from
  // the steps taken (not the rollouts). For crowded maps (lifelong_traffic).
  TrafficSettings traffic;
  // Guide paths (guide_paths.hpp): each agent follows a path round the others' flows, and PIBT
  // tries its next cell first. Off unless asked for (settle_lifelong_config says why).
  GuidePathSettings guide_paths;
};

class PibtLifelong : public LifelongPlanner {
 public:
  PibtLifelong(const Graph& graph, uint32_t seed, PibtLifelongSettings settings = {});
  // Not copied or moved: the window LNS holds a pointer to the guide paths.
  PibtLifelong(const PibtLifelong&) = delete;
  PibtLifelong& operator=(const PibtLifelong&) = delete;
  Poses next_step(const Poses& now, const Config& goals, const Deadline& deadline) override;
  void prepare(const Poses& now, const Config& goals, const Deadline& deadline) override;

  int distance_tables() const { return tables_held_; }
  // Agents parked at the last step (park_dead_end_errands).
  int parked_agents() const { return static_cast<int>(std::count(parked_agent_.begin(), parked_agent_.end(), 1)); }
  const WindowLnsStats& lns_totals() const { return lns_totals_; }
  // keep_window: steps at which the last window could be carried on, and those it was taken at.
  int64_t windows_carried_on() const { return windows_carried_on_; }
  int64_t windows_kept() const { return windows_kept_; }
  const GuidedDistances& distances() const { return distances_; }
  const GuidePaths& guides() const { return guides_; }

 private:
  // What one PIBT step changes besides the positions: a rollout starts from a copy.
  struct StepState {
    std::mt19937 rng;
    std::vector<int> still;
    std::vector<double> boost;
    Config targets;
    int held_steps;
  };
  // One PIBT step from `now` (goals were `previous_goals` the step before).
  Poses one_step(const Poses& now, const Config& goals, const Config& previous_goals);
  bool decide(int agent, int pushed_by, const Poses& now, const Config& goals);
  // The cost to the goal of a step to `cell` (a neighbour or the agent's own); in the rotation
  // model with the turns to face it.
  int64_t step_cost(int agent, const Poses& now, Vertex goal, Vertex cell);
  // The goals PIBT plans for: the errands, but a parked agent's is the cell it stands on.
  Config planning_goals(const Poses& now, const Config& errands);
  // Rotation model: turns the cells in next_ (entering_ holds who enters each) into actions.
  void take_rotation_actions(const Poses& now, const Config& goals);
  // Rotation model: whether an agent stands short of its target; whether some agent does and
  // the targets still make a valid step; and the step that carries them out (hold_plans, above).
  bool short_of_target(const Poses& now, int agent) const;
  bool plan_unfinished(const Poses& now) const;
  Poses carry_out_targets(const Poses& now, const Config& goals);
  // Clears the step's scratch maps (who stands on, who enters each cell: `planned`) and counts
  // the steps each agent has stood still.
  void end_step(const Poses& now, const Config& planned);
  int distance(Vertex goal, const Poses& poses, int agent);
  StepState state() const { return {rng_, still_, boost_, targets_, held_steps_}; }
  void restore(const StepState& state);
  // Searches the distances to goals not seen before, and frees tables of goals nobody needs.
  void follow_goals(const Config& goals, const Deadline& deadline);
  // Traffic costs: counts the step's positions; when the costs change, the tables of goals
  // nobody heads for are let go and the others searched again.
  void follow_traffic(const Config& positions, const Deadline& deadline);
  // Guide paths: brought up to date with the step's positions and goals, within kGuideShare of the budget.
  void follow_guides(const Poses& now, const Config& goals, const Deadline& deadline);
  static constexpr double kGuideShare = 0.2;
  // The guide paths' A* heuristic: the distance tables' cost to the goal, in moves, best heading.
  GuidePaths::Heuristic guide_heuristic();

  const Graph& graph_;
  PibtLifelongSettings settings_;
  GuidedDistances distances_;
  TrafficCosts traffic_;
  GuidePaths guides_;
  std::vector<int> bound_for_;      // vertex -> agents whose goal it is
  std::vector<char> table_held_;    // vertex -> its distance table is held
  int tables_held_ = 0;
  std::deque<Vertex> unneeded_;     // goals that lost their last agent, oldest first
  bool following_ = false;
  std::mt19937 rng_;
  Config last_goals_;
  int stuck_steps_ = kStuckSteps;  // stuck_steps_for the map and the agents
  std::vector<char> parked_agent_;  // per agent: parked at this step
  Config released_for_;             // per agent: the errand it was let go for (kNoVertex: none)
  static constexpr double kTargetPriority = 1e6;  // ahead of any distance, behind a stuck agent's boost
  static constexpr double kParkedPriority = 1e9;  // behind any distance and kept target
  std::vector<double> fraction_;   // per agent, a fixed fraction that breaks ties in priority
  std::vector<int> still_;         // steps the agent stood still (since it last moved, or was drawn)
  std::vector<double> boost_;      // a stuck agent's place ahead of the others (0: none)
  std::vector<int> standing_on_;   // vertex -> agent there now, or -1
  std::vector<int> entering_;      // vertex -> agent there next, or -1
  std::vector<char> planning_;     // per agent: deciding now, waiting for an agent it pushed
  Poses next_;
  static constexpr int kMaxHeldSteps = 3;
  Config targets_;        // per agent, the cell PIBT last chose for it (rotation model)
  int held_steps_ = 0;    // steps the current targets have been carried out for
  bool holding_ = false;  // this run (rollout) holds plans
  // keep_window: the last step's window one step on, its new errands planned again; empty when
  // the last window was not carried out or an agent with a new errand finds no way.
  std::vector<Poses> kept_window(const Poses& now, const Config& goals);

  static constexpr int kReplanRounds = 4;  // kept_window: tries, each planning more agents again
  WindowLns lns_;
  WindowLnsStats lns_totals_;
  std::vector<Poses> last_window_;  // window LNS: the window the last step was taken from
  Config last_window_goals_;
  int64_t windows_carried_on_ = 0;
  int64_t windows_kept_ = 0;
};

}  // namespace planner_core
