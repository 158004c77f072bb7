// One PIBT step of PibtLifelong: priorities, each agent's choice with priority inheritance, and in
// the rotation model the turns that carry the chosen cells out.
#include "planner_core/pibt_lifelong.hpp"

#include <algorithm>
#include <array>

namespace planner_core {

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
  const Vertex guided = settings_.guide_paths.on ? guides_.next(agent, here) : kNoVertex;
  for (int k = 0; k < count; ++k) {
    if (keeps_target && candidates[k] == targets_[agent]) rank[k] = -1;  // before any other
    if (candidates[k] == guided) rank[k] = -1;                           // and so is its guide's next cell
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

}  // namespace planner_core
