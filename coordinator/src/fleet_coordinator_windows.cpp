// FleetCoordinator in lifelong mode: the plan in hand grows window by window while its robots
// carry it out. A task added at runtime goes to a robot by cheapest insertion (add_task) and is
// taken up by the next window: the fleet never stops to replan for it. Robots lost or joining
// still bring a whole replan (fleet_coordinator_planning.cpp), whose plan then grows in turn.
//
//   plan in hand:  [ first plan (CTS solver) | window | window | ... ]
//                                                    ^ robots carry it out here (ADG)
//   a window is planned once a robot still moving is within kLeadSteps of the plan's end, or one
//   that has made every move has tasks to go to or is not parked; unless the slowest robot has kMaxLeadSteps of
//   windows still ahead of it (windows never pile up far ahead of the fleet; the first plan's own
//   length does not count).
//
// Windows are PIBT, which can lock (two robots head-on in a dead end); a robot that comes no
// nearer where it heads for WindowPlanner::kStalledSteps planned steps brings a whole replan,
// whose solver is complete.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <stdexcept>

#include "coordinator/fleet_coordinator.hpp"
#include "planner_core/validator.hpp"
#include "fleet_coordinator_detail.hpp"

namespace coordinator {

using planner_core::Vertex;
using namespace fleet_coordinator_detail;

namespace {

constexpr int kWindowSteps = 5;      // steps a window adds at most
constexpr int kLeadSteps = 5;        // a window once a robot still moving is this close to the end
constexpr int kMaxLeadSteps = 40;    // ... unless the slowest robot has this many window steps ahead
constexpr double kWindowBudgetS = 0.25;
constexpr std::chrono::milliseconds kCheckPeriod{20};  // between two looks at whether a window is due

}  // namespace

bool FleetCoordinator::grows_by_windows(const std::string& robot_id) const {
  return config_.lifelong && phase_ == Phase::kExecuting && plan_ && windows_ && plan_->agent_of(robot_id) >= 0;
}

void FleetCoordinator::extend_plan(fleet_transport::Transport& transport) {
  if (!config_.lifelong || !plan_ || !windows_ || plan_->agent_count() == 0) return;
  // Looking through every robot's tasks costs more than a loop should, every loop (a few ms): at
  // most every kCheckPeriod, a tenth of a step at 5 steps a second; but at once when every robot
  // has run out of moves (else the loop would take the plan as finished and replan).
  const Clock::time_point now = Clock::now();
  if (now < next_window_check_ && !plan_finished()) return;
  next_window_check_ = now + kCheckPeriod;
  const int end = plan_->plan_steps();
  int slowest = end;
  bool near_the_end = false;
  for (int a = 0; a < plan_->agent_count(); ++a) {
    const RobotRecord* robot = robot_of_agent(a);
    if (robot == nullptr || !robot->active) return;  // a replan is due: its robot cannot be moved
    slowest = std::min(slowest, plan_->carried_out_until(a));
    near_the_end = near_the_end || (!plan_->done(a) && end - plan_->carried_out_until(a) <= kLeadSteps);
  }
  if (end - std::max(slowest, first_plan_steps_) > kMaxLeadSteps) return;
  credit_visits_at_rest();
  const std::vector<WindowAgent> agents = window_agents();
  // Or a robot has made every move and has tasks to go to, or is not parked yet.
  const planner_core::Config& last = plan_->last_configuration();
  for (int a = 0; a < plan_->agent_count() && !near_the_end; ++a) {
    near_the_end = plan_->done(a) && (!agents[a].errands.empty() || last[a] != agents[a].park);
  }
  if (!near_the_end) return;
  const Clock::time_point started = now;
  PlanWindow window;
  try {
    window = windows_->plan({plan_->last_configuration(), plan_->last_headings()}, agents, kWindowSteps,
                            planner_core::Deadline::in_seconds(kWindowBudgetS));
  } catch (const std::logic_error& e) {
    spdlog::critical("{}; it is not sent", e.what());
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
  int64_t moves_before = 0;
  for (int a = 0; a < plan_->agent_count(); ++a) moves_before += plan_->move_count(a);
  plan_->extend(window.steps, window.headings);
  mark_planned_visits(window.steps);
  int64_t moves_after = 0;
  for (int a = 0; a < plan_->agent_count(); ++a) moves_after += plan_->move_count(a);
  summary_.steps_planned += moves_after - moves_before;
  const double planning_ms = std::chrono::duration<double, std::milli>(Clock::now() - started).count();
  note_window(window, planning_ms);
  publish_plan(transport, 0, planning_ms);
}

void FleetCoordinator::credit_visits_at_rest() {
  // A robot that ended its moves on the cell of a task added since: that is its visit.
  for (int a = 0; a < plan_->agent_count(); ++a) {
    const RobotRecord& robot = *robot_of_agent(a);
    if (robot.role >= 0 && plan_->done(a)) {
      credit_visits(robot.role, mission_vertex(robot.last.cell_x, robot.last.cell_y), robot.id);
    }
  }
}

std::vector<WindowAgent> FleetCoordinator::window_agents() const {
  const planner_core::Graph& graph = *plan_->graph();
  const planner_core::Config& last = plan_->last_configuration();
  std::vector<WindowAgent> agents(plan_->agent_count());
  for (int a = 0; a < plan_->agent_count(); ++a) {
    agents[a].park = last[a];
    const int role = robot_of_agent(a)->role;
    if (role < 0) continue;  // an extra robot stays where it is
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
    const int role = robot_of_agent(a)->role;
    if (role < 0) continue;
    for (const planner_core::Config& configuration : steps) {
      const planner_core::Cell cell = graph.cell_of(configuration[a]);
      const Vertex at = mission_vertex(cell.x, cell.y);
      for (int t : mission_.tasks_of_agent[role]) {
        const std::vector<int>& roles = mission_.tasks[t].agents;
        for (size_t k = 0; k < roles.size(); ++k) {
          if (roles[k] == role && mission_.tasks[t].at == at && !progress_.visited(t, k)) planned_visits_.insert({t, k});
        }
      }
    }
  }
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
