#include "planner_core/cts_lacam.hpp"

#include "planner_core/lacam_solver.hpp"

namespace planner_core {

Waypoints waypoints_of(const Instance& instance, const JointSequence& sequence) {
  Waypoints waypoints(instance.agent_count());
  for (int a = 0; a < instance.agent_count(); ++a) {
    for (int task : sequence.orders[a]) waypoints[a].push_back(instance.tasks[task].at);
  }
  return waypoints;
}

CompleteSearch::CompleteSearch(const Instance& instance, DistTable& dist, const SolverConfig& config,
                               std::mt19937& rng, bool anytime)
    : instance_(instance), dist_(dist), config_(config), rng_(rng), anytime_(anytime) {}

CompleteSearch::~CompleteSearch() = default;

CompleteSearch::Outcome CompleteSearch::search(const Deadline& deadline, const SolveOptions& options,
                                               SolveResult& result) {
  if (!sequencer_ || !sequencer_->ready()) {
    sequencer_ = std::make_unique<JointSequencer>(instance_, dist_, config_.task_order, deadline);
    if (!sequencer_->ready()) return Outcome::kOutOfTime;
    if (result.lower_bound == 0) result.lower_bound = sequencer_->lower_bound();
    if (result.preprocessing_ms == 0) result.preprocessing_ms = elapsed_ms(options.started);
  }
  const LacamConfig lacam_config{anytime_, config_.forbid_rotations, /*swap=*/true, /*prefer_free_cells=*/true};
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
                                             instance_.goals, std::vector<char>{}, waypoints_of(instance_, *sequence_));
    }
    const LacamResult found = lacam_->run(deadline);
    if (found.solved) {
      exhausted_ = found.exhausted;
      keep_if_better(result, instance_, found.solution, sequence_->orders, sequence_->index, options.started, options,
                     "CTS-LaCAM");
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
                        options, result, "CTS-LaCAM*");
}

SolveResult CtsLacam::solve(const Instance& instance, const SolveOptions& options) {
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

}  // namespace planner_core
