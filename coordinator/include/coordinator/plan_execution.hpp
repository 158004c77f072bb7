// PlanExecution: one validated plan being carried out. Holds the plan's Action Dependency Graph
// and, per plan agent, how far its robot has come (moves confirmed, the move in flight and when it
// was sent); decides which step commands are due and folds robot states into progress. It knows
// nothing of DDS: commands are returned, not sent, so it is tested without a transport.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "planner_core/action_dependency_graph.hpp"
#include "fleet_transport/messages.hpp"
#include "planner_core/graph.hpp"
#include "planner_core/solution.hpp"

namespace coordinator {

class PlanExecution {
 public:
  using Clock = std::chrono::steady_clock;

  // One plan agent: the robot carrying it out and its progress through the agent's moves.
  struct Agent {
    std::string robot_id;
    int finished = 0;                // moves confirmed done (the robot reported their target)
    int sent = -1;                   // index of the move last sent, -1 before the first
    Clock::time_point sent_at;       // when that move was last (re)sent
    Clock::time_point first_sent_at; // when it was first sent, for the round trip
    bool acknowledged = false;       // the robot reported that move (round trip measured)
    Clock::time_point finished_at;   // when its last move was confirmed (the plan's start before one)
  };

  // `robots[a]` carries plan agent a of `plan` (on `graph`, the plan's own map). Commands carry
  // `coordinator` (the sender's incarnation); only states naming it acknowledge or confirm moves.
  // `headings` (plans with turns): every agent's heading at every step; commands then carry the
  // heading to end each step facing, turns in place included, and a move is done only when the
  // robot reports that heading.
  PlanExecution(int epoch, std::shared_ptr<const planner_core::Graph> graph, const planner_core::Solution& plan,
                std::vector<std::string> robots, uint64_t coordinator, const planner_core::HeadingPlan& headings = {});

  int epoch() const { return epoch_; }
  int agent_count() const { return static_cast<int>(agents_.size()); }
  const Agent& agent(int a) const { return agents_[a]; }
  // Agent a's moves so far; move(a, i) for i from agent(a).finished - 1 on (earlier ones are freed
  // as they are confirmed: a lifelong plan grows without end).
  int move_count(int a) const { return adg_.move_count(a); }
  const planner_core::Move& move(int a, int index) const { return adg_.move(a, index); }
  // The plan agent of `robot_id`, or -1.
  int agent_of(const std::string& robot_id) const;

  // Every move of agent a confirmed.
  bool done(int a) const { return agents_[a].finished >= move_count(a); }
  // A move of agent a was sent and not yet confirmed.
  bool in_flight(int a) const { return !done(a) && agents_[a].sent >= agents_[a].finished; }
  // Agent a has no move in flight and the ADG lets its next one go now.
  bool ready_to_move(int a) const { return !done(a) && !in_flight(a) && move_to_send(a) >= 0; }
  // A move in flight that the robot has not reported yet (not even as started).
  bool unacknowledged(int a) const { return in_flight(a) && !agents_[a].acknowledged; }
  // Where the plan has agent a now: its start, or the end of its last confirmed move.
  planner_core::Cell position(int a) const;
  // A cell the robot of agent a may report under the plan: its position, or the target of the move
  // in flight.
  bool allows(int a, planner_core::Cell cell) const;
  // The plan goes on (lifelong mode): `more` starts with the configuration the plan ends on
  // (else std::invalid_argument); the robots' progress is kept.
  void extend(const planner_core::Solution& more, const planner_core::HeadingPlan& headings = {}) {
    adg_.extend(more, headings);
  }
  // Agent a's robot is lost: it will make no move after the one in flight (if any). Drops its
  // moves after that one and every move of the others that waits on its moves not finished,
  // directly or through other moves (ActionDependencyGraph::moves_kept_around), so the others
  // carry out what they can; the plan then ends where each kept move ends. Returns the moves
  // dropped. Throws std::logic_error (and drops nothing) if a move already sent would go, which
  // the graph's order rules out.
  int64_t cut_around(int a);
  // Agent a's robot is back (a new process, or heard again) standing still on `cell`: on the target
  // of its move in flight, that move is done; on its position, that move is sent again once due
  // (it waited only on moves finished). False when `cell` is neither.
  bool take_back(int a, planner_core::Cell cell);
  // A robot not in the plan joins it standing still on `cell` (facing `heading` in plans with
  // turns): moves into `cell` not started go, with every move that waits on them
  // (ActionDependencyGraph::moves_kept_clear_of), and it becomes agent agent_count() - 1, with no
  // moves until the plan grows. Returns the moves dropped; nothing (and nothing changes) when
  // `cell` is off the plan's map, or a robot of the plan stands there or has a move under way into it.
  std::optional<int64_t> admit(const std::string& robot_id, planner_core::Cell cell, int heading);
  int plan_steps() const { return adg_.plan_steps(); }
  // The plan's last configuration, in the vertices of its own map (graph()).
  const planner_core::Config& last_configuration() const { return adg_.last_configuration(); }
  // Plans with turns: the headings the plan ends with (empty otherwise).
  const planner_core::Headings& last_headings() const { return adg_.last_headings(); }
  const std::shared_ptr<const planner_core::Graph>& graph() const { return graph_; }
  // The plan's timestep up to which agent a has carried it out: the step before its next move,
  // or the plan's end when it has made every move.
  int carried_out_until(int a) const {
    return done(a) ? plan_steps() : move(a, agents_[a].finished).plan_time - 1;
  }
  // The cell agent a's move `index` ends on.
  planner_core::Cell target(int a, int index) const { return graph_->cell_of(move(a, index).to); }

  // The round trip (ms, from the first sending) when `state` is the robot's first report of the
  // move in flight in this epoch; nothing otherwise.
  std::optional<double> acknowledge(int a, const fleet_transport::RobotState& state, Clock::time_point received);
  // Confirms the move in flight when `state` says the robot ended it, standing still on its target
  // (facing the move's heading, if the move has one and the robot reports one) in this epoch;
  // returns that target (a cell the robot reached under the plan), or nothing.
  std::optional<planner_core::Cell> confirm(int a, const fleet_transport::RobotState& state);

  // The command due for agent a at `now` (its next move once the ADG allows it, or the move in
  // flight again after `resend_after_s` without confirmation), and records it as sent. In a plan
  // with turns, turns in place followed by a move forward that may start now go as that one move
  // (index skipping the turns' indices; the robot turns, then goes): turns apart cost a round trip
  // each, and only a robot that must wait for its cell gains by turning meanwhile.
  std::optional<fleet_transport::StepCommand> due_command(int a, Clock::time_point now, double resend_after_s,
                                                          int64_t deadline_ms);

 private:
  // The index of the move to send agent a next, or -1 while the ADG holds it back.
  int move_to_send(int a) const;
  // Keeps kept[a] moves of each agent (ActionDependencyGraph::keep_moves); the moves dropped.
  // Throws std::logic_error (and drops nothing) if a move already sent would go.
  int64_t keep_moves(const std::vector<int>& kept, const std::string& what);

  int epoch_;
  uint64_t coordinator_;
  std::shared_ptr<const planner_core::Graph> graph_;
  planner_core::ActionDependencyGraph adg_;
  std::vector<Agent> agents_;
  std::vector<planner_core::Vertex> starts_;  // the plan's first configuration
};

}  // namespace coordinator
