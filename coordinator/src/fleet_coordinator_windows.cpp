// FleetCoordinator in lifelong mode: the plan in hand grows window by window while its robots
// carry it out. A task added at runtime goes to the robot that gets there soonest (add_task); until
// the plan reaches it, a robot that ran out of tasks and gets there sooner may take it (the pool,
// rebalance_pool_tasks); a window takes it up: the fleet never stops to replan for it. Robots lost
// or joining still bring a whole replan (fleet_coordinator_planning.cpp), whose plan then grows in
// turn.
//
//   plan in hand:  [ first plan (CTS solver) | window | window | ... ]
//                                                    ^ robots carry it out here (ADG)
//   a window is planned once a robot still moving is within kLeadSteps of the plan's end, or one
//   that has made every move has tasks to go to or is not parked; unless the laggard (the robot a
//   quarter of the fleet is behind) has kMaxLeadSteps of windows still ahead of it (the first
//   plan's own length does not count). Windows far ahead of the fleet order fast robots behind
//   slow ones at the cells they share (the ADG orders moves at a cell by plan time); gating on the
//   slowest robot instead stalls the whole fleet behind one robot delayed for long. It is planned
//   off the loop (WindowWorker) and appended once it comes back, if the plan still ends where it
//   started.
//
// A robot lost mid-plan (silent, restarted, in fault, deaf to its commands) where the plan has it
// does not stop the others: the plan is cut around it (the moves that would wait on it for ever
// go, PlanExecution::cut_around) and windows go on from where the rest of the plan ends, with the
// robot held where it stands and its cells (its own, and its move's target if one was in flight)
// walled in the window planner's map. Its role's tasks in the pool go to others at the next window.
// Back on one of those cells, it takes its place in the plan again (take_back); anywhere else, or
// off its plan, it brings a whole replan. A robot not in the plan that stands still on a cell no
// robot of the plan stands on or is moving to joins the plan there (join_plan): the moves into its
// cell not yet started go, with what waits on them, and windows plan it from there.
//
// Windows are PIBT, which can lock (two robots head-on in a dead end); a robot that comes no
// nearer where it heads for WindowPlanner::kStalledSteps planned steps brings a whole replan,
// whose solver is complete.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>
#include <string_view>

#include "coordinator/fleet_coordinator.hpp"
#include "planner_core/validator.hpp"
#include "fleet_coordinator_detail.hpp"

namespace coordinator {

using planner_core::Vertex;
using namespace fleet_coordinator_detail;

namespace {

constexpr int kWindowSteps = 5;      // steps a window adds at most
constexpr int kLeadSteps = 5;        // a window once a robot still moving is this close to the end
constexpr int kMaxLeadSteps = 10;    // ... unless the laggard has this many window steps ahead:
constexpr double kLaggardShare = 0.25;  // the robot a quarter of the fleet is behind (docs/RESULTS.md)
constexpr double kWindowBudgetS = 0.25;
constexpr std::chrono::milliseconds kCheckPeriod{20};  // between two looks at whether a window is due

}  // namespace

bool FleetCoordinator::grows_by_windows(const std::string& robot_id) const {
  return config_.lifelong && phase_ == Phase::kExecuting && plan_ && windows_ && plan_->agent_of(robot_id) >= 0;
}

void FleetCoordinator::extend_plan(fleet_transport::Transport& transport) {
  if (!config_.lifelong || !plan_ || !windows_ || plan_->agent_count() == 0) return;
  if (std::optional<WindowOutcome> outcome = windows_->poll()) take_window(transport, *outcome);
  if (!windows_->idle()) return;  // one window at a time
  // Looking through every robot's tasks costs more than a loop should, every loop (a few ms): at
  // most every kCheckPeriod, a tenth of a step at 5 steps a second; but at once when every robot
  // has run out of moves (else the loop would take the plan as finished and replan).
  const Clock::time_point now = Clock::now();
  if (now < next_window_check_ && !plan_finished()) return;
  next_window_check_ = now + kCheckPeriod;
  const int end = plan_->plan_steps();
  std::vector<int> carried_out;
  bool near_the_end = false;
  for (int a = 0; a < plan_->agent_count(); ++a) {
    if (agents_out_.count(a)) continue;  // held where it is
    const RobotRecord* robot = robot_of_agent(a);
    if (robot == nullptr || !robot->active) return;  // a replan is due: its robot cannot be moved
    carried_out.push_back(plan_->carried_out_until(a));
    near_the_end = near_the_end || (!plan_->done(a) && end - plan_->carried_out_until(a) <= kLeadSteps);
  }
  if (carried_out.empty()) return;  // every robot is out
  // The plan keeps at most kMaxLeadSteps ahead of the robot a quarter of the fleet is behind.
  const auto laggard = carried_out.begin() +
                       static_cast<std::ptrdiff_t>(kLaggardShare * static_cast<double>(carried_out.size() - 1));
  std::nth_element(carried_out.begin(), laggard, carried_out.end());
  if (end - std::max(*laggard, first_plan_steps_) > kMaxLeadSteps) return;
  credit_visits_at_rest();
  std::vector<WindowAgent> agents = window_agents();
  if (rebalance_pool_tasks(agents)) agents = window_agents();  // tasks moved: errands changed
  // Or a robot has made every move and has tasks to go to, or is not parked yet.
  const planner_core::Config& last = plan_->last_configuration();
  for (int a = 0; a < plan_->agent_count() && !near_the_end; ++a) {
    near_the_end = !agents[a].held && plan_->done(a) && (!agents[a].errands.empty() || last[a] != agents[a].park);
  }
  if (!near_the_end) return;
  windows_->start({plan_->epoch(), end, {last, plan_->last_headings()}, std::move(agents), kWindowSteps, kWindowBudgetS});
}

bool FleetCoordinator::window_under_way() const { return config_.lifelong && plan_ && windows_ && !windows_->idle(); }

void FleetCoordinator::take_window(fleet_transport::Transport& transport, const WindowOutcome& outcome) {
  // Planned for the plan as it ended when the job started; robots lost meanwhile bring a replan.
  if (outcome.job.epoch != plan_->epoch() || outcome.job.plan_steps != plan_->plan_steps()) return;
  for (int a = 0; a < plan_->agent_count(); ++a) {
    const RobotRecord* robot = robot_of_agent(a);
    if (!agents_out_.count(a) && (robot == nullptr || !robot->active)) return;
  }
  const PlanWindow& window = outcome.window;
  if (!outcome.error.empty()) {
    spdlog::critical("{}; it is not sent", outcome.error);
    request_replan("an invalid lifelong window");
    return;
  }
  if (!window.stalled.empty()) {  // a PIBT lock: the way out is the complete solver, from where they stand
    const RobotRecord* stuck = robot_of_agent(window.stalled.front());
    plan_retry_.complete_solver = true;
    request_replan(fmt::format("lifelong: robot {} (and {} more) came no nearer where it heads in {} planned steps",
                               stuck->id, window.stalled.size() - 1, WindowPlanner::kStalledSteps));
    return;
  }
  if (window.steps.size() < 2) return;  // every robot parked, nothing to do
  // The validator is the gate, as for every plan: the window from the plan's last configuration.
  planner_core::Instance stretch;
  stretch.graph = plan_->graph();
  stretch.starts = window.steps.front();
  stretch.goals = window.steps.back();
  stretch.actions = mission_.actions;
  if (!window.headings.empty()) stretch.start_headings = window.headings.front();
  stretch.index_tasks();
  const planner_core::ValidationReport report = planner_core::validate(
      stretch, window.steps, {.forbid_rotations = true, .first_stretch = true}, window.headings);
  if (!report.ok()) {
    spdlog::critical("a lifelong window failed validation; it is not sent:\n{}", report.summary());
    request_replan("an invalid lifelong window");
    return;
  }
  // A robot at rest where the window starts makes there the visits of tasks added while it was
  // planned: the window counts them reached at its first step, and the robot reports no arrival
  // there again (else such a task was taken as planned and never done: the plan ran out with it).
  credit_visits_at_rest();
  int64_t moves_before = 0;
  std::vector<int> out_of_moves;  // robots with tasks that had made every move
  for (int a = 0; a < plan_->agent_count(); ++a) {
    moves_before += plan_->move_count(a);
    if (plan_->done(a) && !outcome.job.agents[a].errands.empty()) out_of_moves.push_back(a);
  }
  plan_->extend(window.steps, window.headings);
  note_waits_for_window(out_of_moves);
  plan_grew_at_ = Clock::now();
  mark_planned_visits(window.steps);
  int64_t moves_after = 0;
  for (int a = 0; a < plan_->agent_count(); ++a) moves_after += plan_->move_count(a);
  summary_.steps_planned += moves_after - moves_before;
  note_window(window, outcome.planning_ms);
  publish_plan(transport, 0, outcome.planning_ms);
}

int FleetCoordinator::role_of_agent(int a) const {
  const RobotRecord* robot = robot_of_agent(a);
  return robot == nullptr || agents_out_.count(a) ? -1 : robot->role;
}

bool FleetCoordinator::plan_around(const RobotRecord& robot, const char* kind) {
  const int a = robot.plan_agent;
  if (!config_.lifelong || phase_ != Phase::kExecuting || !plan_ || !windows_ || a < 0 || a >= plan_->agent_count() ||
      plan_->agent(a).robot_id != robot.id || agents_out_.count(a)) {
    return false;
  }
  // Its cells must be the plan's: a robot found elsewhere may stand in anyone's way.
  if (robot.has_state && !plan_->allows(a, {robot.last.cell_x, robot.last.cell_y})) return false;
  int64_t dropped = 0;
  try {
    dropped = plan_->cut_around(a);
  } catch (const std::logic_error& e) {
    spdlog::critical("{}; replanning whole instead", e.what());
    return false;
  }
  agents_out_[a] = std::string_view(kind) != "fault";
  mark_visits_of_moves_left();
  restart_window_planner();
  ++summary_.robots_planned_around;
  summary_.moves_cut += dropped;
  spdlog::info("lifelong: the plan goes on around robot {} ({} moves that waited on it dropped; its cells kept clear)",
               robot.id, dropped);
  return true;
}

bool FleetCoordinator::take_back(RobotRecord& robot, planner_core::Cell cell) {
  if (!plan_ || phase_ != Phase::kExecuting) return false;
  const int a = plan_->agent_of(robot.id);
  if (a < 0 || !agents_out_.count(a) || !agents_out_[a] || robot.plan_agent != a || !plan_->take_back(a, cell)) return false;
  robot.active = true;
  agents_out_.erase(a);
  std::erase_if(blocked_, [&](const auto& entry) { return entry.second == robot.id; });
  ++summary_.robots_joined;
  ++summary_.robots_taken_back;
  bind_roles({&robot});
  report("join", robot.id, "back on the grid at " + planner_core::to_string(cell) + ", where the plan left it");
  spdlog::info("lifelong: robot {} is back at {}, where the plan left it: it goes on with the plan", robot.id,
               planner_core::to_string(cell));
  restart_window_planner();
  return true;
}

bool FleetCoordinator::join_plan(RobotRecord& robot, planner_core::Cell cell) {
  // A robot of this plan back elsewhere may have left its cells anywhere between: a whole replan.
  if (!config_.lifelong || phase_ != Phase::kExecuting || !plan_ || !windows_ || plan_->agent_of(robot.id) >= 0) {
    return false;
  }
  const Vertex at = mission_vertex(cell.x, cell.y);
  for (const auto& [blocked, robot_id] : blocked_) {
    if (blocked == at && robot_id != robot.id) return false;  // kept clear for a robot that is out
  }
  const int heading = config_.actions == planner_core::ActionModel::kRotate ? std::max(0, robot.last.heading) : -1;
  std::optional<int64_t> dropped;
  try {
    dropped = plan_->admit(robot.id, cell, heading);
  } catch (const std::logic_error& e) {
    spdlog::critical("{}; replanning whole instead", e.what());
    return false;
  }
  if (!dropped) return false;  // the plan has a robot there, or on its way there
  robot.active = true;
  robot.plan_agent = plan_->agent_count() - 1;
  robot.finished_plan = false;
  std::erase_if(blocked_, [&](const auto& entry) { return entry.second == robot.id || entry.first == at; });
  ++summary_.robots_joined;
  ++summary_.robots_joined_mid_plan;
  summary_.moves_cut += *dropped;
  bind_roles({&robot});
  report("join", robot.id, "joined the plan at " + planner_core::to_string(cell));
  spdlog::info("lifelong: robot {} joins the plan at {} ({} moves into its cell, or waiting on them, dropped)",
               robot.id, planner_core::to_string(cell), *dropped);
  mark_visits_of_moves_left();
  restart_window_planner();
  return true;
}

void FleetCoordinator::mark_visits_of_moves_left() {
  // Visits of moves dropped are not planned any more; those of the moves left still are.
  planned_visits_.clear();
  for (int a = 0; a < plan_->agent_count(); ++a) {
    const int role = role_of_agent(a);
    if (role < 0) continue;
    for (int index = plan_->agent(a).finished; index < plan_->move_count(a); ++index) {
      const planner_core::Cell cell = plan_->target(a, index);
      mark_planned_visit(role, mission_vertex(cell.x, cell.y));
    }
  }
}

void FleetCoordinator::restart_window_planner() {
  const std::shared_ptr<const planner_core::Graph>& graph = plan_->graph();
  std::set<Vertex> walls;
  for (const auto& [a, may_take_back] : agents_out_) {
    walls.insert(graph->vertex_at(plan_->position(a)));
    if (plan_->in_flight(a)) walls.insert(graph->vertex_at(plan_->target(a, plan_->agent(a).sent)));
  }
  walls.erase(planner_core::kNoVertex);
  const auto map = walls.empty() ? graph : std::make_shared<const planner_core::Graph>(graph->with_walls(walls));
  windows_.reset();  // a window under way is cut short
  windows_ = std::make_unique<WindowWorker>(std::make_unique<WindowPlanner>(
      map, static_cast<uint32_t>(config_.seed) + static_cast<uint32_t>(epoch_), mission_.actions,
      window_settings(config_.lifelong_planner, *map, static_cast<size_t>(plan_->agent_count()), mission_.actions)));
}

void FleetCoordinator::credit_visits_at_rest() {
  // A robot that ended its moves on the cell of a task added since: that is its visit.
  for (int a = 0; a < plan_->agent_count(); ++a) {
    const RobotRecord* robot = robot_of_agent(a);
    if (robot != nullptr && robot->active && robot->role >= 0 && plan_->done(a)) {
      credit_visits(robot->role, mission_vertex(robot->last.cell_x, robot->last.cell_y), robot->id);
    }
  }
}

bool FleetCoordinator::rebalance_pool_tasks(const std::vector<WindowAgent>& agents) {
  // The pool: tasks added at runtime for any robot, neither done nor cancelled, whose visit the
  // plan has not reached.
  std::vector<PooledTask> pooled;
  for (int t = progress_.mission_task_count(); t < mission_.task_count(); ++t) {
    if (mission_.tasks[t].agents.size() != 1 || progress_.task_done(t) || progress_.cancelled(t) ||
        progress_.visited(t, 0) || planned_visits_.count({t, 0}) || pinned_tasks_.count(t)) {
      continue;
    }
    pooled.push_back({t, mission_.tasks[t].at, mission_.tasks[t].agents.front()});  // holder: a role for now
  }
  if (pooled.empty()) return false;
  // One pool robot per plan agent with a role, where its plan ends, with the task cells it still
  // heads for (window_agents' errands); then one per role holding a pooled task without a robot.
  const planner_core::Graph& graph = *plan_->graph();
  const planner_core::Config& last = plan_->last_configuration();
  std::vector<PoolRobot> robots;
  std::vector<int> role_of_robot;
  std::map<int, int> robot_of_role;
  for (int a = 0; a < plan_->agent_count(); ++a) {
    const int role = role_of_agent(a);
    if (role < 0) continue;
    PoolRobot robot;
    const planner_core::Cell end = graph.cell_of(last[a]);
    robot.from = mission_vertex(end.x, end.y);
    robot.out = robot.from == planner_core::kNoVertex;  // not on the mission's map: takes nothing
    for (const Vertex errand : agents[a].errands) {
      const planner_core::Cell cell = graph.cell_of(errand);
      if (const Vertex at = mission_vertex(cell.x, cell.y); at != planner_core::kNoVertex) robot.errands.push_back(at);
    }
    robot_of_role[role] = static_cast<int>(robots.size());
    robots.push_back(std::move(robot));
    role_of_robot.push_back(role);
  }
  for (PooledTask& task : pooled) {
    if (!robot_of_role.count(task.holder)) {
      robot_of_role[task.holder] = static_cast<int>(robots.size());
      robots.push_back({planner_core::kNoVertex, {}, /*out=*/true});
      role_of_robot.push_back(task.holder);
    }
    task.holder = robot_of_role[task.holder];
  }
  const std::vector<TaskMove> moves = rebalance_pool(task_distances(), robots, pooled);
  for (const TaskMove& move : moves) {
    const int role = role_of_robot[move.to];
    const std::string& robot_id = progress_.robot_of(role);
    // A journal that fails here stops recording, and the mission goes on from memory (journal_write).
    journal_write("task reassigned", [&](MissionJournal& journal) {
      if (move.task < journaled_tasks_) journal.record_task_role(move.task, role);
    });
    mission_.tasks[move.task].agents = {role};
    const std::string why =
        move.holder_way < 0
            ? fmt::format("task {} goes to robot {} ({} steps away): its robot is out", move.task, robot_id, move.way)
            : fmt::format("task {} goes to robot {}, {} steps away, before role {}'s robot ({} steps on its way)",
                          move.task, robot_id, move.way, role_of_robot[move.from], move.holder_way);
    spdlog::info("lifelong pool: {}", why);
    report("task_reassigned", robot_id, why, move.task);
  }
  if (moves.empty()) return false;
  mission_.index_tasks();
  summary_.tasks_reassigned += static_cast<int64_t>(moves.size());
  desk_.mission_changed();
  schedule_.progress_changed();
  return true;
}

std::vector<WindowAgent> FleetCoordinator::window_agents() const {
  const planner_core::Graph& graph = *plan_->graph();
  const planner_core::Config& last = plan_->last_configuration();
  std::vector<WindowAgent> agents(plan_->agent_count());
  for (int a = 0; a < plan_->agent_count(); ++a) {
    agents[a].park = last[a];
    agents[a].held = agents_out_.count(a) > 0;
    const int role = role_of_agent(a);
    if (role < 0 || agents[a].held) continue;  // an extra robot stays where it is
    const Vertex goal = graph.vertex_at(mission_.graph->cell_of(mission_.goals[role]));
    if (goal != planner_core::kNoVertex) agents[a].park = goal;
    for (int t : mission_.tasks_of_agent[role]) {
      const std::vector<int>& roles = mission_.tasks[t].agents;
      for (size_t k = 0; k < roles.size(); ++k) {
        if (roles[k] != role || progress_.visited(t, k) || planned_visits_.count({t, k})) continue;
        const Vertex cell = graph.vertex_at(mission_.graph->cell_of(mission_.tasks[t].at));
        if (cell != planner_core::kNoVertex) agents[a].errands.push_back(cell);
      }
    }
  }
  return agents;
}

void FleetCoordinator::mark_planned_visits(const planner_core::Solution& steps) {
  // A robot reaching a cell under the plan makes every visit its role owes there (credit_visits).
  const planner_core::Graph& graph = *plan_->graph();
  for (int a = 0; a < plan_->agent_count(); ++a) {
    const int role = role_of_agent(a);
    if (role < 0) continue;
    for (const planner_core::Config& configuration : steps) {
      const planner_core::Cell cell = graph.cell_of(configuration[a]);
      mark_planned_visit(role, mission_vertex(cell.x, cell.y));
    }
  }
}

void FleetCoordinator::mark_planned_visit(int role, Vertex at) {
  for (int t : mission_.tasks_of_agent[role]) {
    const std::vector<int>& roles = mission_.tasks[t].agents;
    for (size_t k = 0; k < roles.size(); ++k) {
      if (roles[k] == role && mission_.tasks[t].at == at && !progress_.visited(t, k)) planned_visits_.insert({t, k});
    }
  }
}

void FleetCoordinator::note_waits_for_window(const std::vector<int>& out_of_moves) {
  // Those whose next move may go at once stood still only for want of this window.
  const Clock::time_point now = Clock::now();
  bool late = false;
  for (const int a : out_of_moves) {
    if (!plan_->ready_to_move(a)) continue;  // it waits on another robot's move: the plan's order
    const Clock::time_point since = std::max(plan_->agent(a).finished_at, plan_grew_at_);
    const double waited_ms = std::chrono::duration<double, std::milli>(now - since).count();
    summary_.robot_s_waiting_for_windows += waited_ms / 1000;
    summary_.wait_for_window_ms_max = std::max(summary_.wait_for_window_ms_max, waited_ms);
    late = true;
  }
  if (late) ++summary_.windows_late;
}

void FleetCoordinator::note_window(const PlanWindow& window, double planning_ms) {
  ++summary_.windows;
  summary_.window_ms_max = std::max(summary_.window_ms_max, planning_ms);
  summary_.last_planning_ms = planning_ms;
  int reached = 0;
  for (const auto& cells : window.reached) reached += static_cast<int>(cells.size());
  spdlog::debug("lifelong window {}: {} steps to plan step {}, {} task visits taken up, planned in {:.1f} ms",
                summary_.windows, window.steps.size() - 1, plan_->plan_steps(), reached, planning_ms);
}

}  // namespace coordinator
