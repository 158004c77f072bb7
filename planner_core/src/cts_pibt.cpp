#include "planner_core/cts_pibt.hpp"

#include <random>
#include <stdexcept>

#include "planner_core/validator.hpp"

namespace planner_core {

SolveResult CtsPibt::solve(const Instance& instance, const SolveOptions& options) {
  const Clock::time_point started = Clock::now();
  std::mt19937 rng(config_.seed);
  DistTable dist(*instance.graph);
  JointSequencer sequencer(instance, dist, config_.task_order);
  PibtConfig pibt_config = config_.pibt;
  pibt_config.forbid_rotations = pibt_config.forbid_rotations || config_.forbid_rotations;
  ExtendedPibt pibt(instance, dist, pibt_config, rng);

  SolveResult result;
  result.lower_bound = sequencer.lower_bound();
  while (!options.deadline.expired()) {
    if (config_.max_sequences > 0 && result.sequences_tried >= config_.max_sequences) break;
    const std::optional<JointSequence> sequence = sequencer.next();
    if (!sequence) break;
    ++result.sequences_tried;
    pibt.reset(*sequence);
    const ExtendedPibt::Outcome outcome = pibt.run(options.deadline);
    if (outcome == ExtendedPibt::Outcome::kStepLimit) ++result.pibt_failures;
    if (outcome == ExtendedPibt::Outcome::kSolved) {
      const int64_t cost = flowtime(pibt.plan(), instance.goals);
      if (!result.solved || cost < result.flowtime) {
        const ValidationReport report = validate(instance, pibt.plan());
        if (!report.ok()) {
          throw std::logic_error("Extended-PIBT produced an invalid plan:\n" + report.summary());
        }
        result.solved = true;
        result.solution = pibt.plan();
        result.orders = sequence->orders;
        result.flowtime = cost;
        result.makespan = report.makespan;
        result.sum_of_loss = sum_of_loss(result.solution, instance.goals);
        const double now = elapsed_ms(started);
        if (result.first_solution_ms < 0) result.first_solution_ms = now;
        result.improvements.push_back({now, cost, sequence->index});
        if (options.on_solution) options.on_solution(result);
      }
    }
    if (!anytime_) break;
  }
  if (!result.solved) {
    result.failure_reason = result.pibt_failures > 0 ? "Extended-PIBT hit its step limit on every sequence tried"
                                                     : "deadline reached before a solution was found";
  }
  result.comp_time_ms = elapsed_ms(started);
  return result;
}

}  // namespace planner_core
