// Which rule hands a lifelong run's tasks to its agents (TaskBoard, task_board.hpp, carries it out).
#pragma once

#include <string>

#include "planner_core/lorr_problem.hpp"

namespace planner_core {

enum class TaskScheduler { kRoundRobin, kNearestErrand, kWholeTask, kWholeTaskReassign };

// The scheduler a problem's rules name: its taskAssignmentStrategy, or ours for a pool.
TaskScheduler scheduler_for(TaskAssignment assignment);
// "round-robin", "nearest-errand", "whole-task", "whole-task-reassign"; parse throws InputError
// naming `what` and the choices.
std::string to_string(TaskScheduler scheduler);
TaskScheduler parse_task_scheduler(const std::string& text, const std::string& what);

}  // namespace planner_core
