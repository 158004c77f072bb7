#include "planner_core/cts_lacam.hpp"

#include <algorithm>

#include "planner_core/guided_distances.hpp"
#include "planner_core/lacam_solver.hpp"
#include "planner_core/turned_solver.hpp"
#include "planner_core/turning_execution.hpp"

namespace planner_core {

Waypoints waypoints_of(const Instance& instance, const JointSequence& sequence) {
  Waypoints waypoints(instance.agent_count());
  for (int a = 0; a < instance.agent_count(); ++a) {
    for (int task : sequence.orders[a]) waypoints[a].push_back(instance.tasks[task].at);
  }
  return waypoints;
}

CompleteSearch::CompleteSearch(const Instance& instance, DistTable& dist, const SolverConfig& config,
                               std::mt19937& rng, bool anytime, GuidedDistances* turning)
    : instance_(instance), dist_(dist), config_(config), rng_(rng), anytime_(anytime), turning_(turning) {}

CompleteSearch::~CompleteSearch() = default;

CompleteSearch::Outcome CompleteSearch::search(const Deadline& deadline, const SolveOptions& options,
                                               SolveResult& result) {
  if (!sequencer_ || !sequencer_->ready()) {
    sequencer_ = std::make_unique<JointSequencer>(instance_, dist_, config_.task_order, deadline);
    if (!sequencer_->ready()) return Outcome::kOutOfTime;
    if (result.lower_bound == 0) result.lower_bound = sequencer_->lower_bound();
    if (result.preprocessing_ms == 0) result.preprocessing_ms = elapsed_ms(options.started);
  }
  LacamConfig lacam_config{anytime_, config_.forbid_rotations, /*swap=*/true, /*prefer_free_cells=*/true};
  lacam_config.turning = turning_;
  while (!deadline.expired()) {
    if (!lacam_) {
      sequence_ = sequencer_->next();
      if (!sequence_) {
        result.failure_reason = "no plan exists: the configurations of every joint sequence (" +
                                std::to_string(impossible_sequences_) + ") were searched to the end";
        return Outcome::kNoPlanExists;
      }
      ++result.sequences_tried;
      lacam_ = std::make_unique<LacamSearch>(*instance_.graph, dist_, lacam_config, rng_, instance_.starts,
                                             instance_.goals, std::vector<char>{}, waypoints_of(instance_, *sequence_),
                                             turning_ ? start_headings_of(instance_) : Headings{});
    }
    const LacamResult found = lacam_->run(deadline);
    if (found.solved) {
      exhausted_ = found.exhausted;
      keep_if_better(result, instance_, found.solution, sequence_->orders, sequence_->index, options.started, options,
                     turning_ ? "CTS-LaCAM with turns" : "CTS-LaCAM", found.headings);
      return Outcome::kFound;
    }
    if (!found.exhausted) break;  // the deadline
    ++impossible_sequences_;      // this sequence cannot be followed; the next may
    lacam_.reset();
  }
  return Outcome::kOutOfTime;
}

void CompleteSearch::refine(const SolveOptions& options, SolveResult& result) {
  if (!lacam_ || !anytime_) return;
  refine_until_deadline(instance_, dist_, *lacam_, exhausted_, config_, rng_, sequence_->orders, sequence_->index,
                        options, result, turning_ ? "CTS-LaCAM* with turns" : "CTS-LaCAM*", turning_);
}

SolveResult CtsLacam::solve(const Instance& instance, const SolveOptions& options) {
  if (instance.actions == ActionModel::kRotate) return solve_with_turns(instance, options);
  SolveResult result;
  std::mt19937 rng(config_.seed);
  DistTable dist(*instance.graph);
  CompleteSearch search(instance, dist, config_, rng, /*anytime=*/true);
  const CompleteSearch::Outcome outcome = search.search(options.deadline, options, result);
  if (outcome == CompleteSearch::Outcome::kFound) search.refine(options, result);
  if (outcome == CompleteSearch::Outcome::kOutOfTime && !result.solved) {
    result.failure_reason = "deadline reached before a plan was found";
  }
  result.comp_time_ms = elapsed_ms(options.started);
  return result;
}

SolveResult CtsLacam::solve_with_turns(const Instance& instance, const SolveOptions& options) {
  GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
  if (!config_.plan_with_turns || !turning_tables_fit(instance, turning)) {
    TurnedSolver turned(std::make_unique<CtsLacam>(config_), config_);
    return turned.solve(instance, options);
  }
  const Deadline& deadline = options.deadline;
  SolveResult result;
  DistTable dist(*instance.graph);
  // Each search keeps its plans in its own result (a plan and the task orders it follows go
  // together: LNS refines a plan along its own orders), reported here when cheaper.
  SolveOptions quiet = options;
  quiet.on_solution = nullptr;
  const auto keep = [&](const SolveResult& found, const std::string& by) {
    if (!found.solved) return;
    keep_if_better(result, instance, found.solution, found.orders, found.improvements.back().sequence_index,
                   options.started, options, by, found.headings);
  };
  // Turns added to four-way CTS-LaCAM's first plan: quick, and as sure to find a plan. (A plan with
  // turns, its turns read as waits, is a four-way plan: none in four ways means none with turns.)
  bool cycles = false;
  int64_t four_way_bound = 0;
  if (config_.add_turns) {
    Instance four_way = instance;
    four_way.actions = ActionModel::kMove4;
    std::mt19937 four_way_rng(config_.seed);
    CompleteSearch four_way_search(four_way, dist, config_, four_way_rng, /*anytime=*/false);
    SolveResult planned;
    const CompleteSearch::Outcome outcome = four_way_search.search(deadline, quiet, planned);
    four_way_bound = planned.lower_bound;
    result.preprocessing_ms = planned.preprocessing_ms;
    if (outcome == CompleteSearch::Outcome::kNoPlanExists) {
      result.failure_reason = planned.failure_reason;
      result.comp_time_ms = elapsed_ms(options.started);
      return result;
    }
    const std::optional<TurningPlan> turned =
        planned.solved ? execute_with_turns(instance, planned.solution, !config_.forbid_rotations) : std::nullopt;
    cycles = planned.solved && !turned;
    if (turned) {
      SolveResult carried = planned;
      carried.solution = turned->cells;
      carried.headings = turned->headings;
      keep(carried, "CTS-LaCAM (turned)");
    }
  }
  result.lower_bound = turning_lower_bound(instance, turning, config_.task_order, four_way_bound, deadline);
  // The search over cell and heading: a quarter of the time left when a turned plan is in hand.
  std::mt19937 rng(config_.seed);
  CompleteSearch search(instance, dist, config_, rng, /*anytime=*/true, &turning);
  SolveResult with_turns;
  const CompleteSearch::Outcome outcome =
      search.search(result.solved ? deadline.slice(0.25 * deadline.budget_left_s()) : deadline, quiet, with_turns);
  if (outcome == CompleteSearch::Outcome::kFound) {
    keep(with_turns, "CTS-LaCAM with turns");
    search.refine(quiet, with_turns);
    keep(with_turns, "CTS-LaCAM* with turns");
  } else if (result.solved && !deadline.expired()) {
    // No plan with turns: four-way plans refined for the rest of the time, the best turned.
    TurnedSolver turned_solver(std::make_unique<CtsLacam>(config_), config_);
    turned_solver.use_turning_tables(turning, result.lower_bound);
    const SolveResult turned = turned_solver.solve(instance, quiet);
    result.lns_iterations += turned.lns_iterations;
    keep(turned, "CTS-LaCAM* (turned)");
  }
  result.lns_iterations += with_turns.lns_iterations;
  result.sequences_tried = std::max(result.sequences_tried, with_turns.sequences_tried);
  if (!result.solved && result.failure_reason.empty()) {
    result.failure_reason = !with_turns.failure_reason.empty() ? with_turns.failure_reason
                            : cycles ? "the four-way plan has agents moving in a cycle, which robots that turn cannot follow"
                                     : "deadline reached before a plan was found";
  }
  result.comp_time_ms = elapsed_ms(options.started);
  return result;
}

}  // namespace planner_core
