// The 2026 rules' run loop: plan periods extending the staged plan, delays, the Action Dependency
// Graph carrying the plan out tick by tick, and a check of every tick (league_run.hpp).
#include "planner_core/league_run.hpp"

#include <algorithm>
#include <chrono>
#include <deque>
#include <optional>
#include <stdexcept>

#include "planner_core/action_dependency_graph.hpp"
#include "planner_core/delay_draws.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/task_board.hpp"

namespace planner_core {

namespace {

// An errand the plan reaches at `plan_step`: finished when its robot has carried the plan out
// that far.
struct PlannedErrand {
  int plan_step;
  int64_t task;
  int errands_done;   // of the task, this one included
  bool task_finished;
  int64_t next_task;  // the robot's task after this errand (-1: none)
};

struct Robot {
  Vertex cell;
  int heading = 0;     // east, as the league starts
  int progress = 0;    // ticks spent on the move under way (0: none under way)
  int finished = 0;    // moves of the plan finished
  Vertex checked = kNoVertex;  // its cell at the last tick's check
  std::deque<PlannedErrand> errands;
};

class LeagueRun {
 public:
  LeagueRun(const LorrProblem& problem, LifelongPlanner& planner, const LeagueRunSettings& settings)
      : problem_(problem),
        graph_(*problem.graph),
        planner_(planner),
        settings_(settings),
        team_(static_cast<int>(problem.starts.size())),
        ticks_per_action_(problem.ticks_per_action),
        distances_(graph_),
        board_(problem, problem.starts, nullptr, settings.scheduler.value_or(scheduler_for(problem.assignment))),
        planned_{problem.starts, Headings(problem.starts.size(), 0)},
        adg_(Solution{problem.starts}, HeadingPlan{planned_.headings}),
        held_by_(graph_.vertex_count(), -1),
        held_stamp_(graph_.vertex_count(), 0) {
    if (settings.tick_ms <= 0 || settings.plan_period_ms <= 0 || settings.plan_period_ms % settings.tick_ms != 0) {
      throw std::invalid_argument("the planning period must be a whole number of ticks");
    }
    period_ticks_ = settings.plan_period_ms / settings.tick_ms;
    // A period's worth of actions, rounded up, and half as much again to carry the fleet over the
    // next call.
    const int per_period = (period_ticks_ + ticks_per_action_ - 1) / ticks_per_action_;
    lead_steps_ = per_period + (per_period + 1) / 2;
    for (Vertex start : problem.starts) robots_.push_back(Robot{start});
    if (settings.delays && problem.delays) draws_.emplace(*problem.delays, team_);
    if (LeagueLog* log = settings.log) {
      *log = LeagueLog{};
      log->starts = problem.starts;
      log->start_headings = planned_.headings;
      log->actual.assign(team_, "");
      log->delay_intervals.assign(team_, {});
      log->schedule.assign(team_, {});
      for (int r = 0; r < team_; ++r) note_task(r, 0, board_.task_of(r));
    }
  }

  LeagueRunResult run() {
    {
      const auto started = std::chrono::steady_clock::now();
      planner_.prepare(planned_, goals(), Deadline::in_seconds(settings_.preprocess_time_s, settings_.interrupt));
      result_.preprocess_ms = elapsed_ms(started);
    }
    for (int tick = 0; tick < settings_.ticks; ++tick) {
      if (settings_.interrupt != nullptr && settings_.interrupt->load()) {
        result_.interrupted = true;
        break;
      }
      if (tick % period_ticks_ == 0) plan_period();
      draw_delays(tick);
      std::vector<char> letters(team_, 'W');
      carry_on_moves(letters);
      std::vector<char> counted(team_, 0);
      int tasks = count_errands(tick, counted);
      start_ready_moves(letters);
      tasks += count_errands(tick, counted);  // robots whose one-tick move has just ended
      result_.tasks_finished += tasks;
      result_.tasks_per_tick.push_back(tasks);
      check_tick(tick, letters);
      result_.robot_ticks += team_;
    }
    if (draws_) result_.delayed_robot_ticks = draws_->delayed_robot_ticks();
    result_.reassignments = board_.reassignments();
    if (settings_.log != nullptr) settings_.log->tasks_revealed = tasks_revealed_;
    return result_;
  }

 private:
  static double elapsed_ms(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
  }

  Config goals() const {
    Config goals(team_);
    for (int r = 0; r < team_; ++r) goals[r] = board_.goal(r) == kNoVertex ? planned_.cells[r] : board_.goal(r);
    return goals;
  }

  // How far robot r has carried the plan out: the last plan step whose pose it stands in.
  int executed_step(int r) const {
    if (robots_[r].finished < adg_.move_count(r)) return adg_.move(r, robots_[r].finished).plan_time - 1;
    return adg_.plan_steps();
  }

  // Extends the staged plan to lead_steps_ steps ahead of the median robot, within the period.
  void plan_period() {
    std::vector<int> executed(team_);
    for (int r = 0; r < team_; ++r) executed[r] = executed_step(r);
    std::nth_element(executed.begin(), executed.begin() + team_ / 2, executed.end());
    const int lead = adg_.plan_steps() - executed[team_ / 2];
    const int steps = std::clamp(lead_steps_ - lead, 0, lead_steps_);
    if (steps == 0) return;
    const auto started = std::chrono::steady_clock::now();
    const double step_budget_s = settings_.plan_period_ms / 1000.0 / steps;
    Solution cells{planned_.cells};
    HeadingPlan headings{planned_.headings};
    for (int s = 0; s < steps; ++s) {
      const auto step_started = std::chrono::steady_clock::now();
      Poses next = planner_.next_step(planned_, goals(), Deadline::in_seconds(step_budget_s, settings_.interrupt));
      const int step = adg_.plan_steps() + s + 1;
      if (elapsed_ms(step_started) > 1000 * step_budget_s) {
        ++result_.late_steps;
        next = planned_;
      } else if (const StepFault fault = find_pose_fault(graph_, ActionModel::kRotate, planned_, next);
                 !fault.what.empty()) {
        if (result_.invalid_steps++ == 0) result_.first_invalid = "plan step " + std::to_string(step) + ": " + fault.what;
        next = planned_;
      }
      planned_ = next;
      board_.set_time(step);
      cells.push_back(planned_.cells);
      headings.push_back(planned_.headings);
      reach_errands(step);
    }
    adg_.extend(cells, headings);
    result_.plan_steps += steps;
    result_.plan_ms.push_back(elapsed_ms(started));
  }

  // The plan reaches errands at `step`: the board moves on (the next errand, or a new task), and
  // each is counted once the robot gets there.
  void reach_errands(int step) {
    for (int r = 0; r < team_; ++r) {
      const int64_t task = board_.task_of(r);
      const int done_before = board_.errands_done(r);
      int64_t unused = 0;
      if (!board_.arrive(r, planned_.cells[r], distances_, unused)) continue;
      const bool task_finished = board_.task_of(r) != task || board_.errands_done(r) == 0;
      robots_[r].errands.push_back({step, task, done_before + 1, task_finished, board_.task_of(r)});
    }
  }

  void draw_delays(int tick) {
    if (!draws_) return;
    const std::vector<int> started = draws_->tick();
    if (settings_.log == nullptr) return;
    for (int r : started) settings_.log->delay_intervals[r].push_back({tick, tick + draws_->ticks_left(r) - 1});
  }

  static char letter_of(const Move& move, int heading_before) {
    if (move.from != move.to) return 'F';
    return move.heading == turned_clockwise(heading_before) ? 'R' : 'C';
  }

  // Moves under way go on a tick, unless their robot is delayed; a move ends after agentCounter ticks.
  void carry_on_moves(std::vector<char>& letters) {
    for (int r = 0; r < team_; ++r) {
      Robot& robot = robots_[r];
      if (robot.progress == 0 || delayed(r)) continue;
      letters[r] = letter_of(adg_.move(r, robot.finished), robot.heading);
      if (++robot.progress == ticks_per_action_) finish_move(r);
    }
  }

  // A robot free and not delayed starts its next move once the Action Dependency Graph allows it.
  void start_ready_moves(std::vector<char>& letters) {
    const auto finished_of = [this](int other) { return robots_[other].finished; };
    for (int r = 0; r < team_; ++r) {
      Robot& robot = robots_[r];
      if (robot.progress != 0 || letters[r] != 'W' || delayed(r)) continue;
      if (!robot.errands.empty() && robot.errands.front().plan_step <= executed_step(r)) continue;
      if (robot.finished >= adg_.move_count(r) || !adg_.ready(r, robot.finished, finished_of)) continue;
      letters[r] = letter_of(adg_.move(r, robot.finished), robot.heading);
      robot.progress = 1;
      if (ticks_per_action_ == 1) finish_move(r);
    }
  }

  void finish_move(int r) {
    Robot& robot = robots_[r];
    const Move& move = adg_.move(r, robot.finished);
    robot.cell = move.to;
    robot.heading = move.heading;
    robot.progress = 0;
    ++robot.finished;
    ++result_.moves_finished;
    adg_.forget_before(r, robot.finished);
  }

  bool delayed(int r) const { return draws_ && draws_->delayed(r); }

  // The tick's check, apart from the executor: each robot holds its cell, and a robot moving
  // forward the cell ahead as well; no cell held twice; a cell changes only to a neighbour.
  void check_tick(int tick, const std::vector<char>& letters) {
    ++stamp_;
    const auto hold = [&](int r, Vertex cell) {
      if (held_stamp_[cell] == stamp_) {
        fault(tick, r, held_by_[cell], "two robots hold cell " + std::to_string(cell));
        return;
      }
      held_stamp_[cell] = stamp_;
      held_by_[cell] = r;
    };
    for (int r = 0; r < team_; ++r) {
      Robot& robot = robots_[r];
      if (robot.checked != kNoVertex && robot.cell != robot.checked && !graph_.adjacent(robot.checked, robot.cell)) {
        fault(tick, r, -1, "robot " + std::to_string(r) + " jumped from cell " + std::to_string(robot.checked) +
                               " to " + std::to_string(robot.cell));
      }
      robot.checked = robot.cell;
      hold(r, robot.cell);
      if (robot.progress > 0) {
        const Move& move = adg_.move(r, robot.finished);
        if (move.to != robot.cell) hold(r, move.to);
      }
      if (settings_.log != nullptr) settings_.log->actual[r] += letters[r];
    }
  }

  void fault(int tick, int r1, int r2, const std::string& what) {
    if (result_.faults++ == 0) result_.first_fault = "tick " + std::to_string(tick) + ": " + what;
    if (settings_.log != nullptr) settings_.log->errors.push_back({r1, r2, tick, what});
  }

  // A robot has reached an errand once it has carried the plan out to the errand's step; its cell
  // (the one it leaves, when a move is under way) is then the plan's cell at that step. One errand
  // per robot and tick, as the league counts: a robot with another errand due on the same cell
  // stays for it (start_ready_moves).
  // Returns the tasks finished; `counted` marks the robots that finished an errand this tick.
  int count_errands(int tick, std::vector<char>& counted) {
    int tasks = 0;
    for (int r = 0; r < team_; ++r) {
      Robot& robot = robots_[r];
      if (counted[r] || robot.errands.empty() || robot.errands.front().plan_step > executed_step(r)) continue;
      counted[r] = 1;
      const PlannedErrand& errand = robot.errands.front();
      if (robot.cell != problem_.tasks[errand.task % problem_.tasks.size()][errand.errands_done - 1]) {
        fault(tick, r, -1, "robot " + std::to_string(r) + " finished an errand away from it");
      }
      ++result_.errands_finished;
      if (errand.task_finished) {
        ++tasks;
        note_task(r, tick + 1, errand.next_task);
      }
      if (settings_.log != nullptr) settings_.log->events.push_back({tick + 1, r, errand.task, errand.errands_done});
      robot.errands.pop_front();
    }
    return tasks;
  }

  // Robot r's first task is `task` from `tick` on.
  void note_task(int r, int tick, int64_t task) {
    tasks_revealed_ = std::max(tasks_revealed_, task + 1);
    if (settings_.log == nullptr || task < 0) return;
    settings_.log->schedule[r].push_back({tick, task});
  }

  const LorrProblem& problem_;
  const Graph& graph_;
  LifelongPlanner& planner_;
  const LeagueRunSettings& settings_;
  const int team_;
  const int ticks_per_action_;
  int period_ticks_ = 1;
  int lead_steps_ = 1;
  DistTable distances_;
  TaskBoard board_;
  Poses planned_;  // where the staged plan ends
  ActionDependencyGraph adg_;
  std::vector<Robot> robots_;
  std::optional<DelayDraws> draws_;
  std::vector<int> held_by_;
  std::vector<unsigned> held_stamp_;
  unsigned stamp_ = 0;
  int64_t tasks_revealed_ = 0;
  LeagueRunResult result_;
};

}  // namespace

LeagueRunResult run_league(const LorrProblem& problem, LifelongPlanner& planner, const LeagueRunSettings& settings) {
  return LeagueRun(problem, planner, settings).run();
}

}  // namespace planner_core
