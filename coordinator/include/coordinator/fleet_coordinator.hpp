// FleetCoordinator: binds robots to the mission's roles, plans with planner_core from where the
// robots really are, validates the plan, and executes it through an Action Dependency Graph;
// replans when robots join or leave. It composes the parts: RobotRegistry (who is there),
// MissionProgress (roles and task visits), build_plan_instance (what to plan) and PlanExecution
// (the plan being carried out). All state lives on the thread that calls step(); the transport's
// handlers only queue events.
//
// One coordinator drives a fleet at a time. Each has an incarnation (random per process) and a
// term, and publishes its heartbeat (CoordinatorStatus) four times per second and its progress
// (FleetStatus) on every change: an active coordinator that
// hears a higher-ranked active one stands down (fleet_transport::outranks). A standby mirrors the
// active one's progress from its status and takes over, with the next term, when that status falls
// silent while every robot the active one drove is still heard (a standby cut off from part of the
// fleet would drive robots into ones it cannot see). With a MissionJournal, every epoch, role binding and task visit is committed to it before
// it counts, and a restarted coordinator resumes the unfinished run it finds there.
#pragma once

#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "coordinator/coordinator_inputs.hpp"
#include "coordinator/fleet_config.hpp"
#include "coordinator/mission_journal.hpp"
#include "coordinator/mission_progress.hpp"
#include "coordinator/operators_desk.hpp"
#include "coordinator/other_coordinators.hpp"
#include "coordinator/plan_builder.hpp"
#include "coordinator/plan_execution.hpp"
#include "coordinator/planning_worker.hpp"
#include "coordinator/publish_schedule.hpp"
#include "coordinator/refused_processes.hpp"
#include "coordinator/replan_requests.hpp"
#include "coordinator/robot_registry.hpp"
#include "coordinator/standby_follower.hpp"
#include "coordinator/task_assignment.hpp"
#include "coordinator/window_planner.hpp"
#include "coordinator/window_worker.hpp"
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
  bool journal_failed = false;    // the journal stopped recording (the mission went on from memory)
  int plans_discarded = 0;        // plans dropped because the fleet changed while they were made
  std::vector<double> replan_latencies_s;  // from a loss/join to the first command of the new plan
  std::vector<double> round_trips_ms;      // command sent -> the robot's state acknowledging it
  uint32_t term = 0;                       // this coordinator's term when it ended
  bool stood_down = false;                 // it yielded to a higher-ranked active coordinator
  std::string stood_down_because;
  bool took_over = false;                  // a standby that became active
  int tasks_done_before = 0;               // done when it started driving (resumed or taken over)
  int64_t first_command_wall_ms = 0;       // wall clock of its first command (0: none)
  double last_planning_ms = 0;             // how long the latest plan took to make
  int64_t steps_planned = 0;               // moves of every plan made, each from its start
  int64_t steps_of_replaced_plans = 0;     // moves confirmed under plans replaced since
  int64_t windows = 0;                     // lifelong: windows the plans in hand grew by
  double window_ms_max = 0;                // lifelong: the longest time to plan one
  // Lifelong: robots that stood still for want of a window. A robot with tasks that had made every
  // move of the plan, whose next move (in the window appended) the ADG let go at once: it waited
  // from its last move's confirmation, or the plan's last growth if later (before, the plan had no
  // move for it: PIBT's choice), to the window. Windows with at least one such robot are late.
  int64_t windows_late = 0;
  double robot_s_waiting_for_windows = 0;
  double wait_for_window_ms_max = 0;
  int64_t tasks_reassigned = 0;            // lifelong: pooled tasks moved to a robot that got there sooner
  // Lifelong: robots lost whose plan was cut around them rather than replanned whole (the others
  // went on), the moves such cuts dropped (also for robots joining), and robots back where they
  // were lost that took their place in the plan again without a replan.
  int robots_planned_around = 0;
  int64_t moves_cut = 0;
  int robots_taken_back = 0;
  int robots_joined_mid_plan = 0;  // robots not in the plan that joined it where they stood (no replan)
};

struct CoordinatorOptions {
  bool standby = false;              // follow the active coordinator, take over when it falls silent
  MissionJournal* journal = nullptr; // not owned; resumes its unfinished run
};

class FleetCoordinator {
 public:
  using Clock = std::chrono::steady_clock;

  FleetCoordinator(const FleetConfig& config, planner_core::Instance mission, CoordinatorOptions options = {});

  // Event inputs, callable from any thread.
  void on_announcement(const fleet_transport::Announcement& announcement);
  void on_state(const fleet_transport::RobotState& state);
  void on_robot_gone(const std::string& robot_id, fleet_transport::GoneReason reason);
  void on_coordinator_status(const fleet_transport::CoordinatorStatus& status);
  void on_fleet_status(const fleet_transport::FleetStatus& progress);
  // An operator's task request (ctsfleet-task, the dashboard): answered on the reply topic by the
  // active coordinator; a repeated request id gets the same answer again.
  void on_task_request(const fleet_transport::TaskRequest& request);
  // The transport refused a participant's message (e.g. a robot writing as another): an event for
  // operators, as well as the log line.
  void on_refused(const std::string& what);
  // A standby mirrors the tasks the active coordinator was given at runtime from its mission info.
  void on_mission_info(const fleet_transport::MissionInfo& info);

  // One iteration; false once the mission has ended (completed, or timed out).
  bool step(fleet_transport::Transport& transport);
  const MissionSummary& summary() const { return summary_; }
  // A flag (Ctrl-C) that cuts a running solve short; the mission then ends at the next step.
  void set_interrupt(const std::atomic<bool>* interrupt) { interrupt_ = interrupt; }
  std::string progress_line() const;
  // The last word: publishes the final status (ended, or stood down) and, when the mission
  // completed, closes the run in the journal.
  void finish(fleet_transport::Transport& transport);

  uint64_t incarnation() const { return identity_.incarnation; }
  const std::string& mission_id() const { return identity_.mission_id; }
  fleet_transport::CoordinatorRole role() const { return identity_.role; }
  // What is left belongs to roles without a robot: the robots hold until one joins.
  bool waiting_for_robot() const { return plan_end_.waiting_for_robot.has_value(); }

 private:
  enum class Phase { kWaiting, kStandby, kExecuting, kSettling, kDone };
  // Who this coordinator is on the domain: what its heartbeat says of it.
  struct Identity {
    uint64_t incarnation = 0;  // random per process
    uint32_t term = 1;
    int64_t claimed_ms = 0;    // when it claimed the fleet (wall clock)
    fleet_transport::CoordinatorRole role = fleet_transport::CoordinatorRole::kActive;
    std::string mission_id;
    int command_strength = -1;  // of this process's command writers (a standby sets it ahead of a takeover)
  };
  // What a plan is made from; a plan is used only while these are unchanged.
  struct PlanningInputs {
    std::vector<PlanMember> members;      // the ready robots, where they stand, their roles
    std::vector<uint64_t> incarnations;   // of the same robots
    std::set<planner_core::Vertex> blocked;
    int64_t replan_requests = 0;          // replans asked for (a loss, a join, a task) so far
    int tasks = 0;
    int tasks_done = 0;
  };
  // The plan the worker is making: what from, and whether it is the mission's first.
  struct PlanUnderWay {
    PlanningInputs from;
    bool first_plan = false;
    bool lifelong_window = false;  // made as a first lifelong window, not by the solver
  };
  // After a failed plan the robots hold and the next try waits a second, with a longer limit.
  struct PlanRetry {
    double limit_factor = 1;  // doubles after each failure, up to 8; back to 1 on success
    Clock::time_point not_before{};
    bool complete_solver = false;  // lifelong: the next plan by the solver, not a window (a window stalled)
  };
  // Everyone active is done but work is left for roles without a robot: since when it waits.
  struct WaitForRobot {
    Clock::time_point since;
    Clock::time_point last_log;
  };
  // What happens when the plan in hand is done.
  struct PlanEnd {
    bool replanned = false;       // the plan in hand was made because the last one left work
    bool lifelong_idle = false;   // lifelong: every task done, waiting for tasks
    std::optional<WaitForRobot> waiting_for_robot;
  };
  struct LoopClocks {
    Clock::time_point started;
    Clock::time_point settle_deadline;     // when a replan stops waiting quietly for moves in flight
    Clock::time_point last_silence_check;  // see check_robots(): a coordinator that stood still blames no robot
    std::optional<Clock::time_point> first_command;
  };

  // The journal's unfinished run, taken up by the constructor.
  void resume(MissionJournal& journal);
  // The phases of step(), in order: the inputs queued since the last step; robots silent, deaf to
  // their commands, or a second process with a driven robot's id; the phase's own work; what
  // robots and operators are told (mission, events, heartbeat, progress).
  void take_in_inputs(fleet_transport::Transport& transport);
  void check_robots(fleet_transport::Transport& transport, Clock::time_point now);
  void step_waiting(Clock::time_point now);  // for robots: a quorum, all expected, or the wait's end
  void step_executing(fleet_transport::Transport& transport, Clock::time_point now);
  // The plan is done but work is left: replan once, then wait for a robot (or end at its timeout).
  void wait_for_a_robot_or_replan(Clock::time_point now);
  // Waits for moves in flight, plans on the worker, uses the plan if the fleet is still as planned from.
  void step_settling(fleet_transport::Transport& transport, Clock::time_point now);
  bool moves_in_flight();
  void publish(fleet_transport::Transport& transport, Clock::time_point now);
  // One input, on the loop's thread (step() visits each queued one).
  void handle(const inputs::Announced& input, fleet_transport::Transport& transport);
  void handle(const inputs::StateHeard& input, fleet_transport::Transport& transport);
  void handle(const inputs::RobotGone& input, fleet_transport::Transport& transport);
  void handle(const inputs::CoordinatorHeard& input, fleet_transport::Transport& transport);
  void handle(const inputs::ProgressHeard& input, fleet_transport::Transport& transport);
  void handle(const inputs::MissionHeard& input, fleet_transport::Transport& transport);
  void handle(const inputs::TaskRequested& input, fleet_transport::Transport& transport);
  void handle(const inputs::Refused& input, fleet_transport::Transport& transport);
  // The record of the robot a message names; nullptr (refused with an event) when the id breaks
  // the rule for robot ids.
  RobotRecord* record_of(const std::string& robot_id);
  fleet_transport::CoordinatorStatus own_status() const;
  void stand_down(const OtherCoordinator& other, fleet_transport::Transport& transport);
  // Standby: mirrors the active coordinator's progress, takes over when it falls silent.
  void follow(fleet_transport::Transport& transport, Clock::time_point now);
  // Standby: the followed coordinator ended the mission; so does the standby.
  void end_with(const OtherCoordinator& ended);
  void take_over(fleet_transport::Transport& transport, const OtherCoordinator& old, Clock::time_point now);
  void bind_role(int role, RobotRecord& robot);
  // Writes to the journal, if any. The first failure (a full disk...) raises journal_failed once;
  // from then on the mission goes on from memory, unrecorded. False when it was not written.
  bool journal_write(const char* what, const std::function<void(MissionJournal&)>& write);
  void unbind_role(int role);
  // Credits the visits `role` owes at `cell`, each committed to the journal first.
  void credit_visits(int role, planner_core::Vertex cell, const std::string& robot_id);
  bool driving() const { return phase_ == Phase::kExecuting || phase_ == Phase::kSettling; }
  void handle_announcement(RobotRecord& robot, const fleet_transport::Announcement& announcement);
  void handle_state(RobotRecord& robot, const fleet_transport::RobotState& state, Clock::time_point received);
  // A robot heard before it announced itself: its cell is kept clear meanwhile.
  void heard_unannounced(RobotRecord& robot, const fleet_transport::RobotState& state);
  // Takes out an active robot whose report the plan does not allow; true if it did.
  bool took_out_off_plan(RobotRecord& robot, const fleet_transport::RobotState& previous, bool had_state);
  // An inactive robot standing still on a cell comes (back) into the fleet.
  void rejoin(RobotRecord& robot, planner_core::Vertex cell);
  // Whether `state` (arrived at `received`) comes from the process that drives robot's id: the
  // first one heard keeps it while it is heard; another is refused (RefusedProcesses), unless the
  // driven one has been quiet a while (a restart).
  bool accept_incarnation(RobotRecord& robot, const fleet_transport::RobotState& state, Clock::time_point received);
  void refuse_second_process(RobotRecord& robot, const fleet_transport::RobotState& state, Clock::time_point received);
  // Forgets refused processes no longer heard; tells the others (again) that they are refused.
  void tell_refused_processes(fleet_transport::Transport& transport, Clock::time_point now);
  // Takes a robot out; `kind` is the operators' event (lost, fault, off_plan, unresponsive).
  void lose(RobotRecord& robot, const std::string& why, const char* kind = "lost");
  // Takes out the robots that have not acknowledged their move for command_timeout_s.
  void take_out_robots_deaf_to_commands(Clock::time_point now);
  void bind_roles(const std::vector<RobotRecord*>& robots);
  // Binds by the journal's bindings, then by start cells; returns the robots still without a role.
  std::vector<RobotRecord*> bind_resumed_and_on_start(const std::vector<RobotRecord*>& robots);
  PlanningInputs planning_inputs() const;
  // "" when the fleet is as `then`; else what changed, for the log.
  std::string what_changed_since(const PlanningInputs& then) const;
  // Hands a plan from where the robots stand to the worker; the loop goes on meanwhile.
  void start_planning();
  // Uses a finished plan (validated, and made from the fleet as it still is): a new epoch, sent.
  // False when planning failed (the robots hold; the caller retries).
  bool finish_planning(PlanningOutcome outcome, fleet_transport::Transport& transport);
  bool planning_failed(const std::string& why);
  // The robots of a new plan, its figures, its epoch in the journal; then it is carried out.
  void take_plan(const PlanningOutcome& outcome);
  void extend_plan(fleet_transport::Transport& transport);
  // Lifelong: a robot lost mid-plan (where the plan has it) is planned around instead of a whole
  // replan: the plan is cut around it (PlanExecution::cut_around) and windows go on with its cells
  // walled. False when that cannot be done here (the caller replans). `kind`: why it is out (lose()).
  bool plan_around(const RobotRecord& robot, const char* kind);
  // Lifelong: a robot planned around is back, standing still on `cell`: it takes its place in the
  // plan again (PlanExecution::take_back). False when it cannot (the caller replans).
  bool take_back(RobotRecord& robot, planner_core::Cell cell);
  // Lifelong: a robot not in the plan, standing still on `cell`, joins it there
  // (PlanExecution::admit). False when it cannot (the caller replans).
  bool join_plan(RobotRecord& robot, planner_core::Cell cell);
  // Lifelong: the visits the plan's moves left (from each robot's next on) make, and only those.
  void mark_visits_of_moves_left();
  // Lifelong: a new window planner, on the plan's map with the cells of robots planned around walled.
  void restart_window_planner();
  // Lifelong: the window planned for the plan in hand is validated, appended and sent.
  void take_window(fleet_transport::Transport& transport, const WindowOutcome& outcome);
  bool window_under_way() const;
  void credit_visits_at_rest();  // the visits owed where robots that made every move stand
  std::vector<WindowAgent> window_agents() const;  // where each robot still has to go, and park
  // Lifelong: tasks added at runtime that the plan has not reached go to robots that ran out of
  // tasks and get there sooner (rebalance_pool, task_assignment.hpp); journaled before they count.
  // `agents`: window_agents() as they stand. Returns whether a task moved.
  bool rebalance_pool_tasks(const std::vector<WindowAgent>& agents);
  planner_core::DistTable& task_distances();
  void note_window(const PlanWindow& window, double planning_ms);
  void note_waits_for_window(const std::vector<int>& out_of_moves);
  void mark_planned_visits(const planner_core::Solution& steps);
  void mark_planned_visit(int role, planner_core::Vertex at);  // the visits `role` owes at `at` (mission ids)
  bool grows_by_windows(const std::string& robot_id) const;
  void update_progress();
  // Sends every command that is due. With `resend_only`, only the repeats of moves already sent
  // and not yet done: while a replan waits for moves in flight, a command that was lost must
  // still reach its robot, or the wait never ends.
  void dispatch(fleet_transport::Transport& transport, bool resend_only = false);
  void note_command_sent(Clock::time_point now, bool resend_only);
  bool mission_complete() const;
  bool plan_finished() const;
  // The heartbeat (at once: a new epoch or role must be announced before it is used).
  void publish_status(fleet_transport::Transport& transport);
  void publish_progress(fleet_transport::Transport& transport);
  void request_replan(const std::string& why);
  void list_pending();
  planner_core::Vertex mission_vertex(int x, int y) const;
  // Operators' tasks (see on_task_request).
  void handle_task_request(const fleet_transport::TaskRequest& request, fleet_transport::Transport& transport);
  fleet_transport::TaskReply answer(const fleet_transport::TaskRequest& request);
  fleet_transport::TaskReply add_task(const fleet_transport::TaskRequest& request);
  // Why a task at `request`'s cell cannot be added now ("" when it can); `tours` keeps the tours
  // that may take it.
  std::string add_task_refusal(const fleet_transport::TaskRequest& request, std::vector<Tour>& tours) const;
  fleet_transport::TaskReply cancel_task(const fleet_transport::TaskRequest& request);
  std::string task_listing() const;
  // Each planned robot with a role: where it stands, its task visits to make in its plan's order, its goal.
  std::vector<Tour> current_tours() const;
  // What operators see: the mission (map, goals, tasks), the plan, events (queued by report and
  // published at the end of the step, where the transport is at hand).
  void publish_mission(fleet_transport::Transport& transport);
  void publish_plan(fleet_transport::Transport& transport, int64_t flowtime, double planning_ms);
  // Standby: appends the tasks the followed coordinator's mission has beyond this one's, and its cancellations.
  void adopt_tasks(const fleet_transport::MissionInfo& info);
  // Journals the tasks added at runtime that the journal does not have yet (after a takeover).
  void journal_added_tasks();
  void report(const std::string& kind, const std::string& robot_id, const std::string& text, double value = 0) {
    desk_.report(kind, robot_id, text, value);
  }
  RobotRecord* robot_of_agent(int a);
  const RobotRecord* robot_of_agent(int a) const;
  int role_of_agent(int a) const;  // its robot's role; -1 without one, or while the robot is out

  FleetConfig config_;
  planner_core::Instance mission_;
  CoordinatorOptions options_;
  Identity identity_;
  inputs::InputQueue inputs_;

  // The fleet and the mission.
  RobotRegistry robots_;
  MissionProgress progress_;
  std::map<int, std::string> resumed_bindings_;           // from the journal: role -> robot, for the first binding
  std::map<planner_core::Vertex, std::string> blocked_;  // cells of lost robots (mission graph ids) -> robot
  RefusedProcesses refused_processes_;                   // second processes claiming a driven robot's id

  // Other coordinators, and operators.
  OtherCoordinators others_;
  StandbyFollower follower_;
  OperatorsDesk desk_;
  PublishSchedule schedule_;

  // The loop's phase and clocks.
  Phase phase_ = Phase::kWaiting;
  LoopClocks clocks_;
  PlanEnd plan_end_;
  const std::atomic<bool>* interrupt_ = nullptr;

  // Plans.
  int epoch_ = 0;  // grows across restarts (journal) and takeovers (the mirrored epoch)
  int plans_made_ = 0;
  std::unique_ptr<PlanExecution> plan_;  // the plan being executed
  // Lifelong mode: the plan in hand grows window by window as its robots carry it out, taking up
  // tasks added meanwhile (coordinator/src/fleet_coordinator_windows.cpp).
  std::unique_ptr<WindowWorker> windows_;  // lifelong: plans the next window off the loop
  // Lifelong: plan agents whose robots are lost, planned around (held), and whether each may take
  // its place again (not after a fault: the robot then takes no command of a plan made before it).
  std::map<int, bool> agents_out_;
  std::set<std::pair<int, size_t>> planned_visits_;  // (task, index in its roles) the plan in hand makes
  std::set<int> pinned_tasks_;  // added for a robot the operator named: never rebalanced
  // Searches from task cells on the mission's map, for placing added tasks and the pool: task_distances().
  std::unique_ptr<planner_core::DistTable> task_distances_;
  int first_plan_steps_ = 0;                         // the plan in hand's length before any window
  Clock::time_point next_window_check_{};            // when extend_plan next looks whether a window is due
  Clock::time_point plan_grew_at_{};                 // when the plan in hand was taken or last grew
  PlanningWorker planning_;              // makes the next plan on a thread of its own
  PlanUnderWay plan_under_way_;
  PlanRetry plan_retry_;
  ReplanRequests replans_;

  MissionSummary summary_;
  int journaled_tasks_ = 0;     // tasks the journal knows: the mission's and those it recorded
};

}  // namespace coordinator
