#include "planner_core/lifelong.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <unordered_map>

#include "planner_core/dist_table.hpp"
#include "planner_core/input_error.hpp"

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

namespace {
// At most a quarter of the free cells: shortest paths and long kept windows pay.
bool agents_are_few(const Graph& graph, size_t agents) {
  return agents * 4 <= static_cast<size_t>(graph.vertex_count());
}
}  // namespace

Guidance lifelong_guidance(const Graph& graph, size_t agents, bool lns, ActionModel actions) {
  if (lns && agents_are_few(graph, agents)) return Guidance::kNone;
  const bool ring_covers_the_map = std::min(graph.width(), graph.height()) <= 3 * GuidedDistances::kRingDepth;
  return lns && actions == ActionModel::kRotate && ring_covers_the_map ? Guidance::kRing : Guidance::kLanes;
}

LifelongWindow lifelong_window(const Graph& graph, size_t agents, ActionModel actions) {
  if (actions != ActionModel::kRotate) return {.steps = 8, .kept = false};
  if (!agents_are_few(graph, agents)) return {.steps = 8, .kept = true, .adaptive_neighbourhoods = true};
  if (agents <= kMostAgentsForLongWindows) {
    return {.steps = 16, .kept = true, .equal_cost_kept = true, .adaptive_neighbourhoods = true};
  }
  return {.steps = 8, .kept = false};
}

bool lifelong_parks_dead_ends(const Graph& graph, size_t agents) {
  return agents * 10 > static_cast<size_t>(graph.vertex_count()) * 9;
}

PlanHolding lifelong_plan_holding(const Graph& graph, size_t agents) {
  return lifelong_parks_dead_ends(graph, agents) ? PlanHolding::kAlways : PlanHolding::kInHalfTheRollouts;
}

int lifelong_rollout_steps(const Graph& graph, size_t agents, ActionModel actions) {
  const bool held_always = actions == ActionModel::kRotate && lifelong_plan_holding(graph, agents) == PlanHolding::kAlways;
  return held_always ? kRolloutStepsWhereHeld : kRolloutSteps;
}

int stuck_steps_for(const Graph& graph, size_t agents) {
  const int64_t cells = graph.vertex_count();
  const int64_t free = std::max<int64_t>(1, cells - static_cast<int64_t>(agents));
  const int64_t stretched = kStuckSteps * static_cast<int64_t>(agents) / free;
  return static_cast<int>(std::min<int64_t>(1'000'000, std::max<int64_t>(kStuckSteps, stretched)));
}

int lifelong_stay_cost(Guidance guidance, bool lns, ActionModel actions) {
  return lns && guidance != Guidance::kNone && actions == ActionModel::kRotate ? 3 : 1;
}

TrafficSettings lifelong_traffic(const Graph& graph, size_t agents, Guidance guidance) {
  TrafficSettings traffic;
  traffic.on = guidance == Guidance::kRing;
  const double fill = static_cast<double>(agents) / std::max(1, graph.vertex_count());
  traffic.threshold = std::min(0.95, std::max(traffic.threshold, fill + 0.1));
  return traffic;
}

PibtLifelong::PibtLifelong(const Graph& graph, uint32_t seed, PibtLifelongSettings settings)
    : graph_(graph),
      settings_(settings),
      distances_(graph, settings.guidance, settings.actions, settings.stay_cost,
                 settings.traffic.on ? settings.traffic.max_moves : 0),
      traffic_(static_cast<size_t>(graph.vertex_count()), settings.traffic, distances_.cost_unit()),
      bound_for_(graph.vertex_count(), 0),
      table_held_(graph.vertex_count(), 0),
      rng_(seed),
      standing_on_(graph.vertex_count(), -1),
      entering_(graph.vertex_count(), -1),
      lns_(graph, distances_, settings.actions) {
  lns_.keep_equal_cost(settings.lns_keeps_equal_cost);
  lns_.neighbourhoods(settings.lns_neighbourhoods);
}

void PibtLifelong::prepare(const Poses&, const Config& goals, const Deadline& deadline) {
  follow_goals(goals, deadline);
}

void PibtLifelong::follow_goals(const Config& goals, const Deadline& deadline) {
  std::vector<Vertex> new_goals;
  for (size_t a = 0; a < goals.size(); ++a) {
    const bool changed = !following_ || last_goals_[a] != goals[a];
    if (!changed) continue;
    if (following_ && --bound_for_[last_goals_[a]] == 0) unneeded_.push_back(last_goals_[a]);
    if (bound_for_[goals[a]]++ == 0 && !table_held_[goals[a]]) {
      table_held_[goals[a]] = 1;
      ++tables_held_;
    }
    new_goals.push_back(goals[a]);
  }
  following_ = true;
  last_goals_ = goals;
  // Free the oldest unneeded tables while over the budget (a goal needed again meanwhile stays).
  const size_t budget = std::max(goals.size(), settings_.distance_bytes / distances_.bytes_per_target());
  while (static_cast<size_t>(tables_held_) > budget && !unneeded_.empty()) {
    const Vertex v = unneeded_.front();
    unneeded_.pop_front();
    if (bound_for_[v] == 0 && table_held_[v]) {
      distances_.forget(v);
      table_held_[v] = 0;
      --tables_held_;
    }
  }
  distances_.prepare(new_goals, deadline, DistTable::default_threads());
}

void PibtLifelong::follow_traffic(const Config& positions, const Deadline& deadline) {
  if (!settings_.traffic.on || !traffic_.observe(positions)) return;
  if (!distances_.set_traffic_costs(traffic_.costs())) return;  // the same costs: tables stand
  std::vector<Vertex> needed;
  for (Vertex v = 0; v < graph_.vertex_count(); ++v) {
    if (bound_for_[v] > 0) {
      needed.push_back(v);
    } else if (table_held_[v]) {
      table_held_[v] = 0;
      --tables_held_;
    }
  }
  unneeded_.clear();
  distances_.prepare(needed, deadline, DistTable::default_threads());
}

int PibtLifelong::distance(Vertex goal, const Poses& poses, int agent) {
  if (settings_.actions == ActionModel::kRotate) return distances_.get(goal, poses.cells[agent], poses.headings[agent]);
  return distances_.get(goal, poses.cells[agent]);
}

Config PibtLifelong::planning_goals(const Poses& now, const Config& errands) {
  const size_t n = errands.size();
  parked_agent_.assign(n, 0);
  if (!settings_.park_dead_end_errands) return errands;
  released_for_.resize(n, kNoVertex);
  Config planned = errands;
  for (size_t a = 0; a < n; ++a) {
    const bool dead_end = errands[a] != now.cells[a] && graph_.neighbours(errands[a]).size() <= 1;
    if (dead_end && released_for_[a] != errands[a]) {
      planned[a] = now.cells[a];
      parked_agent_[a] = 1;
    }
  }
  // A parked agent standing on the errand of one stuck for stuck_steps_ may be unable to make way
  // (in a dead end behind it): it is let go for that errand of its own.
  if (still_.size() == n) {
    for (size_t a = 0; a < n; ++a) standing_on_[now.cells[a]] = static_cast<int>(a);
    for (size_t b = 0; b < n; ++b) {
      const int there = standing_on_[errands[b]];
      if (parked_agent_[b] || still_[b] < stuck_steps_ || there == -1 || !parked_agent_[there]) continue;
      released_for_[there] = errands[there];
      parked_agent_[there] = 0;
      planned[there] = errands[there];
    }
    for (size_t a = 0; a < n; ++a) standing_on_[now.cells[a]] = -1;
  }
  return planned;
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

std::vector<Poses> PibtLifelong::kept_window(const Poses& now, const Config& goals) {
  std::vector<Poses> window;
  if (last_window_.size() < 2 || last_window_goals_.size() != goals.size()) return window;
  const Poses& planned = last_window_[1];
  const bool rotate = settings_.actions == ActionModel::kRotate;
  if (planned.cells != now.cells || (rotate && planned.headings != now.headings)) return window;  // not carried out
  std::vector<Poses> shifted(last_window_.begin() + 1, last_window_.end());
  shifted.push_back(shifted.back());  // the last step: everyone waits
  // Agents with a new errand (arrived at the step just taken, or parked or let go) go elsewhere.
  // So does an agent standing on its goal with the same errand (the next one is where it stands,
  // and is done a step later): the window held its cell only until it arrived, so the others'
  // paths may lead through it.
  std::vector<int> again;
  std::vector<char> listed(goals.size(), 0);
  for (size_t a = 0; a < goals.size(); ++a) {
    if (goals[a] == last_window_goals_[a] && now.cells[a] != goals[a]) continue;
    again.push_back(static_cast<int>(a));
    listed[a] = 1;
  }
  // Others may have planned to drive through where such an agent stands. When one finds no way,
  // it goes first and the agents about to pass next to it are planned again too, after it.
  for (int round = 0; round < kReplanRounds; ++round) {
    window = shifted;
    int blocked = -1;
    if (lns_.replan(window, goals, again, &blocked)) {
      ++windows_carried_on_;
      return window;
    }
    const auto first = std::find(again.begin(), again.end(), blocked);
    std::rotate(again.begin(), first, first + 1);
    const Vertex there = shifted[0].cells[blocked];
    for (size_t a = 0; a < goals.size(); ++a) {
      if (listed[a]) continue;
      for (size_t t = 1; t <= 2 && t < shifted.size(); ++t) {
        const Vertex cell = shifted[t].cells[a];
        if (cell == there || graph_.adjacent(cell, there)) {
          again.push_back(static_cast<int>(a));
          listed[a] = 1;
          break;
        }
      }
    }
  }
  return {};
}

void PibtLifelong::restore(const StepState& state) {
  rng_ = state.rng;
  still_ = state.still;
  boost_ = state.boost;
  targets_ = state.targets;
  held_steps_ = state.held_steps;
}

bool PibtLifelong::short_of_target(const Poses& now, int agent) const {
  if (settings_.actions != ActionModel::kRotate || targets_.size() != now.cells.size()) return false;
  const Vertex target = targets_[agent];
  return target != now.cells[agent] && graph_.adjacent(now.cells[agent], target);
}

bool PibtLifelong::plan_unfinished(const Poses& now) const {
  bool unfinished = false;
  Config planned = now.cells;
  for (size_t a = 0; a < now.cells.size(); ++a) {
    if (short_of_target(now, static_cast<int>(a))) {
      unfinished = true;
      planned[a] = targets_[a];
    }
  }
  // Targets come from one PIBT step, so they hold together; but window LNS may since have sent
  // some agents elsewhere, onto a cell another still heads for. Such a plan is not held.
  return unfinished && find_step_fault(graph_, now.cells, planned).what.empty();
}

Poses PibtLifelong::carry_out_targets(const Poses& now, const Config& goals) {
  const int n = static_cast<int>(now.cells.size());
  ++held_steps_;
  next_.headings = now.headings;
  next_.cells.assign(n, kNoVertex);
  for (int a = 0; a < n; ++a) {
    // A target is a neighbour or the agent's own cell; plan_unfinished checked they make a valid step.
    next_.cells[a] = short_of_target(now, a) ? targets_[a] : now.cells[a];
    entering_[next_.cells[a]] = a;
  }
  const Config planned = next_.cells;
  take_rotation_actions(now, goals);
  end_step(now, planned);
  return next_;
}

Poses PibtLifelong::one_step(const Poses& now, const Config& goals, const Config& previous_goals) {
  const Config& positions = now.cells;
  const int n = static_cast<int>(positions.size());
  if (holding_ && held_steps_ < kMaxHeldSteps && plan_unfinished(now)) return carry_out_targets(now, goals);
  std::uniform_real_distribution<double> draw(0, 1);
  for (int a = 0; a < n; ++a) {
    if (goals[a] != previous_goals[a] || positions[a] == goals[a]) boost_[a] = 0;
    if (still_[a] >= stuck_steps_ && positions[a] != goals[a]) {
      boost_[a] = 1e12 + draw(rng_);
      still_[a] = 0;
    }
  }
  next_.cells.assign(n, kNoVertex);
  next_.headings = now.headings;
  planning_.assign(n, 0);
  for (int a = 0; a < n; ++a) standing_on_[positions[a]] = a;
  // Agents that were stuck first, in the order drawn; then the nearest their goals (measured:
  // 0-9% more errands than the longest waiting first, history 24), ties by a fixed fraction;
  // parked agents last.
  std::vector<double> rank(n);
  for (int a = 0; a < n; ++a) {
    rank[a] = boost_[a] > 0 ? boost_[a] : fraction_[a] - distance(goals[a], now, a);
    if (settings_.keep_targets && boost_[a] == 0 && short_of_target(now, a)) rank[a] += kTargetPriority;
    if (parked_agent_[a]) rank[a] -= kParkedPriority;
  }
  std::vector<int> order(n);
  for (int a = 0; a < n; ++a) order[a] = a;
  std::sort(order.begin(), order.end(), [&](int x, int y) { return rank[x] > rank[y]; });
  for (int a : order) {
    if (next_.cells[a] == kNoVertex) decide(a, -1, now, goals);
  }
  const Config planned = next_.cells;
  if (settings_.actions == ActionModel::kRotate) {
    targets_ = planned;
    held_steps_ = 1;
    take_rotation_actions(now, goals);
  }
  end_step(now, planned);
  return next_;
}

void PibtLifelong::end_step(const Poses& now, const Config& planned) {
  for (size_t a = 0; a < now.cells.size(); ++a) {
    standing_on_[now.cells[a]] = -1;
    entering_[planned[a]] = -1;
    still_[a] = next_.cells[a] == now.cells[a] ? still_[a] + 1 : 0;
  }
}

int64_t PibtLifelong::step_cost(int agent, const Poses& now, Vertex goal, Vertex cell) {
  const Vertex here = now.cells[agent];
  if (settings_.actions == ActionModel::kMove4) {
    return int64_t{cell == here ? distances_.stay_cost(here) : distances_.move_cost(here, cell)} + distances_.get(goal, cell);
  }
  const int heading = now.headings[agent];
  if (cell == here) return distances_.stay_cost(here) + int64_t{distances_.get(goal, here, heading)};
  // The turns to face the cell, the move, and the cost from there facing on.
  const int towards = heading_towards(graph_, here, cell);
  const int turns = towards == heading ? 0 : (towards == (heading + 2) % kHeadings ? 2 : 1);
  return turns * distances_.stay_cost(here) + int64_t{distances_.move_cost(here, cell)} + distances_.get(goal, cell, towards);
}

void PibtLifelong::take_rotation_actions(const Poses& now, const Config& goals) {
  const int n = static_cast<int>(now.cells.size());
  // Which agents stay on their cells: those PIBT kept there, and those that must turn first.
  std::vector<int> staying;
  for (int a = 0; a < n; ++a) {
    const Vertex here = now.cells[a];
    const Vertex to = next_.cells[a];
    const int heading = now.headings[a];
    if (to == here) {
      staying.push_back(a);
    } else if (to != ahead(graph_, here, heading)) {
      const int towards = heading_towards(graph_, here, to);
      int turned = towards;
      if (towards == (heading + 2) % kHeadings) {  // half round: the quarter nearer the goal first
        const int clockwise = turned_clockwise(heading);
        const int counter = turned_counter_clockwise(heading);
        turned = distances_.get(goals[a], here, counter) < distances_.get(goals[a], here, clockwise) ? counter : clockwise;
      }
      next_.headings[a] = turned;
      next_.cells[a] = here;
      staying.push_back(a);
    }
  }
  // An agent that meant to move onto the cell of one that stays stays too, and so on back along
  // the chain: PIBT gave every cell one taker, so what is left is valid.
  for (size_t k = 0; k < staying.size(); ++k) {
    const int taker = entering_[now.cells[staying[k]]];
    if (taker == -1 || taker == staying[k] || next_.cells[taker] == now.cells[taker]) continue;
    next_.cells[taker] = now.cells[taker];
    staying.push_back(taker);
  }
}

bool PibtLifelong::decide(int agent, int pushed_by, const Poses& now, const Config& goals) {
  const Config& positions = now.cells;
  const Vertex here = positions[agent];
  std::array<Vertex, 5> candidates{};
  int count = 0;
  for (Vertex v : graph_.neighbours(here)) candidates[count++] = v;
  candidates[count++] = here;
  std::shuffle(candidates.begin(), candidates.begin() + count, rng_);  // ties broken at random
  // Each move ranked by its cost plus the cost from where it leads (staying costs 1), ties by
  // whether another agent stands there now.
  std::array<int64_t, 5> rank{};
  const bool pushed_by_stuck = pushed_by != -1 && boost_[pushed_by] > 0;
  // A target is kept even when a stuck agent pushes: 16% more errands on random_400 than not.
  const bool keeps_target = settings_.keep_targets && short_of_target(now, agent);
  for (int k = 0; k < count; ++k) {
    const Vertex v = candidates[k];
    const bool taken = standing_on_[v] != -1 && standing_on_[v] != agent;
    rank[k] = 2 * step_cost(agent, now, goals[agent], v) + (taken ? 1 : 0);
  }
  if (settings_.actions == ActionModel::kRotate && pushed_by_stuck) {
    // Pushed on along the way of an agent that was stuck, it would be pushed again and again down
    // a corridor: a cell to the side is dearer to reach (turns) but lets the pusher pass.
    const Vertex straight_on = ahead(graph_, here, heading_towards(graph_, positions[pushed_by], here));
    for (int k = 0; k < count; ++k) {
      if (candidates[k] == straight_on) rank[k] += 2 * settings_.straight_push_cost;
    }
  }
  for (int k = 0; k < count; ++k) {
    if (keeps_target && candidates[k] == targets_[agent]) rank[k] = -1;  // before any other
  }
  for (int i = 1; i < count; ++i) {  // insertion sort, keeping the shuffled order of ties
    for (int j = i; j > 0 && rank[j] < rank[j - 1]; --j) {
      std::swap(rank[j], rank[j - 1]);
      std::swap(candidates[j], candidates[j - 1]);
    }
  }
  planning_[agent] = 1;
  for (int k = 0; k < count; ++k) {
    const Vertex v = candidates[k];
    if (entering_[v] != -1) continue;
    if (pushed_by != -1 && v == positions[pushed_by]) continue;  // no swap with the agent that pushed
    const int there = standing_on_[v];
    if (settings_.forbid_rotations && there != -1 && there != agent && planning_[there]) continue;
    entering_[v] = agent;
    next_.cells[agent] = v;
    if (there != -1 && there != agent && next_.cells[there] == kNoVertex && !decide(there, agent, now, goals)) {
      continue;  // the agent there could not make way
    }
    planning_[agent] = 0;
    return true;
  }
  planning_[agent] = 0;
  entering_[here] = agent;
  next_.cells[agent] = here;
  return false;
}

StepFault find_step_fault(const Graph& graph, const Config& positions, const Config& next) {
  if (next.size() != positions.size()) {
    return {-1, -1, "a step for " + std::to_string(next.size()) + " agents, not " + std::to_string(positions.size())};
  }
  std::vector<int> entering(graph.vertex_count(), -1);
  for (size_t a = 0; a < next.size(); ++a) {
    const int agent = static_cast<int>(a);
    const Vertex v = next[a];
    if (v < 0 || v >= graph.vertex_count()) return {agent, -1, "agent " + std::to_string(a) + " to no cell"};
    if (v != positions[a] && !graph.adjacent(positions[a], v)) {
      return {agent, -1,
              "agent " + std::to_string(a) + " jumps from " + to_string(graph.cell_of(positions[a])) + " to " +
                  to_string(graph.cell_of(v))};
    }
    if (entering[v] != -1) {
      return {entering[v], agent,
              "agents " + std::to_string(entering[v]) + " and " + std::to_string(a) + " both on " +
                  to_string(graph.cell_of(v))};
    }
    entering[v] = agent;
  }
  std::vector<int> standing(graph.vertex_count(), -1);
  for (size_t a = 0; a < positions.size(); ++a) standing[positions[a]] = static_cast<int>(a);
  for (size_t a = 0; a < next.size(); ++a) {
    const int other = standing[next[a]];
    if (other != -1 && other != static_cast<int>(a) && next[other] == positions[a]) {
      return {static_cast<int>(a), other, "agents " + std::to_string(a) + " and " + std::to_string(other) + " swap"};
    }
  }
  return {};
}

std::string invalid_step(const Graph& graph, const Config& positions, const Config& next) {
  return find_step_fault(graph, positions, next).what;
}

StepFault find_pose_fault(const Graph& graph, ActionModel model, const Poses& now, const Poses& next) {
  if (model == ActionModel::kRotate) {
    if (next.headings.size() != next.cells.size() || now.headings.size() != now.cells.size()) {
      return {-1, -1, "a step without a heading for every agent"};
    }
    for (size_t a = 0; a < next.cells.size() && a < now.cells.size(); ++a) {
      const int agent = static_cast<int>(a);
      const int from = now.headings[a];
      const int to = next.headings[a];
      if (to < 0 || to >= kHeadings) return {agent, -1, "agent " + std::to_string(a) + " faces no heading"};
      if (next.cells[a] == now.cells[a]) {
        if (to == (from + 2) % kHeadings) return {agent, -1, "agent " + std::to_string(a) + " turns half round in one step"};
        continue;
      }
      if (to != from || next.cells[a] != ahead(graph, now.cells[a], from)) {
        return {agent, -1,
                "agent " + std::to_string(a) + " facing " + heading_letter(from) + " moves from " +
                    to_string(graph.cell_of(now.cells[a])) + " other than forward"};
      }
    }
  }
  return find_step_fault(graph, now.cells, next.cells);
}

StepFault find_rotation(const Config& positions, const Config& next) {
  std::unordered_map<Vertex, int> standing;  // cell -> agent there now
  for (size_t a = 0; a < positions.size(); ++a) standing[positions[a]] = static_cast<int>(a);
  // Follow each chain of agents moving into a cell another one leaves; a chain that comes back to
  // one of its own agents holds a cycle. Each agent is walked through once.
  std::vector<int> chain_of(positions.size(), -1);
  for (size_t first = 0; first < positions.size(); ++first) {
    std::vector<int> chain;
    int agent = static_cast<int>(first);
    while (agent != -1 && chain_of[agent] == -1 && next[agent] != positions[agent]) {
      chain_of[agent] = static_cast<int>(first);
      chain.push_back(agent);
      const auto there = standing.find(next[agent]);
      agent = there == standing.end() ? -1 : there->second;
    }
    if (agent != -1 && chain_of[agent] == static_cast<int>(first)) {
      const auto start = std::find(chain.begin(), chain.end(), agent);
      const size_t length = static_cast<size_t>(chain.end() - start);
      if (length < 2) continue;  // an agent into its own cell does not move
      return {*start, *(start + 1),
              "agents " + std::to_string(*start) + ", " + std::to_string(*(start + 1)) + (length > 2 ? ", ..." : "") +
                  " move in a cycle of " + std::to_string(length)};
    }
  }
  return {};
}

namespace {

// Which tasks each agent holds, and how tasks are revealed and handed out.
class TaskBoard {
 public:
  TaskBoard(const LorrProblem& problem, const Config& starts, LifelongLog* log)
      : problem_(problem), log_(log), in_hand_(starts.size()), errand_(starts.size(), 0) {
    const int team = static_cast<int>(starts.size());
    reveal_ = std::max(1, static_cast<int>(std::ceil(problem.tasks_revealed_per_agent)));
    if (problem.assignment == TaskAssignment::kRoundRobin) {
      next_of_agent_.resize(team);
      for (int a = 0; a < team; ++a) next_of_agent_[a] = a;
      for (int a = 0; a < team; ++a) refill(a, starts[a]);
    } else {
      for (int k = 0; k < reveal_ * team; ++k) pool_.push_back(next_task_++);
      for (int a = 0; a < team; ++a) refill(a, starts[a]);
    }
  }

  // The errand agent a heads for, or kNoVertex.
  Vertex goal(int a) const {
    if (in_hand_[a].empty()) return kNoVertex;
    return task(in_hand_[a].front())[errand_[a]];
  }

  // The time events are recorded at: the steps done so far.
  void set_time(int time) { time_ = time; }

  // Agent a stands on `cell`: finishes its errand there, if it is one; returns whether it did,
  // and counts a finished task in `tasks_finished`.
  bool arrive(int a, Vertex cell, DistTable& distances, int64_t& tasks_finished) {
    if (in_hand_[a].empty() || goal(a) != cell) return false;
    if (++errand_[a] == static_cast<int>(task(in_hand_[a].front()).size())) {
      ++tasks_finished;
      if (log_ != nullptr) log_->events[a].push_back({in_hand_[a].front(), time_, true});
      errand_[a] = 0;
      in_hand_[a].pop_front();
      refill(a, cell, &distances);
    }
    return true;
  }

 private:
  const std::vector<Vertex>& task(int64_t k) const { return problem_.tasks[k % problem_.tasks.size()]; }

  void refill(int a, Vertex here, DistTable* distances = nullptr) {
    if (problem_.assignment == TaskAssignment::kRoundRobin) {
      while (static_cast<int>(in_hand_[a].size()) < reveal_) {
        hand_out(a, next_of_agent_[a]);
        next_of_agent_[a] += static_cast<int64_t>(in_hand_.size());
      }
      return;
    }
    if (!in_hand_[a].empty() || pool_.empty()) return;
    size_t best = 0;
    int best_distance = std::numeric_limits<int>::max();
    for (size_t k = 0; k < pool_.size(); ++k) {
      const int d = distances ? distances->get(task(pool_[k]).front(), here) : static_cast<int>(k);
      if (d < best_distance) best_distance = d, best = k;
    }
    hand_out(a, pool_[best]);
    pool_[best] = next_task_++;  // the pool is refilled from the file
  }

  void hand_out(int a, int64_t task) {
    in_hand_[a].push_back(task);
    if (log_ == nullptr) return;
    log_->events[a].push_back({task, time_, false});
    log_->tasks_revealed = std::max(log_->tasks_revealed, task + 1);
  }

  const LorrProblem& problem_;
  LifelongLog* log_;
  int time_ = 0;
  int reveal_ = 1;
  std::vector<std::deque<int64_t>> in_hand_;  // per agent, its tasks in order
  std::vector<int> errand_;                   // per agent, the errand of its first task it heads for
  std::vector<int64_t> next_of_agent_;        // round-robin: the next task each agent gets
  std::vector<int64_t> pool_;                 // greedy: revealed tasks nobody holds
  int64_t next_task_ = 0;
};

}  // namespace

namespace {

// The league's letter for agent a's step from `now` to `next`: in four moves U D L R (row up, row
// down, column left, column right); in the rotation model F (forward), R (clockwise), C
// (counter-clockwise); W for staying, T for no action (no step open to the agent).
char action_letter(const Graph& graph, ActionModel model, const Poses& now, const Poses& next, size_t a) {
  const Vertex from = now.cells[a];
  const Vertex to = next.cells[a];
  if (to < 0 || to >= graph.vertex_count()) return 'T';
  if (model == ActionModel::kRotate) {
    if (a >= next.headings.size()) return 'T';
    const int heading = now.headings[a];
    if (to == from) {
      if (next.headings[a] == heading) return 'W';
      if (next.headings[a] == turned_clockwise(heading)) return 'R';
      return next.headings[a] == turned_counter_clockwise(heading) ? 'C' : 'T';
    }
    return to == ahead(graph, from, heading) && next.headings[a] == heading ? 'F' : 'T';
  }
  if (to == from) return 'W';
  if (!graph.adjacent(from, to)) return 'T';
  const Cell a_cell = graph.cell_of(from);
  const Cell b_cell = graph.cell_of(to);
  if (b_cell.y < a_cell.y) return 'U';
  if (b_cell.y > a_cell.y) return 'D';
  return b_cell.x < a_cell.x ? 'L' : 'R';
}

}  // namespace

LifelongResult run_lifelong(const LorrProblem& problem, LifelongPlanner& planner, const LifelongSettings& settings) {
  const Graph& graph = *problem.graph;
  const ActionModel model = settings.actions;
  Poses now{problem.starts, {}};
  if (model == ActionModel::kRotate) now.headings.assign(now.cells.size(), 0);  // east, as the league starts
  Config& positions = now.cells;
  const int team = static_cast<int>(positions.size());
  LifelongLog* log = settings.log;
  if (log != nullptr) {
    *log = LifelongLog{};
    log->actions = model;
    log->start_headings = now.headings;
    log->starts = positions;
    log->actual.assign(team, "");
    log->planned.assign(team, "");
    log->events.assign(team, {});
    log->cost.assign(team, 0);
  }
  DistTable distances(graph);
  TaskBoard board(problem, positions, log);
  LifelongResult result;
  const auto current_goals = [&] {
    Config goals(team);
    for (int a = 0; a < team; ++a) goals[a] = board.goal(a) == kNoVertex ? positions[a] : board.goal(a);
    return goals;
  };
  {
    const auto started = std::chrono::steady_clock::now();
    planner.prepare(now, current_goals(), Deadline::in_seconds(settings.preprocess_time_s, settings.interrupt));
    result.preprocess_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  }
  for (int step = 0; step < settings.steps; ++step) {
    if (settings.interrupt != nullptr && settings.interrupt->load()) {
      result.interrupted = true;
      break;
    }
    const Config goals = current_goals();
    const auto started = std::chrono::steady_clock::now();
    Poses next = planner.next_step(now, goals, Deadline::in_seconds(settings.step_time_s, settings.interrupt));
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
    result.step_ms.push_back(ms);
    const bool late = ms > 1000 * settings.step_time_s;
    if (log != nullptr) {
      for (int a = 0; a < team; ++a) {
        if (step > 0) log->planned[a] += ',';
        const bool dropped = (late && !settings.late_steps_taken) || next.cells.size() != positions.size();
        log->planned[a] += dropped ? 'T' : action_letter(graph, model, now, next, a);
        if (board.goal(a) != kNoVertex) ++log->cost[a];
      }
    }
    if (late) ++result.steps_over_budget;
    if (late && !settings.late_steps_taken) {
      next = now;
    } else if (const StepFault fault = find_pose_fault(graph, model, now, next); !fault.what.empty()) {
      if (result.invalid_steps++ == 0) result.first_invalid = "step " + std::to_string(step) + ": " + fault.what;
      if (log != nullptr) log->errors.push_back({fault.agent1, fault.agent2, step, fault.what});
      next = now;
    }
    board.set_time(step + 1);
    int finished = 0;
    for (int a = 0; a < team; ++a) {
      result.moves += next.cells[a] != positions[a] ? 1 : 0;
      if (log != nullptr) {
        if (step > 0) log->actual[a] += ',';
        log->actual[a] += action_letter(graph, model, now, next, a);
      }
      positions[a] = next.cells[a];
      if (model == ActionModel::kRotate) now.headings[a] = next.headings[a];
      // One errand per agent and step, as the league counts: a next errand on the same cell is
      // finished at the next step.
      if (board.arrive(a, positions[a], distances, result.tasks_finished)) ++finished;
    }
    result.errands_finished += finished;
    result.errands_per_step.push_back(finished);
  }
  return result;
}

}  // namespace planner_core
