// MissionProgress: which robot holds each of the mission's roles, and which task visits are done.
// A task shared by several roles is done when every one of their robots has visited its cell
// under the plan. Plain data with rules; no DDS, no clock, tested on its own.
#pragma once

#include <string>
#include <vector>

#include "fleet_transport/messages.hpp"
#include "planner_core/instance.hpp"

namespace coordinator {

class MissionProgress {
 public:
  // `mission` must outlive this object (the coordinator owns both).
  explicit MissionProgress(const planner_core::Instance& mission);

  int role_count() const { return static_cast<int>(robot_of_role_.size()); }
  // The robot holding `role`, "" when none.
  const std::string& robot_of(int role) const { return robot_of_role_[role]; }
  bool any_role_free() const;
  void bind(int role, const std::string& robot_id) { robot_of_role_[role] = robot_id; }
  void unbind(int role) { robot_of_role_[role].clear(); }

  // The visits `role` owes at `cell` and has not made yet.
  std::vector<fleet_transport::TaskVisit> visits_due_at(int role, planner_core::Vertex cell) const;
  // Marks a visit done; false when it names no task or role of the mission (nothing changes).
  bool mark(const fleet_transport::TaskVisit& visit);
  // The robot of `role` stands on `cell` under the plan: its visits to tasks there are done.
  void visit(int role, planner_core::Vertex cell);
  // Every visit done, for the fleet status and the journal.
  std::vector<fleet_transport::TaskVisit> done_visits() const;
  // Whether task t's k-th role (mission.tasks[t].agents[k]) has visited, or need not (cancelled).
  bool visited(int task, size_t k) const { return task_done_[task][k] != 0 || cancelled_[task]; }
  int task_count() const { return static_cast<int>(task_done_.size()); }
  // The mission's own tasks, those it was made with; tasks added at runtime (add_task) come after.
  int mission_task_count() const { return mission_task_count_; }
  // The mission has a new task, appended to its tasks (mission.tasks.back()), none of it done.
  void add_task();
  // No visit to `task` is owed any more; it counts neither as done nor as to do. False when it
  // is no task, or is done or cancelled already.
  bool cancel(int task);
  bool cancelled(int task) const { return cancelled_[task] != 0; }
  bool task_done(int task) const;
  // Tasks not cancelled.
  int tasks_to_do() const;
  // Tasks (not cancelled) every one of whose roles has visited.
  int tasks_done() const;
  bool all_tasks_done() const { return tasks_done() == tasks_to_do(); }
  // (tasks of the role, of which visited) for the fleet status.
  std::pair<int, int> role_tasks(int role) const;
  // Some visit is owed by a role that has no robot.
  bool work_waits_for_a_robot() const;
  // One line per task visit not done, naming its role and robot.
  std::vector<std::string> pending_visits() const;

 private:
  const planner_core::Instance& mission_;
  std::vector<std::string> robot_of_role_;
  std::vector<std::vector<char>> task_done_;  // [task][index in task.agents]
  std::vector<char> cancelled_;               // [task]
  int mission_task_count_ = 0;
};

}  // namespace coordinator
