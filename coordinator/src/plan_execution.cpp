#include "coordinator/plan_execution.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace coordinator {

PlanExecution::PlanExecution(int epoch, std::shared_ptr<const planner_core::Graph> graph,
                             const planner_core::Solution& plan, std::vector<std::string> robots, uint64_t coordinator,
                             const planner_core::HeadingPlan& headings)
    : epoch_(epoch), coordinator_(coordinator), graph_(std::move(graph)), adg_(plan, headings), starts_(plan.empty() ? planner_core::Config{} : plan[0]) {
  agents_.resize(robots.size());
  const Clock::time_point now = Clock::now();
  for (size_t a = 0; a < robots.size(); ++a) {
    agents_[a].robot_id = std::move(robots[a]);
    agents_[a].finished_at = now;
  }
}

int PlanExecution::agent_of(const std::string& robot_id) const {
  for (int a = 0; a < agent_count(); ++a) {
    if (agents_[a].robot_id == robot_id) return a;
  }
  return -1;
}

planner_core::Cell PlanExecution::position(int a) const {
  const int finished = agents_[a].finished;
  return graph_->cell_of(finished > 0 ? move(a, finished - 1).to : starts_[a]);
}

bool PlanExecution::allows(int a, planner_core::Cell cell) const {
  return cell == position(a) || (in_flight(a) && cell == target(a, agents_[a].sent));
}

std::optional<double> PlanExecution::acknowledge(int a, const fleet_transport::RobotState& state,
                                                 Clock::time_point received) {
  Agent& agent = agents_[a];
  if (state.coordinator != coordinator_ || state.plan_epoch != epoch_ || agent.sent < 0 || state.action_index != agent.sent || agent.acknowledged) {
    return std::nullopt;
  }
  agent.acknowledged = true;
  return std::chrono::duration<double, std::milli>(received - agent.first_sent_at).count();
}

std::optional<planner_core::Cell> PlanExecution::confirm(int a, const fleet_transport::RobotState& state) {
  if (!in_flight(a)) return std::nullopt;
  // A robot that reports no heading (-1: its body has no compass) is confirmed by its cell alone, or
  // it would never be: its turns are then left to it, as in a four-way plan.
  Agent& agent = agents_[a];
  const planner_core::Move& sent = move(a, agent.sent);
  const planner_core::Cell cell = graph_->cell_of(sent.to);
  if (state.coordinator != coordinator_ || state.plan_epoch != epoch_ || state.action_index != agent.sent ||
      state.status == fleet_transport::RobotStatus::kMoving || state.cell_x != cell.x || state.cell_y != cell.y ||
      (sent.heading >= 0 && state.heading >= 0 && state.heading != sent.heading)) {
    return std::nullopt;
  }
  agent.finished = agent.sent + 1;  // with the turns folded into it, if any
  agent.finished_at = Clock::now();
  adg_.forget_before(a, agent.finished - 1);  // the last one confirmed is where the agent stands
  return cell;
}

int64_t PlanExecution::cut_around(int a) {
  const Agent& lost = agents_[a];
  const auto finished_of = [this](int other) { return agents_[other].finished; };
  return keep_moves(adg_.moves_kept_around(a, lost.finished, in_flight(a) ? lost.sent + 1 : lost.finished, finished_of),
                    "cutting the plan around agent " + std::to_string(a));
}

std::optional<int64_t> PlanExecution::admit(const std::string& robot_id, planner_core::Cell cell, int heading) {
  const planner_core::Vertex at = graph_->vertex_at(cell);
  if (at == planner_core::kNoVertex) return std::nullopt;
  for (int a = 0; a < agent_count(); ++a) {
    if (position(a) == cell || (in_flight(a) && target(a, agents_[a].sent) == cell)) return std::nullopt;
  }
  const auto finished_of = [this](int other) { return agents_[other].finished; };
  const int64_t dropped = keep_moves(adg_.moves_kept_clear_of(at, finished_of),
                                     "clearing " + planner_core::to_string(cell) + " for robot " + robot_id);
  adg_.add_robot(at, heading);
  agents_.push_back({.robot_id = robot_id, .finished_at = Clock::now()});
  starts_.push_back(at);
  return dropped;
}

int64_t PlanExecution::keep_moves(const std::vector<int>& kept, const std::string& what) {
  int64_t dropped = 0;
  for (int other = 0; other < agent_count(); ++other) {
    if (in_flight(other) && kept[other] <= agents_[other].sent) {
      throw std::logic_error(what + " would drop move " + std::to_string(agents_[other].sent) + " of agent " +
                             std::to_string(other) + ", already sent");
    }
    dropped += move_count(other) - kept[other];
  }
  adg_.keep_moves(kept);
  return dropped;
}

bool PlanExecution::take_back(int a, planner_core::Cell cell) {
  Agent& agent = agents_[a];
  if (in_flight(a) && cell == target(a, agent.sent)) {
    agent.finished = agent.sent + 1;
    agent.finished_at = Clock::now();
    adg_.forget_before(a, agent.finished - 1);
    return true;
  }
  if (cell != position(a)) return false;
  agent.sent = agent.finished - 1;  // the move in flight, if any, goes again as a new one
  agent.acknowledged = false;
  return true;
}

int PlanExecution::move_to_send(int a) const {
  const int next = agents_[a].finished;
  if (!adg_.ready(a, next, [this](int other) { return agents_[other].finished; })) return -1;
  // Turns in place followed by a move forward that may start now: one command, the robot turns and
  // goes. A move that must wait keeps its turns apart, so the robot turns while it waits.
  int forward = next;
  while (forward < move_count(a) && move(a, forward).from == move(a, forward).to) ++forward;
  if (forward == next || forward == move_count(a)) return next;
  const auto finished_of = [&](int other) { return other == a ? forward : agents_[other].finished; };
  return adg_.ready(a, forward, finished_of) ? forward : next;
}

std::optional<fleet_transport::StepCommand> PlanExecution::due_command(int a, Clock::time_point now,
                                                                       double resend_after_s, int64_t deadline_ms) {
  if (done(a)) return std::nullopt;
  Agent& agent = agents_[a];
  const bool resend = in_flight(a);
  if (resend && std::chrono::duration<double>(now - agent.sent_at).count() < resend_after_s) return std::nullopt;
  const int next = resend ? agent.sent : move_to_send(a);
  if (next < 0) return std::nullopt;
  const planner_core::Cell cell = target(a, next);
  fleet_transport::StepCommand command;
  command.robot_id = agent.robot_id;
  command.plan_epoch = epoch_;
  command.action_index = next;
  command.target_x = cell.x;
  command.target_y = cell.y;
  command.target_pose_x = cell.x;
  command.target_pose_y = cell.y;
  command.target_heading = move(a, next).heading;
  command.deadline_ms = deadline_ms;
  command.sent_ms = fleet_transport::wall_clock_ms();
  command.coordinator = coordinator_;
  if (!resend) {
    agent.first_sent_at = now;
    agent.acknowledged = false;
  }
  agent.sent = next;
  agent.sent_at = now;
  return command;
}

}  // namespace coordinator
