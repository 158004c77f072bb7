// FleetCoordinator: binds robots to the mission's roles, plans with planner_core from where the
// robots really are, validates the plan, and executes it through an Action Dependency Graph;
// replans when robots join or leave. It composes the parts: RobotRegistry (who is there),
// MissionProgress (roles and task visits), build_plan_instance (what to plan) and PlanExecution
// (the plan being carried out). All state lives on the thread that calls step(); the transport's
// handlers only queue events.
#pragma once

#include <atomic>
#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "coordinator/fleet_config.hpp"
#include "coordinator/mission_progress.hpp"
#include "coordinator/plan_execution.hpp"
#include "coordinator/robot_registry.hpp"
#include "fleet_transport/transport.hpp"
#include "planner_core/instance.hpp"

namespace coordinator {

struct MissionSummary {
  bool completed = false;         // every task done and every robot on its goal
  int tasks_done = 0;
  int tasks_total = 0;
  std::vector<std::string> pending;  // tasks left undone, with the reason
  int replans = 0;
  int robots_lost = 0;
  int robots_joined = 0;
  int off_plan = 0;               // robots taken out for standing where the plan did not have them
  double seconds = 0;             // from the first command to the end
  int first_plan_makespan = 0;    // steps
  int64_t first_plan_flowtime = 0;
  double sum_of_finish_s = 0;     // sum over robots of the time each finished its last plan
  int64_t commands_sent = 0;
  int64_t states_received = 0;
  std::vector<double> replan_latencies_s;  // from a loss/join to the first command of the new plan
  std::vector<double> round_trips_ms;      // command sent -> the robot's state acknowledging it
};

class FleetCoordinator {
 public:
  using Clock = std::chrono::steady_clock;

  FleetCoordinator(const FleetConfig& config, planner_core::Instance mission);

  // Event inputs, callable from any thread.
  void on_announcement(const fleet_transport::Announcement& announcement);
  void on_state(const fleet_transport::RobotState& state);
  void on_robot_gone(const std::string& robot_id, fleet_transport::GoneReason reason);

  // One iteration; false once the mission has ended (completed, or timed out).
  bool step(fleet_transport::Transport& transport);
  const MissionSummary& summary() const { return summary_; }
  // A flag (Ctrl-C) that cuts a running solve short; the mission then ends at the next step.
  void set_interrupt(const std::atomic<bool>* interrupt) { interrupt_ = interrupt; }
  std::string progress_line() const;

 private:
  enum class Phase { kWaiting, kExecuting, kSettling, kDone };
  struct Event {
    enum class Kind { kAnnouncement, kState, kGone } kind = Kind::kAnnouncement;
    fleet_transport::Announcement announcement;
    fleet_transport::RobotState state;
    std::string robot_id;
    fleet_transport::GoneReason reason{};
    Clock::time_point received{};
  };

  void handle(const Event& event);
  void handle_announcement(RobotRecord& robot, const fleet_transport::Announcement& announcement);
  void handle_state(RobotRecord& robot, const fleet_transport::RobotState& state, Clock::time_point received);
  bool accept_incarnation(RobotRecord& robot, const fleet_transport::RobotState& state, Clock::time_point now);
  void lose(RobotRecord& robot, const std::string& why);
  void bind_roles(const std::vector<RobotRecord*>& robots);
  bool replan(fleet_transport::Transport& transport);
  void update_progress();
  void dispatch(fleet_transport::Transport& transport);
  bool mission_complete() const;
  bool plan_finished() const;
  void publish_status(fleet_transport::Transport& transport);
  void request_replan(const std::string& why);
  void list_pending();
  planner_core::Vertex mission_vertex(int x, int y) const;

  FleetConfig config_;
  planner_core::Instance mission_;
  std::mutex events_mutex_;
  std::deque<Event> events_;

  RobotRegistry robots_;
  MissionProgress progress_;
  std::map<planner_core::Vertex, std::string> blocked_;  // cells of lost robots (mission graph ids) -> robot
  std::set<std::string> warned_unknown_;
  std::map<std::string, planner_core::Vertex> unknown_cells_;  // robots heard but not announced

  Phase phase_ = Phase::kWaiting;
  Clock::time_point started_, first_command_, settle_deadline_, next_status_, replan_requested_at_;
  bool replan_requested_ = false;
  bool first_command_sent_ = false;
  bool awaiting_replan_latency_ = false;
  Clock::time_point retry_plan_at_;
  std::optional<Clock::time_point> waiting_for_robot_since_;
  bool replanned_after_finish_ = false;  // the plan in hand was made because the last one left work

  int epoch_ = 0;
  double plan_limit_factor_ = 1;
  const std::atomic<bool>* interrupt_ = nullptr;  // grows after each failed planning attempt, back to 1 on success
  std::unique_ptr<PlanExecution> plan_;  // the plan being executed
  MissionSummary summary_;
};

}  // namespace coordinator
