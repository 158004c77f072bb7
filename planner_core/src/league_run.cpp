// The 2026 rules' run loop: the engine (league_engine.hpp) called every plan period, delays, the
// staged plan carried out tick by tick as the Action Dependency Graph allows, and a check of
// every tick (league_run.hpp).
#include "planner_core/league_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "planner_core/delay_draws.hpp"
#include "planner_core/league_engine.hpp"

namespace planner_core {

namespace {

struct Robot {
  Vertex cell;
  int heading = 0;     // east, as the league starts
  int progress = 0;    // ticks spent on the move under way (0: none under way)
  int finished = 0;    // moves of the staged plan finished
  Vertex checked = kNoVertex;  // its cell at the last tick's check
};

// A period's worth of actions, rounded up, times settings.lead_periods (1.5: half as much again to
// carry the fleet over the next call), rounded.
int lead_steps_for(const LorrProblem& problem, const LeagueRunSettings& settings) {
  if (settings.tick_ms <= 0 || settings.plan_period_ms <= 0 || settings.plan_period_ms % settings.tick_ms != 0) {
    throw std::invalid_argument("the planning period must be a whole number of ticks");
  }
  const int period_ticks = settings.plan_period_ms / settings.tick_ms;
  const int per_period = (period_ticks + problem.ticks_per_action - 1) / problem.ticks_per_action;
  return std::max(1, static_cast<int>(std::lround(per_period * settings.lead_periods)));
}

class LeagueRun {
 public:
  LeagueRun(const LorrProblem& problem, LifelongPlanner& planner, const LeagueRunSettings& settings)
      : problem_(problem),
        graph_(*problem.graph),
        settings_(settings),
        team_(static_cast<int>(problem.starts.size())),
        ticks_per_action_(problem.ticks_per_action),
        engine_(problem, planner, settings.scheduler.value_or(scheduler_for(problem.assignment)),
                lead_steps_for(problem, settings)),
        period_ticks_(settings.plan_period_ms / settings.tick_ms),
        held_by_(graph_.vertex_count(), -1),
        held_stamp_(graph_.vertex_count(), 0) {
    for (Vertex start : problem.starts) robots_.push_back(Robot{start});
    if (settings.delays && problem.delays) draws_.emplace(*problem.delays, team_);
    if (LeagueLog* log = settings.log) {
      *log = LeagueLog{};
      log->starts = problem.starts;
      log->start_headings.assign(team_, 0);
      log->actual.assign(team_, "");
      log->delay_intervals.assign(team_, {});
      log->schedule.assign(team_, {});
    }
    for (int r = 0; r < team_; ++r) note_task(r, 0, engine_.task_of(r));
  }

  LeagueRunResult run() {
    {
      const auto started = std::chrono::steady_clock::now();
      engine_.prepare(Deadline::in_seconds(settings_.preprocess_time_s, settings_.interrupt));
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
    result_.reassignments = engine_.reassignments();
    if (settings_.log != nullptr) settings_.log->tasks_revealed = tasks_revealed_;
    return result_;
  }

 private:
  void plan_period() {
    std::vector<int> finished(team_);
    for (int r = 0; r < team_; ++r) finished[r] = robots_[r].finished;
    if (draws_ && settings_.plan_round_delayed) {
      std::vector<char> held(team_, 0);
      for (int r = 0; r < team_; ++r) held[r] = draws_->ticks_left(r) > ticks_per_action_ ? 1 : 0;
      engine_.hold(std::move(held));
    }
    const LeagueEngine::PlanCall call = engine_.plan(finished, settings_.plan_period_ms / 1000.0, settings_.interrupt);
    if (call.steps == 0) return;
    result_.plan_steps += call.steps;
    result_.late_steps += call.late_steps;
    if (call.invalid_steps > 0 && result_.invalid_steps == 0) result_.first_invalid = call.first_invalid;
    result_.invalid_steps += call.invalid_steps;
    result_.plan_ms.push_back(call.ms);
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
      letters[r] = letter_of(engine_.staged().move(r, robot.finished), robot.heading);
      if (++robot.progress == ticks_per_action_) finish_move(r);
    }
  }

  // A robot free and not delayed, with no errand due where it stands, starts its next move once
  // the Action Dependency Graph allows it.
  void start_ready_moves(std::vector<char>& letters) {
    const ActionDependencyGraph& staged = engine_.staged();
    const auto finished_of = [this](int other) { return robots_[other].finished; };
    for (int r = 0; r < team_; ++r) {
      Robot& robot = robots_[r];
      if (robot.progress != 0 || letters[r] != 'W' || delayed(r) || engine_.errand_due(r, robot.finished)) continue;
      if (robot.finished >= staged.move_count(r) || !staged.ready(r, robot.finished, finished_of)) continue;
      letters[r] = letter_of(staged.move(r, robot.finished), robot.heading);
      robot.progress = 1;
      if (ticks_per_action_ == 1) finish_move(r);
    }
  }

  void finish_move(int r) {
    Robot& robot = robots_[r];
    const Move& move = engine_.staged().move(r, robot.finished);
    robot.cell = move.to;
    robot.heading = move.heading;
    robot.progress = 0;
    ++robot.finished;
    ++result_.moves_finished;
    engine_.staged().forget_before(r, robot.finished);
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
        const Move& move = engine_.staged().move(r, robot.finished);
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
  // stays for it (start_ready_moves). Returns the tasks finished; `counted` marks the robots that
  // finished an errand this tick.
  int count_errands(int tick, std::vector<char>& counted) {
    int tasks = 0;
    for (int r = 0; r < team_; ++r) {
      Robot& robot = robots_[r];
      if (counted[r] || !engine_.errand_due(r, robot.finished)) continue;
      counted[r] = 1;
      const LeagueEngine::Errand& errand = *engine_.next_errand(r);
      if (robot.cell != problem_.tasks[errand.task % problem_.tasks.size()][errand.errands_done - 1]) {
        fault(tick, r, -1, "robot " + std::to_string(r) + " finished an errand away from it");
      }
      ++result_.errands_finished;
      if (errand.task_finished) {
        ++tasks;
        note_task(r, tick + 1, errand.next_task);
      }
      if (settings_.log != nullptr) settings_.log->events.push_back({tick + 1, r, errand.task, errand.errands_done});
      engine_.errand_counted(r);
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
  const LeagueRunSettings& settings_;
  const int team_;
  const int ticks_per_action_;
  LeagueEngine engine_;
  const int period_ticks_;
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
