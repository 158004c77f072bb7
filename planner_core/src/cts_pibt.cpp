#include "planner_core/cts_pibt.hpp"

#include <random>

#include "planner_core/cts_lacam.hpp"

namespace planner_core {

SolveResult CtsPibt::solve(const Instance& instance, const SolveOptions& options) {
  const Clock::time_point started = options.started;
  std::mt19937 rng(config_.seed);
  DistTable dist(*instance.graph);
  JointSequencer sequencer(instance, dist, config_.task_order, options.deadline);
  PibtConfig pibt_config = config_.pibt;
  pibt_config.forbid_rotations = pibt_config.forbid_rotations || config_.forbid_rotations;
  ExtendedPibt pibt(instance, dist, pibt_config, rng);

  SolveResult result;
  result.lower_bound = sequencer.lower_bound();
  result.preprocessing_ms = elapsed_ms(started);
  CompleteSearch complete(instance, dist, config_, rng, anytime_);
  bool no_plan_exists = false;
  while (!options.deadline.expired()) {
    if (config_.max_sequences > 0 && result.sequences_tried >= config_.max_sequences) break;
    const std::optional<JointSequence> sequence = sequencer.next();
    if (!sequence) break;
    ++result.sequences_tried;
    const int64_t work_before_sequence = options.deadline.work_done();
    pibt.reset(*sequence);
    const ExtendedPibt::Outcome outcome = pibt.run(options.deadline);
    if (outcome == ExtendedPibt::Outcome::kStepLimit) ++result.pibt_failures;
    if (outcome == ExtendedPibt::Outcome::kSolved) {
      keep_if_better(result, instance, pibt.plan(), sequence->orders, sequence->index, started, options,
                     "Extended-PIBT");
    } else if (anytime_ && !result.solved && config_.complete_fallback) {
      // The anytime loop gives the complete search as much work as the failed sequence took.
      const int64_t spent = options.deadline.work_done() - work_before_sequence;
      if (complete.search(options.deadline.within_work(std::max(Deadline::work_of(0.05), spent)), options, result) ==
          CompleteSearch::Outcome::kNoPlanExists) {
        no_plan_exists = true;
        break;
      }
    }
    if (!anytime_) break;
  }
  // Never give up before the deadline: the complete search takes over.
  if (!result.solved && !no_plan_exists && config_.complete_fallback && !options.deadline.expired()) {
    if (complete.search(options.deadline, options, result) == CompleteSearch::Outcome::kFound) {
      complete.refine(options, result);
    }
  }
  if (!result.solved && result.failure_reason.empty()) {
    result.failure_reason = result.pibt_failures > 0 ? "Extended-PIBT hit its step limit on every sequence tried"
                                                     : "deadline reached before a solution was found";
  }
  result.comp_time_ms = elapsed_ms(started);
  return result;
}

}  // namespace planner_core
