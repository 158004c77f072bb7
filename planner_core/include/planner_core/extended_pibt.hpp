// Extended-PIBT: PIBT (Okumura et al., "Priority inheritance with backtracking for iterative
// multi-agent path finding", AIJ 2022) extended to task sequences as in CTS-PIBT (Jiang et al.)
// and Algorithm 1 of the CTS-PLL paper: each agent heads for the next unvisited task of its order,
// then its goal; priorities are task-aware.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "planner_core/corridor_swap.hpp"
#include "planner_core/deadline.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/guided_distances.hpp"
#include "planner_core/joint_sequencer.hpp"
#include "planner_core/solution.hpp"

namespace planner_core {

struct PibtConfig {
  // The run fails after step_limit_factor * (longest single-agent tour of the sequence) + step_limit_slack steps.
  double step_limit_factor = 3.0;
  int step_limit_slack = 50;
  // Stop early when the number of targets reached (tasks visited + agents finished) has not
  // exceeded its best for this many steps (0 = never; CTS-PIBT runs to the step limit).
  int stall_window = 0;
  // No rotations: never move into the cell of an agent that is itself (through priority
  // inheritance) waiting to move, which would close a cycle of agents moving in one step. Plans
  // for real robots need this: a rotation cannot be executed one move at a time.
  bool forbid_rotations = false;
  // The swap operation of LaCAM3's PIBT (Okumura, "Engineering LaCAM*", AAMAS 2024): when two
  // agents meet head-on in a corridor, the one with priority backs off and pulls the other along
  // until there is room to pass, instead of both waiting forever. On by default since it measured
  // better overall (docs/results/HISTORY.md, section 5); --no-swap turns it off, e.g. for the paper's
  // CTS-PIBT baseline exactly as published.
  bool swap = true;
  // CTS-PLL: each joint sequence's run is guided by Scatter paths through the agents' task orders
  // (scatter.hpp): an agent's next cell on its path is its first choice.
  bool scatter = false;
};

class Scatter;

class ExtendedPibt {
 public:
  enum class Outcome { kSolved, kStepLimit, kStalled, kInterrupted };

  ExtendedPibt(const Instance& instance, DistTable& dist, const PibtConfig& config, std::mt19937& rng);

  // Plans in the rotation model (the instance's model must be kRotate): a move is ranked by the
  // turns to face it plus the cost on from there, read from `turning` (a table per cell and
  // heading, which must outlive the runs); a chosen neighbour that is not ahead becomes a quarter
  // turn towards it, and whoever meant to enter the cell of an agent that stays waits as well.
  void use_rotation_model(GuidedDistances& turning) { turning_ = &turning; }

  // Starts a run for `sequence` from the instance's starts, or from the last configuration of
  // `prefix` (whose visits count) when it is given; in the rotation model `prefix_headings` are
  // the prefix's headings.
  void reset(const JointSequence& sequence, const Solution& prefix = {}, const HeadingPlan& prefix_headings = {});
  // Paths to follow where they lead (null: none); `guide` must outlive the runs it guides.
  void set_guide(const Scatter* guide) { guide_ = guide; }
  // Steps until every agent has visited its tasks and stands on its goal, the step limit, a stall
  // (see PibtConfig::stall_window), or the deadline.
  Outcome run(const Deadline& deadline);
  // One synchronous step of all agents (Algorithm 1); returns true when all agents are finished.
  bool step();

  const Solution& plan() const { return plan_; }
  const HeadingPlan& headings() const { return headings_; }  // empty in the four-move model
  bool finished(int agent) const;                 // all tasks visited and on its goal
  bool tasks_done(int agent) const { return agents_[agent].next == agents_[agent].task_count; }
  int last_target_time(int agent) const { return agents_[agent].last_target_time; }
  Vertex target_of(int agent) const;              // next unvisited task in order, else the goal
  const Instance& instance() const { return instance_; }

 private:
  struct AgentState {
    std::vector<Vertex> targets;        // task cells in order, then the goal
    std::vector<char> visited;          // per task position
    std::vector<int64_t> suffix;        // suffix[k]: tour length from targets[k] to the goal
    int task_count = 0;
    int next = 0;                       // first unvisited task position (task_count when all done)
    int steps_since_target = 0;         // task-aware priority: longer without progress goes first
    int last_target_time = 0;           // timestep the agent last completed a target
    float tie_break = 0;
  };

  void mark_visits(int agent, Vertex at, int time);
  int64_t remaining_distance(int agent, Vertex at);
  bool plan_move(int agent);  // funcExPIBT of Algorithm 1
  int distance_to_target(int agent, Vertex v) { return dist_.get(target_of(agent), v); }
  // Rotation model: the cost of stepping towards neighbour `v` (or staying, v == here) and on to the target.
  int turning_cost(int agent, Vertex here, int heading, Vertex v);
  void take_rotation_actions();  // turns the cells chosen into forward moves, turns and waits

  const Instance& instance_;
  DistTable& dist_;
  PibtConfig config_;
  std::mt19937& rng_;
  std::vector<AgentState> agents_;
  Solution plan_;
  HeadingPlan headings_;
  GuidedDistances* turning_ = nullptr;
  int step_limit_ = 0;
  int finished_count_ = 0;
  int best_progress_ = 0;       // most targets ever reached at once in this run
  int best_progress_step_ = 0;  // plan length when it was reached

  struct PriorityKey {
    bool active;
    int waiting;
    int64_t remaining;
    float tie;
  };

  // Scratch state of one step, indexed by vertex and reset only where touched.
  Config from_, to_, planned_;
  std::vector<int> occupied_now_, occupied_next_;
  std::vector<char> planning_;  // agents on the current priority-inheritance chain
  std::vector<int> order_;
  std::vector<PriorityKey> priority_;
  CorridorSwap swap_;  // reads occupied_now_
  const Scatter* guide_ = nullptr;
};

}  // namespace planner_core
