#include "planner_core/task_scheduler.hpp"

#include "planner_core/input_error.hpp"

namespace planner_core {

namespace {

constexpr const char* kSchedulerNames[] = {"round-robin", "nearest-errand", "whole-task", "whole-task-reassign"};

}  // namespace

TaskScheduler scheduler_for(TaskAssignment assignment) {
  switch (assignment) {
    case TaskAssignment::kRoundRobin: return TaskScheduler::kRoundRobin;
    case TaskAssignment::kGreedy: return TaskScheduler::kNearestErrand;
    case TaskAssignment::kPool: break;
  }
  return TaskScheduler::kWholeTaskReassign;
}

std::string to_string(TaskScheduler scheduler) { return kSchedulerNames[static_cast<int>(scheduler)]; }

TaskScheduler parse_task_scheduler(const std::string& text, const std::string& what) {
  for (int k = 0; k < 4; ++k) {
    if (text == kSchedulerNames[k]) return static_cast<TaskScheduler>(k);
  }
  throw InputError(what + ": '" + text + "' is not round-robin, nearest-errand, whole-task or whole-task-reassign");
}

}  // namespace planner_core
