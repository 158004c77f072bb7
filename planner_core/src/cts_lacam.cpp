#include "planner_core/cts_lacam.hpp"

#include "planner_core/joint_sequencer.hpp"
#include "planner_core/lacam.hpp"
#include "planner_core/lacam_solver.hpp"

namespace planner_core {

namespace {

Waypoints waypoints_of(const Instance& instance, const JointSequence& sequence) {
  Waypoints waypoints(instance.agent_count());
  for (int a = 0; a < instance.agent_count(); ++a) {
    for (int task : sequence.orders[a]) waypoints[a].push_back(instance.tasks[task].at);
  }
  return waypoints;
}

}  // namespace

void solve_completely(const Instance& instance, DistTable& dist, const SolverConfig& config, std::mt19937& rng,
                      bool anytime, const SolveOptions& options, SolveResult& result) {
  const Deadline& deadline = options.deadline;
  JointSequencer sequencer(instance, dist, config.task_order, deadline);
  if (result.lower_bound == 0) result.lower_bound = sequencer.lower_bound();
  if (result.preprocessing_ms == 0) result.preprocessing_ms = elapsed_ms(options.started);
  const LacamConfig lacam_config{anytime, config.forbid_rotations, /*swap=*/true, /*prefer_free_cells=*/true};
  int impossible_sequences = 0;
  while (!deadline.expired()) {
    const std::optional<JointSequence> sequence = sequencer.next();
    if (!sequence) {
      if (!result.solved) {
        result.failure_reason = "no plan exists: the configurations of every joint sequence (" +
                                std::to_string(impossible_sequences) + ") were searched to the end";
      }
      return;
    }
    ++result.sequences_tried;
    LacamSearch search(*instance.graph, dist, lacam_config, rng, instance.starts, instance.goals, {},
                       waypoints_of(instance, *sequence));
    const LacamResult found = search.run(deadline);
    if (!found.solved) {
      if (!found.exhausted) break;  // the deadline
      ++impossible_sequences;       // this sequence cannot be followed; the next may
      continue;
    }
    keep_if_better(result, instance, found.solution, sequence->orders, sequence->index, options.started, options,
                   "CTS-LaCAM");
    if (anytime) {
      refine_until_deadline(instance, dist, search, found.exhausted, config, rng, sequence->orders, sequence->index,
                            options, result, "CTS-LaCAM*");
    }
    return;
  }
  if (!result.solved) result.failure_reason = "deadline reached before a plan was found (by the complete search too)";
}

SolveResult CtsLacam::solve(const Instance& instance, const SolveOptions& options) {
  SolveResult result;
  std::mt19937 rng(config_.seed);
  DistTable dist(*instance.graph);
  solve_completely(instance, dist, config_, rng, /*anytime=*/true, options, result);
  result.comp_time_ms = elapsed_ms(options.started);
  return result;
}

}  // namespace planner_core
