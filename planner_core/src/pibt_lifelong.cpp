// PibtLifelong's step: rollouts (PIBT run several steps ahead, the best first step taken), then
// window LNS on the best rollout's window.
#include "planner_core/pibt_lifelong.hpp"

#include <chrono>
#include <limits>
#include <stdexcept>

#include "planner_core/input_error.hpp"
#include "planner_core/lifelong_auto_rules.hpp"

namespace planner_core {

PlanHolding parse_plan_holding(const std::string& text, const std::string& what) {
  if (text == "never") return PlanHolding::kNever;
  if (text == "half") return PlanHolding::kInHalfTheRollouts;
  if (text == "always") return PlanHolding::kAlways;
  throw InputError(what + ": \"" + text + "\" is no way of holding plans (never, half or always)");
}

std::string to_string(PlanHolding holding) {
  switch (holding) {
    case PlanHolding::kNever:
      return "never";
    case PlanHolding::kInHalfTheRollouts:
      return "half";
    case PlanHolding::kAlways:
      return "always";
  }
  return "?";
}

PibtLifelong::PibtLifelong(const Graph& graph, uint32_t seed, PibtLifelongSettings settings)
    : graph_(graph),
      settings_(settings),
      distances_(graph, settings.guidance, settings.actions, settings.stay_cost,
                 settings.traffic.on ? settings.traffic.max_moves : 0),
      traffic_(static_cast<size_t>(graph.vertex_count()), settings.traffic, distances_.cost_unit()),
      guides_(graph, settings.guide_paths),
      bound_for_(graph.vertex_count(), 0),
      table_held_(graph.vertex_count(), 0),
      rng_(seed),
      standing_on_(graph.vertex_count(), -1),
      entering_(graph.vertex_count(), -1),
      lns_(graph, distances_, settings.actions) {
  lns_.keep_equal_cost(settings.lns_keeps_equal_cost);
  lns_.neighbourhoods(settings.lns_neighbourhoods);
  if (settings.guide_paths.on) {
    lns_.follow_guides(&guides_, static_cast<int>(settings.guide_paths.off_guide_moves * distances_.cost_unit()));
  }
}

void PibtLifelong::prepare(const Poses& now, const Config& goals, const Deadline& deadline) {
  follow_goals(goals, deadline);
  if (settings_.guide_paths.on) guides_.update(now.cells, goals, guide_heuristic(), deadline);
}

Poses PibtLifelong::next_step(const Poses& now, const Config& errands, const Deadline& deadline) {
  const Config& positions = now.cells;
  if (settings_.actions == ActionModel::kRotate && now.headings.size() != positions.size()) {
    throw std::invalid_argument("PibtLifelong: the rotation model needs a heading per agent");
  }
  const Config goals = planning_goals(now, errands);
  const Config previous_goals = following_ ? last_goals_ : goals;
  follow_goals(goals, deadline);
  if (fraction_.size() != positions.size()) {  // the first step (a rollout starts from a copy of what follows)
    std::uniform_real_distribution<double> fraction(0, 1);
    fraction_.resize(positions.size());
    for (double& f : fraction_) f = fraction(rng_);
    still_.assign(positions.size(), 0);
    boost_.assign(positions.size(), 0);
    stuck_steps_ = stuck_steps_for(graph_, positions.size());
  }
  follow_traffic(positions, deadline);
  follow_guides(now, goals, deadline);
  if (settings_.rollouts <= 1 && !settings_.lns) {
    holding_ = settings_.hold_plans == PlanHolding::kAlways;
    return one_step(now, goals, previous_goals);
  }
  const auto started = std::chrono::steady_clock::now();
  const bool counted = settings_.lns_rounds > 0;  // the work, not the clock, decides
  const double budget_s = settings_.rollout_share * deadline.seconds_left();
  const double share_s = settings_.lns ? budget_s / 2 : budget_s;
  const int n = static_cast<int>(positions.size());
  const StepState before = state();
  const uint32_t seeds = static_cast<uint32_t>(rng_());
  int64_t best_score = std::numeric_limits<int64_t>::max();
  Poses best_first;
  std::vector<Poses> best_window;
  StepState after_best;
  for (int run = 0; run < settings_.rollouts; ++run) {
    restore(before);
    if (run > 0) rng_.seed(seeds + static_cast<uint32_t>(run));
    holding_ = settings_.hold_plans == PlanHolding::kAlways ||
               (settings_.hold_plans == PlanHolding::kInHalfTheRollouts && run % 2 == 1);
    Poses at = one_step(now, goals, previous_goals);
    const Poses first = at;
    std::vector<Poses> window{now, first};
    const StepState after_first = state();
    std::vector<int> reached(n, -1);  // the step an agent first stood on its goal
    for (int a = 0; a < n; ++a) {
      if (at.cells[a] == goals[a]) reached[a] = 1;
    }
    for (int step = 2; step <= settings_.rollout_steps; ++step) {
      at = one_step(at, goals, goals);
      if (settings_.lns) window.push_back(at);
      for (int a = 0; a < n; ++a) {
        if (reached[a] < 0 && at.cells[a] == goals[a]) reached[a] = step;
      }
    }
    // In cost units (GuidedDistances::cost_unit), a step counting as a move along a lane.
    const int64_t unit = distances_.cost_unit();
    int64_t score = 0;
    for (int a = 0; a < n; ++a) {
      score += reached[a] >= 0 ? reached[a] * unit : settings_.rollout_steps * unit + int64_t{distance(goals[a], at, a)};
    }
    if (score < best_score) {
      best_score = score;
      best_first = first;
      best_window = std::move(window);
      after_best = after_first;
    }
    // Another run only if it fits in the share, at the pace so far (work counted: every run).
    const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (!counted && spent * (run + 2) / (run + 1) > share_s) break;
  }
  restore(after_best);
  if (settings_.lns) {
    if (settings_.keep_window) {
      std::vector<Poses> kept = kept_window(now, goals);
      if (!kept.empty() && lns_.cost(kept, goals) < lns_.cost(best_window, goals)) {
        best_window = std::move(kept);
        ++windows_kept_;
      }
    }
    const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    Deadline lns_deadline = Deadline::in_seconds(counted ? 1e18 : std::max(0.0, budget_s - spent));
    lns_deadline.interrupt = deadline.interrupt;
    const int64_t rounds = counted ? settings_.lns_rounds : std::numeric_limits<int64_t>::max();
    const WindowLnsStats stats = lns_.improve(best_window, goals, lns_deadline, rng_, rounds);
    lns_totals_.iterations += stats.iterations;
    lns_totals_.improvements += stats.improvements;
    lns_totals_.cost_before += stats.cost_before;
    lns_totals_.cost_after += stats.cost_after;
    for (size_t k = 0; k < stats.rounds_by_kind.size(); ++k) {
      lns_totals_.rounds_by_kind[k] += stats.rounds_by_kind[k];
      lns_totals_.improvements_by_kind[k] += stats.improvements_by_kind[k];
    }
    // The first step may have changed: agents that now stay count as standing still, and an
    // agent sent elsewhere is no longer short of its target.
    for (int a = 0; a < n; ++a) {
      if (best_window[1].cells[a] != best_first.cells[a]) {
        still_[a] = best_window[1].cells[a] == positions[a] ? still_[a] + 1 : 0;
      }
      const bool turned_otherwise =
          settings_.actions == ActionModel::kRotate && best_window[1].headings[a] != best_first.headings[a];
      if (!targets_.empty() && (best_window[1].cells[a] != best_first.cells[a] || turned_otherwise)) {
        targets_[a] = best_window[1].cells[a];
      }
    }
    last_window_ = best_window;
    last_window_goals_ = goals;
    return best_window[1];
  }
  return best_first;
}

void PibtLifelong::restore(const StepState& state) {
  rng_ = state.rng;
  still_ = state.still;
  boost_ = state.boost;
  targets_ = state.targets;
  held_steps_ = state.held_steps;
}

}  // namespace planner_core
