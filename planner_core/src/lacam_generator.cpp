// LaCAM's configuration generator: PIBT under the node's constraints; in the rotation model the
// actions that carry its cells out, and no cycles where the caller forbids them.
#include "lacam_search_state.hpp"

namespace planner_core {

bool LacamSearch::State::generate(const HighLevelNode& node, const Constraint& constraint, Config& next) {
  from_ = &node.config;
  std::fill(next.begin(), next.end(), kNoVertex);
  to_ = &next;
  for (int i = 0; i < n_; ++i) occupied_now_[node.config[i]] = i;
  bool valid = true;
  for (size_t k = 0; k < constraint.who.size() && valid; ++k) {
    const int i = constraint.who[k];
    const Vertex v = turning_ ? cell_of_pose(constraint.where[k]) : constraint.where[k];
    const int occupant = occupied_now_[v];
    if (occupied_next_[v] != kNobody || (occupant != kNobody && next[occupant] == node.config[i])) {
      valid = false;
      break;
    }
    next[i] = v;
    if (turning_) next[n_ + i] = heading_of_pose(constraint.where[k]);
    claim(v, i);
    constrained_[i] = 1;
  }
  for (int k = 0; k < n_ && valid; ++k) {
    const int i = node.order[k];
    if (next[i] == kNoVertex && !plan_move(i)) valid = false;
  }
  if (valid && turning_) valid = take_rotation_actions(node.config, next);
  if (valid && config_.forbid_rotations && has_rotation(node.config, next)) valid = false;
  for (int i = 0; i < n_; ++i) occupied_now_[node.config[i]] = kNobody;
  for (Vertex v : claimed_) occupied_next_[v] = kNobody;
  claimed_.clear();
  for (int i : constraint.who) constrained_[i] = 0;
  return valid;
}

bool LacamSearch::State::plan_move(int agent) {
  const Config& from = *from_;
  Config& to = *to_;
  const Vertex here = from[agent];
  const int progress = current(from, agent);
  Moves candidates;
  int count = 0;
  for (Vertex u : graph_.neighbours(here)) {
    if (!is_blocked(u)) candidates[count++] = u;
  }
  candidates[count++] = here;
  std::shuffle(candidates.begin(), candidates.begin() + count, rng_);
  MoveKeys to_goal{};
  // An agent on its current target (its goal, mostly) needs no look-up: it is 0 away and each
  // open neighbour 1 (the look-ups are cache misses, and at 10,000 agents many stand on goals).
  const int target_slot = slot(agent, progress);
  const bool on_target = here == targets_[target_slot];
  // Nearest to the goal first; among equals (with prefer_free_cells) a cell nobody stands on.
  for (int k = 0; k < count; ++k) {
    const Vertex v = candidates[k];
    const bool pushes_someone = config_.prefer_free_cells && occupied_now_[v] != kNobody && v != here;
    int distance = 0;
    if (turning_) {
      distance = std::min(turning_cost(agent, progress, here, heading(from, agent), v), kUnreachable);
    } else {
      distance = on_target ? remaining_[target_slot] + (v == here ? 0 : 1) : distance_to_goal(agent, progress, v);
    }
    to_goal[k] = 2 * distance + (pushes_someone ? 1 : 0);
  }
  sort_by_key(candidates, to_goal, count);
  if (config_.guide && !augmented_) {
    const Vertex preferred = config_.guide->next(agent, here);
    const auto at = std::find(candidates.begin(), candidates.begin() + count, preferred);
    if (preferred != kNoVertex && at != candidates.begin() + count) std::rotate(candidates.begin(), at, at + 1);
  }
  // A head-on meeting in a corridor: back off (worst candidate first) and pull the other along.
  const int partner = config_.swap ? swap_.partner(agent, here, candidates[0], to) : kNobody;
  if (partner != kNobody) std::reverse(candidates.begin(), candidates.begin() + count);
  for (int k = 0; k < count; ++k) {
    const Vertex v = candidates[k];
    if (occupied_next_[v] != kNobody) continue;
    const int occupant = occupied_now_[v];
    if (occupant != kNobody && occupant != agent && to[occupant] == here) continue;
    if (config_.forbid_rotations && v != here && closes_rotation(agent, v)) continue;
    to[agent] = v;
    claim(v, agent);
    if (occupant != kNobody && occupant != agent && to[occupant] == kNoVertex && !plan_move(occupant)) continue;
    if (k == 0 && partner != kNobody && v != here && to[partner] == kNoVertex && occupied_next_[here] == kNobody &&
        !(config_.forbid_rotations && closes_rotation(partner, here))) {
      to[partner] = here;  // the partner follows into the cell we leave
      claim(here, partner);
    }
    return true;
  }
  // Staying put is impossible when a constrained agent must move here; the claim of the agent
  // that pushed us is simply overridden (it goes on to its next candidate, as in PIBT).
  const int claimant = occupied_next_[here];
  if (claimant != kNobody && claimant != agent && constrained_[claimant]) {
    to[agent] = kNoVertex;
    return false;
  }
  to[agent] = here;
  claim(here, agent);
  return false;
}

int LacamSearch::State::turning_actions(const Config& config, int agent, Moves& poses) const {
  const Vertex here = config[agent];
  const int facing = heading(config, agent);
  int count = 0;
  const Vertex forward = ahead(graph_, here, facing);
  if (forward != kNoVertex) poses[count++] = pose_code(forward, facing);
  poses[count++] = pose_code(here, turned_clockwise(facing));
  poses[count++] = pose_code(here, turned_counter_clockwise(facing));
  poses[count++] = pose_code(here, facing);
  return count;
}

int LacamSearch::State::turning_cost(int agent, int progress, Vertex here, int facing, Vertex v) {
  if (v == here) return 1 + distance_to_goal(agent, progress, here, facing);
  const int towards = heading_towards(graph_, here, v);
  return turns_between(facing, towards) + 1 + distance_to_goal(agent, progress, v, towards);
}

bool LacamSearch::State::take_rotation_actions(const Config& from, Config& to) {
  staying_.clear();
  for (int a = 0; a < n_; ++a) {
    const Vertex here = from[a];
    const int facing = heading(from, a);
    if (constrained_[a]) {
      if (to[a] == here) staying_.push_back(a);
      continue;
    }
    to[n_ + a] = facing;
    if (to[a] == here) {
      staying_.push_back(a);
      continue;
    }
    if (to[a] == ahead(graph_, here, facing)) continue;
    int turned = heading_towards(graph_, here, to[a]);
    if (turns_between(facing, turned) == 2) {
      const int progress = current(from, a);
      const int clockwise = turned_clockwise(facing);
      const int counter = turned_counter_clockwise(facing);
      turned = distance_to_goal(a, progress, here, counter) < distance_to_goal(a, progress, here, clockwise)
                   ? counter
                   : clockwise;
    }
    to[n_ + a] = turned;
    to[a] = here;
    staying_.push_back(a);
  }
  for (size_t k = 0; k < staying_.size(); ++k) {
    const int taker = occupied_next_[from[staying_[k]]];
    if (taker == kNobody || taker == staying_[k] || to[taker] == from[taker]) continue;
    if (constrained_[taker]) return false;
    to[taker] = from[taker];
    to[n_ + taker] = heading(from, taker);
    staying_.push_back(taker);
  }
  return true;
}

bool LacamSearch::State::closes_rotation(int agent, Vertex v) const {
  const Config& to = *to_;
  Vertex cell = v;
  for (int hops = 0; hops <= n_; ++hops) {
    const int occupant = occupied_now_[cell];
    if (occupant == kNobody) return false;  // the chain ends at a free cell
    if (occupant == agent) return true;
    if (to[occupant] == kNoVertex || to[occupant] == cell) return false;  // not planned yet, or stays
    cell = to[occupant];
  }
  return false;
}

bool LacamSearch::State::has_rotation(const Config& from, const Config& to) const {
  for (int start = 0; start < n_; ++start) {
    int agent = start;
    for (int hops = 0; hops <= n_; ++hops) {
      if (to[agent] == from[agent]) break;  // the chain ends at an agent that stays
      const int next = occupied_now_[to[agent]];
      if (next == kNobody) break;             // moving into a free cell
      if (next == start) return true;
      agent = next;
    }
  }
  return false;
}

}  // namespace planner_core
