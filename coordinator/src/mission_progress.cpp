#include "coordinator/mission_progress.hpp"

#include <algorithm>

namespace coordinator {

MissionProgress::MissionProgress(const planner_core::Instance& mission)
    : mission_(mission), robot_of_role_(mission.agent_count()) {
  for (const planner_core::Task& task : mission.tasks) task_done_.emplace_back(task.agents.size(), 0);
  cancelled_.assign(task_done_.size(), 0);
  mission_task_count_ = task_count();
}

void MissionProgress::add_task() {
  task_done_.emplace_back(mission_.tasks.back().agents.size(), 0);
  cancelled_.push_back(0);
}

bool MissionProgress::task_done(int task) const {
  const std::vector<char>& visits = task_done_[task];
  return !cancelled_[task] && std::find(visits.begin(), visits.end(), 0) == visits.end();
}

bool MissionProgress::cancel(int task) {
  if (task < 0 || task >= task_count() || cancelled_[task] || task_done(task)) return false;
  cancelled_[task] = 1;
  return true;
}

int MissionProgress::tasks_to_do() const {
  return task_count() - static_cast<int>(std::count(cancelled_.begin(), cancelled_.end(), 1));
}

bool MissionProgress::any_role_free() const {
  return std::any_of(robot_of_role_.begin(), robot_of_role_.end(), [](const std::string& id) { return id.empty(); });
}

std::vector<fleet_transport::TaskVisit> MissionProgress::visits_due_at(int role, planner_core::Vertex cell) const {
  std::vector<fleet_transport::TaskVisit> due;
  for (int t : mission_.tasks_of_agent[role]) {
    const planner_core::Task& task = mission_.tasks[t];
    if (task.at != cell || cancelled_[t]) continue;
    for (size_t k = 0; k < task.agents.size(); ++k) {
      if (task.agents[k] == role && !task_done_[t][k]) due.push_back({t, role});
    }
  }
  return due;
}

bool MissionProgress::mark(const fleet_transport::TaskVisit& visit) {
  if (visit.task < 0 || visit.task >= task_count()) return false;
  const std::vector<int>& agents = mission_.tasks[visit.task].agents;
  bool found = false;
  for (size_t k = 0; k < agents.size(); ++k) {
    if (agents[k] == visit.role) {
      task_done_[visit.task][k] = 1;
      found = true;
    }
  }
  return found;
}

void MissionProgress::visit(int role, planner_core::Vertex cell) {
  for (const fleet_transport::TaskVisit& due : visits_due_at(role, cell)) mark(due);
}

std::vector<fleet_transport::TaskVisit> MissionProgress::done_visits() const {
  std::vector<fleet_transport::TaskVisit> done;
  for (int t = 0; t < task_count(); ++t) {
    for (size_t k = 0; k < task_done_[t].size(); ++k) {
      if (task_done_[t][k]) done.push_back({t, mission_.tasks[t].agents[k]});
    }
  }
  return done;
}

int MissionProgress::tasks_done() const {
  int done = 0;
  for (int t = 0; t < task_count(); ++t) done += task_done(t) ? 1 : 0;
  return done;
}

std::pair<int, int> MissionProgress::role_tasks(int role) const {
  int total = 0, visited_count = 0;
  for (int t : mission_.tasks_of_agent[role]) {
    const planner_core::Task& task = mission_.tasks[t];
    if (cancelled_[t]) continue;
    ++total;
    for (size_t k = 0; k < task.agents.size(); ++k) {
      if (task.agents[k] == role && task_done_[t][k]) ++visited_count;
    }
  }
  return {total, visited_count};
}

bool MissionProgress::work_waits_for_a_robot() const {
  for (int t = 0; t < task_count(); ++t) {
    if (cancelled_[t]) continue;
    for (size_t k = 0; k < task_done_[t].size(); ++k) {
      if (!task_done_[t][k] && robot_of_role_[mission_.tasks[t].agents[k]].empty()) return true;
    }
  }
  return false;
}

std::vector<std::string> MissionProgress::pending_visits() const {
  std::vector<std::string> lines;
  for (int t = 0; t < task_count(); ++t) {
    if (cancelled_[t]) continue;
    for (size_t k = 0; k < task_done_[t].size(); ++k) {
      if (task_done_[t][k]) continue;
      const int role = mission_.tasks[t].agents[k];
      lines.push_back("task " + std::to_string(t) + " for role " + std::to_string(role) +
                      (robot_of_role_[role].empty() ? " (no robot)" : " (robot " + robot_of_role_[role] + ")"));
    }
  }
  return lines;
}

}  // namespace coordinator
