#include "planner_core/cts_pll.hpp"

#include <memory>
#include <random>

#include "planner_core/cts_lacam.hpp"
#include "planner_core/scatter.hpp"

namespace planner_core {

namespace {

// The least work the complete search gets after a joint sequence failed (in seconds at
// kWorkPerSecond).
constexpr double kMinCompleteSliceS = 0.05;

}  // namespace

SolveResult CtsPll::solve(const Instance& instance, const SolveOptions& options) {
  const Clock::time_point started = options.started;
  std::mt19937 rng(config_.seed);
  DistTable dist(*instance.graph);
  JointSequencer sequencer(instance, dist, config_.task_order, options.deadline);
  PibtConfig pibt_config = config_.pibt;
  pibt_config.stall_window = config_.pll_stall_window;
  pibt_config.forbid_rotations = pibt_config.forbid_rotations || config_.forbid_rotations;
  ExtendedPibt pibt(instance, dist, pibt_config, rng);
  Lacam lacam(*instance.graph, dist, LacamConfig{false, config_.forbid_rotations}, rng);
  LnsConfig lns_config = config_.lns;
  lns_config.search.forbid_rotations = lns_config.search.forbid_rotations || config_.forbid_rotations;
  // Made when a plan is first refined (v3 only): its tables span the whole map, which on a big
  // one takes seconds that a solve without refinement should not spend.
  std::unique_ptr<LnsRefiner> lns;
  const Deadline& deadline = options.deadline;

  const double total_s = deadline.budget_s;
  // Refinement (LNS, and more sequences once a plan is in hand) ends here; a first plan may take
  // until `deadline`.
  const Deadline refining = options.refine_share < 1.0 ? deadline.slice(total_s * options.refine_share) : deadline;
  // v3's LNS: by default each feasible sequence gets up to a quarter of the limit (less when its
  // LNS stalls), and after the first two the better refined plan gets the rest (docs/results/HISTORY.md
  // section 7: half each did worse on dense mazes, the whole limit on the first sequence worse on
  // warehouses).
  const bool race_two_sequences = config_.lns.time_per_sequence_s <= 0;
  const double lns_per_sequence_s = race_two_sequences ? std::max(0.5, total_s / 4) : config_.lns.time_per_sequence_s;
  int refined_sequences = 0;

  SolveResult result;
  result.lower_bound = sequencer.lower_bound();
  result.preprocessing_ms = elapsed_ms(started);
  // v3: LNS on each feasible plan, for its share of the time.
  auto refine_by_lns = [&](Solution plan, const std::vector<std::vector<int>>& orders, int sequence_index,
                           const Deadline& until) {
    ++refined_sequences;
    if (!until.expired()) {
      if (!lns) lns = std::make_unique<LnsRefiner>(instance, dist, lns_config, rng);
      const LnsStats stats = lns->refine(plan, orders, until, [&](int64_t flow) {
        if (result.solved && flow < result.flowtime &&
            (result.improvements.empty() || flow < result.improvements.back().flowtime)) {
          result.improvements.push_back({elapsed_ms(started), flow, sequence_index});
        }
      });
      result.lns_iterations += stats.iterations;
    }
    keep_if_better(result, instance, plan, orders, sequence_index, started, options, "CTS-PLL");
  };
  CompleteSearch complete(instance, dist, config_, rng, variant_ == Variant::kV3);
  std::unique_ptr<Scatter> scatter;  // guides `pibt` through the current sequence (PibtConfig::scatter)
  bool no_plan_exists = false;
  while (!deadline.expired() && !(result.solved && refining.expired())) {
    if (config_.max_sequences > 0 && result.sequences_tried >= config_.max_sequences) break;
    const std::optional<JointSequence> sequence = sequencer.next();
    if (!sequence) break;
    ++result.sequences_tried;
    // Once a plan is in hand, another sequence is refinement: it ends with `refining`.
    const Deadline& until = result.solved ? refining : deadline;
    // Work, not time: what this sequence has taken so far decides the complete search's share
    // (the same share on every run).
    const int64_t work_before_sequence = until.work_done();
    const auto work_share = [&] {
      return until.within_work(
          std::max(Deadline::work_of(kMinCompleteSliceS), until.work_done() - work_before_sequence));
    };
    // The complete search from a lock (CTS-LaCAM over every agent), for as much as this sequence
    // has taken so far.
    const auto search_from_lock = [&](const LockSet& lock) {
      return complete_by_search(pibt, *sequence, lock, dist, rng, config_.forbid_rotations, work_share());
    };

    // Extended-PIBT, releasing locks until the plan is feasible (Algorithm 2, lines 4-7).
    pibt.reset(*sequence);
    if (config_.pibt.scatter) {
      scatter = std::make_unique<Scatter>(*instance.graph, dist, instance.starts, instance.goals, kScatterMargin,
                                          config_.seed + sequence->index, waypoints_of(instance, *sequence));
      scatter->build(until.within_work(Deadline::work_of(total_s * kScatterTimeShare)));
    }
    pibt.set_guide(scatter.get());
    bool feasible = false;
    std::optional<Solution> completed_plan;
    for (int releases = 0; !until.expired() && releases < config_.lock_release.max_releases;) {
      const ExtendedPibt::Outcome outcome = pibt.run(until);
      if (outcome == ExtendedPibt::Outcome::kSolved) {
        feasible = true;
        break;
      }
      if (outcome == ExtendedPibt::Outcome::kInterrupted) break;
      ++result.pibt_failures;
      // LockDetect&Release; when LaCAM finds no release, widen the lock set and try again.
      LockSet lock = detect_lock(pibt, dist);
      std::optional<Solution> prefix;
      size_t tried_size = 0;
      for (int escalation = 0; !prefix && escalation <= config_.lock_release.max_escalations && !until.expired();
           ++escalation) {
        const LockSet attempt = escalation == 0 ? lock : widen_lock(pibt, lock, 1 << escalation);
        // A wider set is a superset: the same size is the same set, already tried. Once every
        // agent is in it, nothing wider remains.
        if (attempt.agents.size() == tried_size) {
          if (tried_size == static_cast<size_t>(instance.agent_count())) break;
          continue;
        }
        tried_size = attempt.agents.size();
        // Random-permutation targets first (the paper's choice); when a lock comes back after a
        // release, alternate with next-target goals, which resolve corridor swaps outright.
        const bool next_targets_first = releases % 2 == 1;
        prefix = release_lock(pibt, attempt, lacam, config_.lock_release, next_targets_first, rng, until);
        if (!prefix) prefix = release_lock(pibt, attempt, lacam, config_.lock_release, !next_targets_first, rng, until);
        if (!prefix && escalation == 0 && 2 * lock.agents.size() >= static_cast<size_t>(instance.agent_count()) &&
            config_.complete_fallback) {
          // A lock of half the fleet or more is no local matter (warehouse aisles): rather than
          // ever wider local releases, the complete search from the lock at once.
          completed_plan = search_from_lock(lock);
          if (completed_plan) break;
        }
      }
      if (!completed_plan && (!prefix || releases + 1 >= config_.lock_release.completion_after_releases)) {
        // Releases failed or the lock keeps coming back: complete by prioritized planning.
        if (auto completed = complete_by_prioritized_planning(pibt, *sequence, lock, dist, rng, 8,
                                                                 config_.forbid_rotations, until)) {
          ++result.prioritized_completions;
          completed_plan = std::move(completed);
          feasible = true;
          break;
        }
      }
      // No local release works: the complete search takes over from the lock.
      if (!completed_plan && !prefix && config_.complete_fallback) completed_plan = search_from_lock(lock);
      if (completed_plan) {
        ++result.searched_completions;
        feasible = true;
        break;
      }
      if (!prefix) break;  // give this sequence up
      ++releases;
      ++result.lock_releases;
      pibt.reset(*sequence, *prefix);
    }
    if (feasible) {
      Solution plan = completed_plan ? std::move(*completed_plan) : pibt.plan();
      keep_if_better(result, instance, plan, sequence->orders, sequence->index, started, options, "CTS-PLL");
      if (variant_ == Variant::kV3) refine_by_lns(plan, sequence->orders, sequence->index, refining.slice(lns_per_sequence_s));
    } else if (config_.complete_fallback && variant_ != Variant::kV1) {
      // This sequence defeated Extended-PIBT and the releases: the complete search gets as much
      // work as they took (it goes on where it stopped the next time).
      const CompleteSearch::Outcome outcome = complete.search(work_share(), options, result);
      if (outcome == CompleteSearch::Outcome::kNoPlanExists) {
        no_plan_exists = true;
        break;
      }
      if (outcome == CompleteSearch::Outcome::kFound && variant_ == Variant::kV3) {
        refine_by_lns(result.solution, result.orders, result.improvements.back().sequence_index,
                      refining.slice(lns_per_sequence_s));
      }
    }
    if (variant_ == Variant::kV1) break;
    if (variant_ == Variant::kV2 && result.solved) break;
    if (variant_ == Variant::kV3 && race_two_sequences && refined_sequences == 2 && result.solved) {
      // The better of the first two refined plans gets the rest of the time; when its LNS stalls
      // first (small instances), the next sequences go on as before.
      refine_by_lns(result.solution, result.orders, result.improvements.back().sequence_index, refining);
    }
  }
  // v3: when the sequences ran out before the race, the best plan gets the rest of the time.
  if (variant_ == Variant::kV3 && race_two_sequences && refined_sequences < 2 && result.solved && !refining.expired()) {
    refine_by_lns(result.solution, result.orders, result.improvements.back().sequence_index, refining);
  }
  // Never give up before the deadline: the complete search takes over (and v3 refines its plan).
  if (!result.solved && !no_plan_exists && config_.complete_fallback && !deadline.expired()) {
    if (complete.search(deadline, options, result) == CompleteSearch::Outcome::kFound) {
      SolveOptions refine_options = options;
      refine_options.deadline = refining;
      complete.refine(refine_options, result);
    }
  }
  if (!result.solved && result.failure_reason.empty()) {
    result.failure_reason = deadline.expired() ? "deadline reached before a feasible plan was found"
                                               : "no feasible plan from the sequences tried";
  }
  result.comp_time_ms = elapsed_ms(started);
  return result;
}

}  // namespace planner_core
