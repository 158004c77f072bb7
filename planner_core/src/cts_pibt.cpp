#include "planner_core/cts_pibt.hpp"

#include <optional>
#include <random>

#include "planner_core/cts_lacam.hpp"
#include "planner_core/turned_solver.hpp"
#include "planner_core/turning_execution.hpp"

namespace planner_core {

SolveResult CtsPibt::solve(const Instance& instance, const SolveOptions& options) {
  const Clock::time_point started = options.started;
  std::mt19937 rng(config_.seed);
  DistTable dist(*instance.graph);
  JointSequencer sequencer(instance, dist, config_.task_order, options.deadline);
  PibtConfig pibt_config = config_.pibt;
  pibt_config.forbid_rotations = pibt_config.forbid_rotations || config_.forbid_rotations;
  const bool turning = instance.actions == ActionModel::kRotate;
  // With turns, no swap operation: backing off means turning round, and two agents that took
  // turns to back off turned to and fro for ever (measured: the first sequence of 4 of 5 dense
  // maze instances solved without it, none with it).
  PibtConfig turning_config = pibt_config;
  turning_config.swap = false;
  ExtendedPibt pibt(instance, dist, turning ? turning_config : pibt_config, rng);

  // The rotation model: Extended-PIBT plans with turns (costs per cell and heading for every task
  // and goal); for each sequence it also plans four-way moves, as in the four-way model and with
  // the same random numbers, and adds the turns (turning_execution.hpp); the cheaper plan is
  // kept. The complete search plans four-way moves too, its plan turned the same way.
  std::optional<GuidedDistances> turning_distances;
  std::optional<Instance> four_way_copy;  // the instance in the four-way model (turning only)
  std::mt19937 four_way_rng(config_.seed);
  std::optional<ExtendedPibt> four_way_pibt;
  bool plan_with_turns = config_.plan_with_turns;
  if (turning) {
    four_way_copy.emplace(instance);
    four_way_copy->actions = ActionModel::kMove4;
    four_way_pibt.emplace(*four_way_copy, dist, pibt_config, four_way_rng);
    turning_distances.emplace(*instance.graph, Guidance::kNone, ActionModel::kRotate);
    // Too many tables to hold (8 bytes per cell for each task and goal): turns added only.
    plan_with_turns = plan_with_turns && turning_tables_fit(instance, *turning_distances);
    pibt.use_rotation_model(*turning_distances);
  }
  const auto keep_turned = [&](SolveResult& result, const Solution& plan, const std::vector<std::vector<int>>& orders,
                               int sequence_index, const std::string& by) {
    const std::optional<TurningPlan> turned = execute_with_turns(instance, plan, !config_.forbid_rotations);
    if (turned) keep_if_better(result, instance, turned->cells, orders, sequence_index, started, options, by, turned->headings);
  };

  SolveResult result;
  // With turns, the tables are searched up front (PIBT needs them too) in at most a quarter of the time.
  result.lower_bound = turning ? turning_lower_bound(instance, *turning_distances, config_.task_order,
                                                     sequencer.lower_bound(),
                                                     options.deadline.slice(0.25 * options.deadline.budget_left_s()))
                               : sequencer.lower_bound();
  result.preprocessing_ms = elapsed_ms(started);
  CompleteSearch complete(turning ? *four_way_copy : instance, dist, config_, rng, anytime_);
  SolveResult four_way_result;  // the complete search's plans in the rotation model (turned when kept)
  SolveResult& complete_result = turning ? four_way_result : result;
  // Its four-way plans are not reported as they are found: the turned ones are, when kept.
  SolveOptions complete_options = options;
  if (turning) complete_options.on_solution = nullptr;
  bool no_plan_exists = false;
  while (!options.deadline.expired()) {
    if (config_.max_sequences > 0 && result.sequences_tried >= config_.max_sequences) break;
    const std::optional<JointSequence> sequence = sequencer.next();
    if (!sequence) break;
    ++result.sequences_tried;
    const int64_t work_before_sequence = options.deadline.work_done();
    if (!turning || plan_with_turns) {
      pibt.reset(*sequence);
      const ExtendedPibt::Outcome outcome = pibt.run(options.deadline);
      if (outcome == ExtendedPibt::Outcome::kStepLimit) ++result.pibt_failures;
      if (outcome == ExtendedPibt::Outcome::kSolved) {
        keep_if_better(result, instance, pibt.plan(), sequence->orders, sequence->index, started, options,
                       "Extended-PIBT", pibt.headings());
      }
    }
    if (turning && (config_.add_turns || !plan_with_turns) && !options.deadline.expired()) {
      four_way_pibt->reset(*sequence);
      if (four_way_pibt->run(options.deadline) == ExtendedPibt::Outcome::kSolved) {
        keep_turned(result, four_way_pibt->plan(), sequence->orders, sequence->index, "Extended-PIBT (four-way, turned)");
      }
    }
    if (anytime_ && !result.solved && config_.complete_fallback) {
      // The anytime loop gives the complete search as much work as the failed sequence took.
      const int64_t spent = options.deadline.work_done() - work_before_sequence;
      const CompleteSearch::Outcome searched = complete.search(
          options.deadline.within_work(std::max(Deadline::work_of(0.05), spent)), complete_options, complete_result);
      if (searched == CompleteSearch::Outcome::kNoPlanExists) {
        no_plan_exists = true;
        break;
      }
      if (turning && four_way_result.solved) {
        keep_turned(result, four_way_result.solution, four_way_result.orders, 0, "the complete search (turned)");
      }
    }
    if (!anytime_) break;
  }
  // Never give up before the deadline: the complete search takes over.
  if (!result.solved && !no_plan_exists && config_.complete_fallback && !options.deadline.expired()) {
    if (complete.search(options.deadline, complete_options, complete_result) == CompleteSearch::Outcome::kFound) {
      complete.refine(complete_options, complete_result);
    }
    if (turning && four_way_result.solved) {
      keep_turned(result, four_way_result.solution, four_way_result.orders, 0, "the complete search (turned)");
    }
  }
  if (turning && !result.solved && !four_way_result.failure_reason.empty()) {
    result.failure_reason = four_way_result.failure_reason;
  }
  if (!result.solved && result.failure_reason.empty()) {
    result.failure_reason = result.pibt_failures > 0 ? "Extended-PIBT hit its step limit on every sequence tried"
                                                     : "deadline reached before a solution was found";
  }
  result.comp_time_ms = elapsed_ms(started);
  return result;
}

}  // namespace planner_core
