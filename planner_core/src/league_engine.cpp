#include "planner_core/league_engine.hpp"

#include <algorithm>
#include <chrono>

#include "planner_core/step_faults.hpp"

namespace planner_core {

LeagueEngine::LeagueEngine(const LorrProblem& problem, LifelongPlanner& planner, TaskScheduler scheduler,
                           int lead_steps)
    : graph_(*problem.graph),
      planner_(planner),
      lead_steps_(std::max(1, lead_steps)),
      distances_(graph_),
      board_(problem, problem.starts, nullptr, scheduler, Headings(problem.starts.size(), 0)),
      planned_{problem.starts, Headings(problem.starts.size(), 0)},
      staged_(Solution{problem.starts}, HeadingPlan{planned_.headings}),
      errands_(problem.starts.size()) {}

void LeagueEngine::prepare(const Deadline& deadline) { planner_.prepare(planned_, goals(), deadline); }

Config LeagueEngine::goals() const {
  Config goals(planned_.cells.size());
  for (size_t r = 0; r < goals.size(); ++r) {
    const bool held = r < held_.size() && held_[r];
    goals[r] = held || board_.goal(static_cast<int>(r)) == kNoVertex ? planned_.cells[r] : board_.goal(static_cast<int>(r));
  }
  return goals;
}

int LeagueEngine::executed_step(int r, int moves_finished) const {
  if (moves_finished < staged_.move_count(r)) return staged_.move(r, moves_finished).plan_time - 1;
  return staged_.plan_steps();
}

bool LeagueEngine::errand_due(int r, int moves_finished) const {
  return !errands_[r].empty() && errands_[r].front().plan_step <= executed_step(r, moves_finished);
}

LeagueEngine::PlanCall LeagueEngine::plan(const std::vector<int>& moves_finished, double budget_s,
                                          const std::atomic<bool>* interrupt) {
  PlanCall call;
  const int team = robots();
  std::vector<int> executed(team);
  for (int r = 0; r < team; ++r) executed[r] = executed_step(r, moves_finished[r]);
  std::nth_element(executed.begin(), executed.begin() + team / 2, executed.end());
  const int lead = staged_.plan_steps() - executed[team / 2];
  call.steps = std::clamp(lead_steps_ - lead, 0, lead_steps_);
  if (call.steps == 0) {
    held_.clear();
    return call;
  }
  const auto started = std::chrono::steady_clock::now();
  const double step_budget_s = budget_s / call.steps;
  Solution cells{planned_.cells};
  HeadingPlan headings{planned_.headings};
  for (int s = 0; s < call.steps; ++s) {
    const auto step_started = std::chrono::steady_clock::now();
    Poses next = planner_.next_step(planned_, goals(), Deadline::in_seconds(step_budget_s, interrupt));
    const int step = staged_.plan_steps() + s + 1;
    if (elapsed_ms(step_started) > 1000 * step_budget_s) {
      ++call.late_steps;
      next = planned_;
    } else if (const StepFault fault = find_pose_fault(graph_, ActionModel::kRotate, planned_, next);
               !fault.what.empty()) {
      if (call.invalid_steps++ == 0) call.first_invalid = "plan step " + std::to_string(step) + ": " + fault.what;
      next = planned_;
    }
    planned_ = next;
    board_.set_time(step);
    cells.push_back(planned_.cells);
    headings.push_back(planned_.headings);
    reach_errands(step);
  }
  staged_.extend(cells, headings);
  held_.clear();
  call.ms = elapsed_ms(started);
  return call;
}

void LeagueEngine::reach_errands(int step) {
  for (int r = 0; r < robots(); ++r) {
    const int64_t task = board_.task_of(r);
    const int done_before = board_.errands_done(r);
    int64_t tasks_finished = 0;
    if (!board_.arrive(r, planned_.cells[r], planned_.headings[r], distances_, tasks_finished)) continue;
    errands_[r].push_back({step, task, done_before + 1, tasks_finished > 0, board_.task_of(r)});
  }
}

}  // namespace planner_core
