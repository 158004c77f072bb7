// The lifelong run loop: each step the planner decides within its budget; a late or invalid step
// is replaced by everyone waiting; errands finished are counted.
#include "planner_core/lifelong.hpp"

#include <chrono>

#include "planner_core/dist_table.hpp"
#include "planner_core/task_board.hpp"

namespace planner_core {

namespace {

// The league's letter for agent a's step from `now` to `next`: in four moves U D L R (row up, row
// down, column left, column right); in the rotation model F (forward), R (clockwise), C
// (counter-clockwise); W for staying, T for no action (no step open to the agent).
char action_letter(const Graph& graph, ActionModel model, const Poses& now, const Poses& next, size_t a) {
  const Vertex from = now.cells[a];
  const Vertex to = next.cells[a];
  if (to < 0 || to >= graph.vertex_count()) return 'T';
  if (model == ActionModel::kRotate) {
    if (a >= next.headings.size()) return 'T';
    const int heading = now.headings[a];
    if (to == from) {
      if (next.headings[a] == heading) return 'W';
      if (next.headings[a] == turned_clockwise(heading)) return 'R';
      return next.headings[a] == turned_counter_clockwise(heading) ? 'C' : 'T';
    }
    return to == ahead(graph, from, heading) && next.headings[a] == heading ? 'F' : 'T';
  }
  if (to == from) return 'W';
  if (!graph.adjacent(from, to)) return 'T';
  const Cell a_cell = graph.cell_of(from);
  const Cell b_cell = graph.cell_of(to);
  if (b_cell.y < a_cell.y) return 'U';
  if (b_cell.y > a_cell.y) return 'D';
  return b_cell.x < a_cell.x ? 'L' : 'R';
}

}  // namespace

LifelongResult run_lifelong(const LorrProblem& problem, LifelongPlanner& planner, const LifelongSettings& settings) {
  const Graph& graph = *problem.graph;
  const ActionModel model = settings.actions;
  Poses now{problem.starts, {}};
  if (model == ActionModel::kRotate) now.headings.assign(now.cells.size(), 0);  // east, as the league starts
  Config& positions = now.cells;
  const int team = static_cast<int>(positions.size());
  LifelongLog* log = settings.log;
  if (log != nullptr) {
    *log = LifelongLog{};
    log->actions = model;
    log->start_headings = now.headings;
    log->starts = positions;
    log->actual.assign(team, "");
    log->planned.assign(team, "");
    log->events.assign(team, {});
    log->cost.assign(team, 0);
  }
  DistTable distances(graph);
  TaskBoard board(problem, positions, log, settings.scheduler.value_or(scheduler_for(problem.assignment)), now.headings);
  LifelongResult result;
  const auto current_goals = [&] {
    Config goals(team);
    for (int a = 0; a < team; ++a) goals[a] = board.goal(a) == kNoVertex ? positions[a] : board.goal(a);
    return goals;
  };
  {
    const auto started = std::chrono::steady_clock::now();
    planner.prepare(now, current_goals(), Deadline::in_seconds(settings.preprocess_time_s, settings.interrupt));
    result.preprocess_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  }
  for (int step = 0; step < settings.steps; ++step) {
    if (settings.interrupt != nullptr && settings.interrupt->load()) {
      result.interrupted = true;
      break;
    }
    const Config goals = current_goals();
    const auto started = std::chrono::steady_clock::now();
    Poses next = planner.next_step(now, goals, Deadline::in_seconds(settings.step_time_s, settings.interrupt));
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
    result.step_ms.push_back(ms);
    const bool late = ms > 1000 * settings.step_time_s;
    if (log != nullptr) {
      for (int a = 0; a < team; ++a) {
        if (step > 0) log->planned[a] += ',';
        const bool dropped = (late && !settings.late_steps_taken) || next.cells.size() != positions.size();
        log->planned[a] += dropped ? 'T' : action_letter(graph, model, now, next, a);
        if (board.goal(a) != kNoVertex) ++log->cost[a];
      }
    }
    if (late) ++result.steps_over_budget;
    if (late && !settings.late_steps_taken) {
      next = now;
    } else if (const StepFault fault = find_pose_fault(graph, model, now, next); !fault.what.empty()) {
      if (result.invalid_steps++ == 0) result.first_invalid = "step " + std::to_string(step) + ": " + fault.what;
      if (log != nullptr) log->errors.push_back({fault.agent1, fault.agent2, step, fault.what});
      next = now;
    }
    board.set_time(step + 1);
    int finished = 0;
    for (int a = 0; a < team; ++a) {
      result.moves += next.cells[a] != positions[a] ? 1 : 0;
      if (log != nullptr) {
        if (step > 0) log->actual[a] += ',';
        log->actual[a] += action_letter(graph, model, now, next, a);
      }
      positions[a] = next.cells[a];
      if (model == ActionModel::kRotate) now.headings[a] = next.headings[a];
      // One errand per agent and step, as the league counts: a next errand on the same cell is
      // finished at the next step.
      const int heading = model == ActionModel::kRotate ? now.headings[a] : 0;
      if (board.arrive(a, positions[a], heading, distances, result.tasks_finished)) ++finished;
    }
    result.errands_finished += finished;
    result.errands_per_step.push_back(finished);
  }
  return result;
}

}  // namespace planner_core
