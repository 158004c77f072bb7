// Lifelong MAPF as the League of Robot Runners runs it (docs/FORMATS.md, "League of Robot Runners
// problems"): agents never finish. Each has a queue of revealed tasks; a task is a list of errands
// (locations) visited in order; when an agent reaches the errand it heads for, that errand is
// finished, and when its last errand is, the task is, and the next task is revealed. Every step a
// planner decides each agent's next cell within a time budget; a step that takes longer, or that
// is not a valid step (a move to a non-neighbouring cell, two agents on one cell, two agents
// swapping), is replaced by everyone waiting, as the league does. An agent finishes at most one
// errand per step. The figure is errands finished within the horizon.
//
// Agents act in one of two models (action_model.hpp): four moves, or the league's rotation model
// (forward, turn clockwise, turn counter-clockwise, wait), every agent facing east at the start
// as in the league.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <deque>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "planner_core/action_model.hpp"
#include "planner_core/deadline.hpp"
#include "planner_core/guided_distances.hpp"
#include "planner_core/instance.hpp"
#include "planner_core/lorr_problem.hpp"
#include "planner_core/traffic_costs.hpp"
#include "planner_core/window_lns.hpp"

namespace planner_core {

// Decides every agent's next pose from where they stand and the errand each heads for (its
// current cell when it has none).
class LifelongPlanner {
 public:
  virtual ~LifelongPlanner() = default;
  virtual Poses next_step(const Poses& now, const Config& goals, const Deadline& deadline) = 0;
  // The league's preprocessing time, before the first step: learn what helps plan these goals.
  virtual void prepare(const Poses& /*now*/, const Config& /*goals*/, const Deadline& /*deadline*/) {}
};

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
};

// Steps an agent stands still before it is drawn ahead of the others (above): kStuckSteps while
// free cells are at least as many as agents, more the fewer they are.
int stuck_steps_for(const Graph& graph, size_t agents);
// Whether a lifelong run parks agents whose errand is a dead end: when agents fill more than 90%
// of the free cells. random_800 (98%, rotation model, plans held always): 950 / 972 / 993 errands
// in 500 steps (seeds 0 / 1 / 2) against 914 / 921 / 948 without; random_600 (73%, window LNS):
// 720 against 772 in 200 steps.

// The guidance a lifelong run takes when asked for "auto": one-way lanes (with a ring road in the
// rotation model with window LNS), except with window LNS while agents number at most a quarter
// of the free cells. There the few meetings LNS plans around cost less than the lanes' detours; more crowded, lanes keep streams apart better than
// LNS (8 agents at a time) can. Measured on random-32-32-20, 200 steps, seed 0, shortest paths
// against lanes, with LNS: 100 agents 812 / 734 errands (four moves), 608 / 563 (rotation); 200
// agents 989 / 989 (rotation); 400 agents 636 / 913 (rotation). Without LNS lanes win even at 100
// agents (rotation 1,148 / 1,325 in 500 steps).
// In the rotation model with LNS the lanes get a ring road (Guidance::kRing; the 2023 winner's
// learned weights for random_400 are lanes whose cells cost less the nearer the map's edge):
// 200 steps, random_400 1,197 / 1,181 errands against 1,012 / 971 (seeds 0 / 1), random_600 757
// against 585, warehouse_small_800 1,674 against 1,343; warehouse_small_400 1,579 both. It
// costs in four moves (1,752 against 1,899) and without LNS (random_800, plans held always: 242
// against 275), so not there. Nor on large maps: those it helped are 32 and 33 cells across, where
// its 12 cells from each edge cover all but the middle; on warehouse_large (140 by 500 cells,
// MR23-I-10, 10,000 agents, 200 steps) it drew paths round the edge, 2,455 errands against 4,599
// with lanes. So only where the map's shorter side is at most 3 kRingDepth (36 cells).
// In the rotation model on lanes with LNS, a wait or a turn costs 3 (lifelong_stay_cost), as much
// as a move against the lane: random_400 +28% over 500 steps, random_800 +11% over 200. Without
// LNS it gained 3% at random_400 and cost 9% at random_800 (plans held always), and in four moves
// with LNS it cost 2% at random_400, so it stays 1 there. Figures: docs/RESULTS.md.
Guidance lifelong_guidance(const Graph& graph, size_t agents, bool lns, ActionModel actions);
bool lifelong_parks_dead_ends(const Graph& graph, size_t agents);
// How a lifelong run in the rotation model holds plans when asked for "auto": always where it parks
// dead-end errands (more than 90% full), else in half the rollouts. random_800 (500 steps, seeds
// 0 / 1 / 2): 950 / 972 / 993 errands held always against 958 / 942 / 950 in half; MR23-I-08
// 4,453 against 4,337. Less crowded, holding always costs (random_400 1,139 against 1,454).
PlanHolding lifelong_plan_holding(const Graph& graph, size_t agents);
// How far ahead a lifelong run's rollouts look without window LNS when asked for "auto"
// (PibtLifelongSettings::rollout_steps; with LNS, lifelong_window): 8 steps in the rotation model
// where plans are held always (more than 90% full), else 3. Held plans take up to three steps to
// carry out, and 3 steps ahead see only the first; random_800 (500 steps, seeds 0-11): 1,028
// errands on the mean against 981 with 3 steps (+4.8%, every seed gains); 16 steps no better
// (seeds 0-2) and dearer. Less crowded, rollouts only, and in four moves, 3 stays (measured:
// docs/RESULTS.md).
constexpr int kRolloutStepsWhereHeld = 8;
int lifelong_rollout_steps(const Graph& graph, size_t agents, ActionModel actions);
int lifelong_stay_cost(Guidance guidance, bool lns, ActionModel actions);
// A lifelong run's traffic costs (traffic_costs.hpp): on, when asked for "auto", with the ring
// road (rotation model, window LNS, crowded small maps; lifelong_guidance), where a jam grew
// without them (random_400, 500 steps, 12 seeds, work counted: +9.3% errands). A cell costs more
// once taken more than 60% of the time, or 10 points above the map's mean fill where that is more
// (random_600 is 73% full: from 83%). Figures: docs/RESULTS.md.
TrafficSettings lifelong_traffic(const Graph& graph, size_t agents, Guidance guidance);
// Window LNS's window when asked for "auto" (PibtLifelongSettings::rollout_steps and keep_window,
// with lns). In the rotation model: where agents are few (at most a quarter of the free cells, where
// lifelong_guidance takes shortest paths) 16 steps, else 8, carried on from step to step; but 8
// planned afresh each step for more than kMostAgentsForLongWindows few agents. In four moves 8
// afresh (kept: random_400 4,874 errands against 4,867, seeds 0-3, work counted). Rotation model, 1 s steps (docs/RESULTS.md): 16 kept against 8
// afresh, random_100 1,583 errands on the mean of seeds 0-3 against 1,557 (+1.7%, every seed),
// random_200 +3.7% (seeds 0-1), warehouse_small_200 +10.6%; warehouse_large 2,000 and 4,000
// agents +2.6% and +3.8% (200 steps), but 8,000 -2.6%: there LNS reached a third of the agents a
// step. 8 kept against 8 afresh, random_400 2,882 against 2,826 (+2.0%, seeds 0-3, 3 of 4 gain).
constexpr size_t kMostAgentsForLongWindows = 4000;
// Where the window is 16 steps and kept (agents few), its LNS also keeps paths of equal cost
// (PibtLifelongSettings::lns_keeps_equal_cost): there it finds all it can within a step, and
// wandering over plateaus gained random_100 0.4% (seeds 0-5, every seed) and random_200 0.7%
// (seed 0), work counted; at random_400, whose LNS has more to find than time, it cost 1% (seeds
// 0-1). Wherever the window is kept, LNS rounds pick their agents by adaptive neighbourhoods
// (PibtLifelongSettings::lns_neighbourhoods; work counted: random_100 +0.8% on six seeds, every
// seed; random_400 +2.1% on three, every seed; random_200 +4.8% on one; warehouse_small_800 even
// over 200 steps); elsewhere (four moves, and more than kMostAgentsForLongWindows few agents) they
// were not measured. Figures: docs/RESULTS.md.
struct LifelongWindow {
  int steps;
  bool kept;
  bool equal_cost_kept = false;
  bool adaptive_neighbourhoods = false;
};
LifelongWindow lifelong_window(const Graph& graph, size_t agents, ActionModel actions);

class PibtLifelong : public LifelongPlanner {
 public:
  PibtLifelong(const Graph& graph, uint32_t seed, PibtLifelongSettings settings = {});
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

  const Graph& graph_;
  PibtLifelongSettings settings_;
  GuidedDistances distances_;
  TrafficCosts traffic_;
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

// What the league's output file records of a run (docs/FORMATS.md, "League of Robot Runners
// output"); filled when LifelongSettings::log is set.
struct LifelongLog {
  struct Event {
    int64_t task;
    int step;
    bool finished;  // else assigned
  };
  struct Error {
    int agent1;
    int agent2;  // -1 when one agent is involved
    int step;
    std::string what;
  };
  std::vector<Vertex> starts;
  ActionModel actions = ActionModel::kMove4;
  Headings start_headings;            // rotation model
  std::vector<std::string> actual;    // per agent, one letter per step: U D L R W, or F R C W
  std::vector<std::string> planned;   // as the planner returned it; T when it was late
  std::vector<std::vector<Event>> events;  // per agent
  std::vector<Error> errors;
  int64_t tasks_revealed = 0;         // tasks 0 .. tasks_revealed-1 were handed out
  std::vector<int> cost;              // per agent, steps it held a task
};

struct LifelongSettings {
  int steps = 500;            // the horizon
  double step_time_s = 1.0;   // the budget to decide one step
  double preprocess_time_s = 60;  // the budget before the first step (the league's preprocessing)
  LifelongLog* log = nullptr;     // set: the run is recorded there
  const std::atomic<bool>* interrupt = nullptr;  // set (Ctrl-C): the run ends after the step under way
  ActionModel actions = ActionModel::kMove4;     // the planner must plan in the same one
  // A step decided after its budget is still taken (and counted in steps_over_budget), not
  // replaced by waiting: for planners whose work is counted, not timed (lns_rounds).
  bool late_steps_taken = false;
};

struct LifelongResult {
  int64_t errands_finished = 0;
  int64_t tasks_finished = 0;
  std::vector<int> errands_per_step;  // finished at each step
  std::vector<double> step_ms;        // time the planner took to decide each step
  double preprocess_ms = 0;           // time the planner took to prepare
  int steps_over_budget = 0;          // the planner took longer than its budget: replaced by waiting
                                      // (unless LifelongSettings::late_steps_taken)
  int invalid_steps = 0;              // replaced by waiting: not a valid step
  std::string first_invalid;          // what the first invalid step did
  int64_t moves = 0;                  // agent-steps spent off their current cell
  bool interrupted = false;           // ended by settings.interrupt before the horizon
};

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

// Runs `problem` for settings.steps steps with `planner`. The task file is read in order and
// started over at its end. Round-robin: agent a's tasks are a, a + teamSize, a + 2 teamSize...,
// tasks_revealed_per_agent (rounded up) of them revealed at a time, done in order. Greedy: a pool
// of tasks_revealed_per_agent x teamSize revealed tasks; an agent without a task takes the one
// whose first errand is nearest, and the pool is refilled.
LifelongResult run_lifelong(const LorrProblem& problem, LifelongPlanner& planner, const LifelongSettings& settings);

}  // namespace planner_core
