#include "dashboard/playback.hpp"

#include <algorithm>

#include "dashboard/message_json.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/validator.hpp"

namespace dashboard {

namespace {

constexpr uint64_t kViewer = 1;  // the "coordinator" of a plan shown without a fleet

std::string robot_name(int agent) { return "agent" + std::to_string(agent); }

}  // namespace

void RecordedPlayback::play_until(int64_t until_ms, const std::function<void(const HistoryEntry&)>& apply) {
  while (next_ < entries_.size() && entries_[next_].t_ms <= until_ms) apply(entries_[next_++]);
}

PlanPlayback::PlanPlayback(const planner_core::Instance& instance, planner_core::Solution solution, int64_t step_ms,
                           const std::string& plan_source)
    : instance_(instance), solution_(std::move(solution)), step_ms_(step_ms) {
  if (solution_.empty()) throw planner_core::InputError(plan_source + ": no timesteps in it");
  const planner_core::ValidationReport report = planner_core::validate(instance_, solution_);
  if (!report.ok()) {
    std::string first = report.summary(1);
    first = first.substr(0, first.find('\n'));
    throw planner_core::InputError(plan_source + ": not a valid plan of " + instance_.source + ": " + first + " (" +
                                   std::to_string(report.violations.size()) + " faults in all)");
  }
  flowtime_ = report.flowtime;
  makespan_ = report.makespan;
}

void PlanPlayback::play_until(int64_t until_ms, const std::function<void(const HistoryEntry&)>& apply) {
  if (!started_) {
    play_start(apply);
    started_ = true;
  }
  while (next_step_ < solution_.size() && static_cast<int64_t>(next_step_) * step_ms_ <= until_ms) {
    play_step(next_step_++, apply);
  }
}

void PlanPlayback::play_start(const std::function<void(const HistoryEntry&)>& apply) {
  const planner_core::Graph& map = *instance_.graph;
  apply({0, "coordinator",
         fleet_transport::CoordinatorStatus{kViewer, 1, 0, fleet_transport::CoordinatorRole::kActive, "plan", 1}});
  fleet_transport::MissionInfo mission;
  mission.coordinator = kViewer;
  mission.mission_id = "plan";
  mission.width = map.width();
  mission.height = map.height();
  for (int y = 0; y < map.height(); ++y) {
    if (y > 0) mission.map_rows += '\n';
    for (int x = 0; x < map.width(); ++x) mission.map_rows += map.is_free({x, y}) ? '.' : '@';
  }
  const auto cell = [&](planner_core::Vertex v) {
    const planner_core::Cell c = map.cell_of(v);
    return fleet_transport::GridCell{c.x, c.y};
  };
  for (planner_core::Vertex goal : instance_.goals) mission.goals.push_back(cell(goal));
  for (const planner_core::Task& task : instance_.tasks) {
    const fleet_transport::GridCell at = cell(task.at);
    mission.tasks.push_back({at.x, at.y, task.agents, false});
  }
  apply({0, "mission", mission});
  fleet_transport::FleetEvent verdict{kViewer, 0, "replan", "", "", 0};
  verdict.text = "plan of " + instance_.source + ": valid, flowtime " + std::to_string(flowtime_) + ", makespan " +
                 std::to_string(makespan_) + ", " + std::to_string(instance_.agent_count()) + " agents";
  apply({0, "event", verdict});
}

void PlanPlayback::play_step(size_t t, const std::function<void(const HistoryEntry&)>& apply) {
  const planner_core::Graph& map = *instance_.graph;
  const int agents = instance_.agent_count();
  const int64_t at = static_cast<int64_t>(t) * step_ms_;
  const int epoch = epoch_of(t);
  const size_t window_start = static_cast<size_t>(epoch - 1) * kPlanWindow;
  if (t == window_start && t + 1 < solution_.size()) {  // the next window of the plan
    const size_t window_end = std::min(solution_.size(), window_start + kPlanWindow + 1);
    fleet_transport::FleetPlan plan{kViewer, epoch, at, 0, flowtime_, {}};
    plan.robots.reserve(agents);
    for (int j = 0; j < agents; ++j) {
      fleet_transport::RobotPlan part{robot_name(j), j, {}};
      part.path.reserve(window_end - window_start);
      for (size_t k = window_start; k < window_end; ++k) {
        const planner_core::Cell c = map.cell_of(solution_[k][j]);
        part.path.push_back({c.x, c.y});
      }
      plan.robots.push_back(std::move(part));
    }
    apply({at, "plan", plan});
  }
  for (int j = 0; j < agents; ++j) {
    const planner_core::Cell here = map.cell_of(solution_[t][j]);
    fleet_transport::RobotState state;
    state.robot_id = robot_name(j);
    state.cell_x = here.x;
    state.cell_y = here.y;
    state.pose_x = here.x;
    state.pose_y = here.y;
    state.plan_epoch = epoch;
    state.coordinator = kViewer;
    state.incarnation = 1;
    state.seq_number = 2 * t + 1;
    state.stamp_ms = at;
    state.action_index = static_cast<int>(t - window_start) - 1;  // arrived at the target of the step before
    state.status = fleet_transport::RobotStatus::kArrived;
    apply({at, "state", state});
    if (t + 1 < solution_.size()) {  // on its way to the next step's cell
      state.action_index = static_cast<int>(t - window_start);
      state.status = fleet_transport::RobotStatus::kMoving;
      state.seq_number = 2 * t + 2;
      apply({at + 1, "state", state});
    }
    for (int task : instance_.tasks_of_agent[j]) {
      if (instance_.tasks[task].at == solution_[t][j] && visits_done_.insert({task, j}).second) {
        visit_list_.push_back({task, j});
        const auto& roles = instance_.tasks[task].agents;
        tasks_done_ += std::all_of(roles.begin(), roles.end(), [&](int r) { return visits_done_.count({task, r}) > 0; });
      }
    }
  }
  fleet_transport::FleetStatus status{kViewer, epoch, tasks_done_, instance_.task_count(), agents, {}, visit_list_};
  for (int j = 0; j < agents; ++j) status.assignments.push_back({robot_name(j), j, 0, 0});
  status.steps_done = static_cast<int64_t>(t) * agents;
  status.steps_planned = static_cast<int64_t>(solution_.size() - 1) * agents;
  apply({at, "status", status});
  apply({at, "coordinator",
         fleet_transport::CoordinatorStatus{kViewer, 1, epoch, fleet_transport::CoordinatorRole::kActive, "plan", 1}});
}

std::vector<HistoryEntry> all_entries(Playback& playback) {
  std::vector<HistoryEntry> out;
  playback.play_until(playback.end_ms() + 1, [&](const HistoryEntry& entry) { out.push_back(entry); });
  return out;
}

}  // namespace dashboard
