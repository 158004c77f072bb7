#include "planner_core/lacam.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <iterator>
#include <map>
#include <numeric>
#include <memory>
#include <queue>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_set>
#include <utility>

#include "planner_core/corridor_swap.hpp"
#include "planner_core/guided_distances.hpp"
#include "planner_core/scatter.hpp"

namespace planner_core {

namespace {

constexpr int kNobody = -1;
// Work (deadline.hpp) of one high-level iteration beyond its agents' moves: a node's allocations
// and bookkeeping, which dominate with the few agents of a lock release (measured with perf).
constexpr int kWorkPerNode = 16;

struct ConfigHash {
  size_t operator()(const Config& config) const {
    size_t hash = config.size();
    for (Vertex v : config) hash ^= static_cast<size_t>(v) + 0x9e3779b97f4a7c15ULL + (hash << 6) + (hash >> 2);
    return hash;
  }
};

// A low-level node: the first `who.size()` agents of the high-level order are fixed to `where`:
// a cell, or in the rotation model a pose (pose_code: the cell and the heading after the action).
struct Constraint {
  std::vector<int> who;
  std::vector<Vertex> where;
};

// A cell and a heading in one number (the rotation model's constraints and candidate actions).
Vertex pose_code(Vertex cell, int heading) { return cell * kHeadings + heading; }
Vertex cell_of_pose(Vertex pose) { return pose / kHeadings; }
int heading_of_pose(Vertex pose) { return pose % kHeadings; }

struct HighLevelNode {
  Config config;  // the agents' vertices; in the rotation model then their headings; with waypoints
                  // then their progress
  HighLevelNode* parent = nullptr;
  int64_t g = 0;  // sum of loss from the start
  int64_t h = -1;  // sum of distances to the goals (through the waypoints still to visit); -1 until asked
  std::vector<float> priority;
  std::vector<int> order;  // agents by decreasing priority
  std::deque<Constraint> constraints;
  std::vector<HighLevelNode*> neighbours;  // LaCAM*: known successors, for rewiring
  int64_t id = 0;  // the order of creation: breaks ties where an address would (reproducibility)
};

// The explored nodes are kept by their configuration without a second copy of it (40 KB a node
// at 10,000 agents): the set holds the nodes and is searched with a bare configuration.
struct NodeByConfig {
  using is_transparent = void;
  size_t operator()(const HighLevelNode* node) const { return ConfigHash{}(node->config); }
  size_t operator()(const Config& config) const { return ConfigHash{}(config); }
};

struct SameConfig {
  using is_transparent = void;
  bool operator()(const HighLevelNode* a, const HighLevelNode* b) const { return a->config == b->config; }
  bool operator()(const Config& a, const HighLevelNode* b) const { return a == b->config; }
  bool operator()(const HighLevelNode* a, const Config& b) const { return a->config == b; }
};

}  // namespace

class LacamSearch::State {
 public:
  State(const Graph& graph, DistTable& dist, const LacamConfig& config, std::mt19937& rng, const Config& starts,
        const Config& goals, const std::vector<char>& blocked, const Waypoints& waypoints,
        const Headings& start_headings)
      : graph_(graph),
        config_(config),
        rng_(rng),
        goals_(goals),
        blocked_(blocked),
        n_(static_cast<int>(starts.size())),
        turning_(config.turning),
        occupied_now_(graph.vertex_count(), kNobody),
        occupied_next_(graph.vertex_count(), kNobody),
        constrained_(starts.size(), 0),
        swap_(graph, occupied_now_, [this](int agent, Vertex v) { return distance_to_target(agent, current(*from_, agent), v); },
              [this](int agent) { return targets_[slot(agent, current(*from_, agent))]; }) {
    for (const std::vector<Vertex>& row : waypoints) augmented_ = augmented_ || !row.empty();
    if (turning_) {
      if (!blocked.empty()) throw std::invalid_argument("LaCAM in the rotation model takes no blocked cells");
      if (start_headings.size() != starts.size()) {
        throw std::invalid_argument("LaCAM in the rotation model needs one start heading per agent");
      }
      for (int heading : start_headings) {
        if (heading < 0 || heading >= kHeadings) {
          throw std::invalid_argument("LaCAM in the rotation model: start heading " + std::to_string(heading) +
                                      " is not 0..3");
        }
      }
      config_.swap = false;  // CorridorSwap's moves are four-way
      config_.guide = nullptr;
    }
    progress_at_ = turning_ ? 2 * n_ : n_;
    config_size_ = progress_at_ + (augmented_ ? n_ : 0);
    // Every agent's targets in a row: its waypoints, then its goal; slot(agent, k) indexes them.
    for (int i = 0; i < n_; ++i) {
      first_target_.push_back(static_cast<int>(targets_.size()));
      if (augmented_) targets_.insert(targets_.end(), waypoints[i].begin(), waypoints[i].end());
      last_.push_back(static_cast<int>(targets_.size()) - first_target_.back());
      targets_.push_back(goals[i]);
    }
    if (!blocked.empty()) {
      config_.swap = false;  // CorridorSwap's corridor walks do not know blocked cells
      std::map<Vertex, int> searched;
      for (Vertex target : targets_) {
        const auto [it, is_new] = searched.try_emplace(target, static_cast<int>(own_distances_.size()));
        if (is_new) own_distances_.push_back(bfs_around_blocked(target));
        own_index_.push_back(it->second);
      }
    } else {
      for (Vertex target : targets_) target_rows_.push_back(dist.row(target));
    }
    // What is left of each agent's tour from each of its targets, along its order.
    remaining_.assign(targets_.size(), 0);
    for (int i = 0; i < n_; ++i) {
      for (int k = last_[i] - 1; k >= 0; --k) {
        const int leg = distance_to_target(i, k + 1, targets_[slot(i, k)]);
        remaining_[slot(i, k)] = std::min(kUnreachable, remaining_[slot(i, k + 1)] + leg);
      }
    }
    Config start = starts;
    start.resize(config_size_, 0);
    if (turning_) std::copy(start_headings.begin(), start_headings.end(), start.begin() + n_);
    if (augmented_) {
      for (int i = 0; i < n_; ++i) start[progress_at_ + i] = advance(i, 0, starts[i]);
    }
    open_.push_back(make_node(start, nullptr));
  }

  // Searches until the deadline, until the whole space has been searched, or until it holds a
  // solution cheaper than the one it last returned; a later call goes on from there.
  LacamResult run(const Deadline& deadline) {
    LacamResult result;
    Config next(config_size_);
    // With many agents an iteration is long enough to look at the clock every time.
    const int64_t clock_mask = n_ >= 256 ? 0 : 63;
    while (!open_.empty()) {
      deadline.spend(n_ + kWorkPerNode);
      if ((++iterations_ & clock_mask) == 0 && deadline.expired()) break;
      if (goal_node_ && goal_node_->g < reported_cost_) break;
      HighLevelNode* node = open_.back();
      if (all_home(node->config) && (!goal_node_ || node->g < goal_node_->g)) {
        goal_node_ = node;
        if (!config_.refine) break;
        settle_costs();  // the links recorded before the first solution can make it cheaper
        continue;
      }
      if (goal_node_ && node->g + heuristic(*node) >= goal_node_->g) {  // LaCAM*: cannot beat the best found
        open_.pop_back();
        continue;
      }
      if (node->constraints.empty()) {
        open_.pop_back();
        continue;
      }
      Constraint constraint = std::move(node->constraints.front());
      node->constraints.pop_front();
      grow_constraints(*node, constraint);
      if (!generate(*node, constraint, next)) continue;
      if (augmented_) {
        for (int i = 0; i < n_; ++i) next[progress_at_ + i] = advance(i, current(node->config, i), next[i]);
      }
      const auto found = explored_.find(next);
      if (found != explored_.end()) {
        HighLevelNode* known = *found;
        if (config_.refine) {
          // Before the first solution costs matter to nobody: only record the link, and
          // settle_costs propagates them all once when a goal is found, instead of a propagation
          // at every revisit (a search stuck near the goal revisits thousands of times).
          if (goal_node_) {
            rewire(node, known);
          } else {
            node->neighbours.push_back(known);
          }
        }
        open_.push_back(known);
      } else {
        open_.push_back(make_node(next, node));
      }
    }
    result.explored = static_cast<int64_t>(nodes_.size());
    result.exhausted = open_.empty();
    if (goal_node_) {
      result.solved = true;
      result.cost = goal_node_->g;
      reported_cost_ = goal_node_->g;
      for (HighLevelNode* h = goal_node_; h; h = h->parent) {
        result.solution.emplace_back(h->config.begin(), h->config.begin() + n_);
        if (turning_) result.headings.emplace_back(h->config.begin() + n_, h->config.begin() + 2 * n_);
      }
      std::reverse(result.solution.begin(), result.solution.end());
      std::reverse(result.headings.begin(), result.headings.end());
    }
    return result;
  }

 private:
  std::vector<int> bfs_around_blocked(Vertex target) const {
    std::vector<int> dist(graph_.vertex_count(), kUnreachable);
    std::vector<Vertex> queue{target};
    dist[target] = 0;
    for (size_t head = 0; head < queue.size(); ++head) {
      for (Vertex u : graph_.neighbours(queue[head])) {
        if (dist[u] == kUnreachable && !blocked_[u]) {
          dist[u] = dist[queue[head]] + 1;
          queue.push_back(u);
        }
      }
    }
    return dist;
  }

  bool is_blocked(Vertex v) const { return !blocked_.empty() && blocked_[v]; }

  // Where agent's k-th target (0 for plain MAPF) is kept in targets_ and the tables beside it.
  int slot(int agent, int k) const { return augmented_ ? first_target_[agent] + k : agent; }
  // How many of its waypoints the agent has visited in `config` (always 0 for plain MAPF).
  int current(const Config& config, int agent) const { return augmented_ ? config[progress_at_ + agent] : 0; }
  int heading(const Config& config, int agent) const { return config[n_ + agent]; }
  // The progress after standing on v, having visited k waypoints before.
  int advance(int agent, int k, Vertex v) const {
    while (k < last_[agent] && v == targets_[slot(agent, k)]) ++k;
    return k;
  }
  bool home(const Config& config, int agent) const {
    return config[agent] == goals_[agent] && current(config, agent) == last_[agent];
  }
  bool all_home(const Config& config) const {
    for (int i = 0; i < n_; ++i) {
      if (!home(config, i)) return false;
    }
    return true;
  }

  int distance_to_target(int agent, int k, Vertex v) {
    const int s = slot(agent, k);
    return own_distances_.empty() ? target_rows_[s].get(v) : own_distances_[own_index_[s]][v];
  }
  // Through the waypoints still to visit, to the goal.
  int distance_to_goal(int agent, int k, Vertex v) {
    return std::min(kUnreachable, distance_to_target(agent, k, v) + remaining_[slot(agent, k)]);
  }
  // The same from a pose in the rotation model: the next target's distance with turns (any heading
  // there), the rest of the tour without (still a lower bound, and LaCAM*'s pruning needs no more).
  int distance_to_goal(int agent, int k, Vertex v, int facing) {
    const int to_target = std::min(kUnreachable, turning_->get(targets_[slot(agent, k)], v, facing));
    return std::min(kUnreachable, to_target + remaining_[slot(agent, k)]);
  }
  // Agent's distance to its goal in `config`, in either model.
  int distance_from(const Config& config, int agent) {
    const int k = current(config, agent);
    return turning_ ? distance_to_goal(agent, k, config[agent], heading(config, agent))
                    : distance_to_goal(agent, k, config[agent]);
  }

  int64_t transition_cost(const Config& from, const Config& to) const {
    int64_t cost = 0;
    for (int i = 0; i < n_; ++i) cost += (home(from, i) && home(to, i)) ? 0 : 1;
    return cost;
  }

  // LaCAM*'s pruning needs it only once a solution is known: computed then, for the nodes it
  // meets (a look-up per agent, mostly cache misses at 10,000 agents).
  int64_t heuristic(HighLevelNode& node) {
    if (node.h < 0) {
      node.h = 0;
      for (int i = 0; i < n_; ++i) node.h += distance_from(node.config, i);
    }
    return node.h;
  }

  HighLevelNode* make_node(const Config& config, HighLevelNode* parent) {
    auto node = std::make_unique<HighLevelNode>();
    node->config = config;
    node->parent = parent;
    node->id = static_cast<int64_t>(nodes_.size());
    node->priority.resize(n_);
    grew_.assign(n_, 0);
    for (int i = 0; i < n_; ++i) {
      const int k = current(config, i);
      if (!parent) {
        node->priority[i] = static_cast<float>(distance_from(config, i)) / static_cast<float>(n_ * 4 + 1);
      } else if (!home(config, i) && k == current(parent->config, i)) {
        // dynamic priorities: grow until the next waypoint or the goal is reached
        node->priority[i] = parent->priority[i] + 1;
        grew_[i] = 1;
      } else {
        node->priority[i] = parent->priority[i] - static_cast<float>(static_cast<int64_t>(parent->priority[i]));
      }
    }
    if (parent) {
      node->g = parent->g + transition_cost(parent->config, config);
      if (config_.refine) parent->neighbours.push_back(node.get());
    }
    order_by_priority(*node, parent);
    node->constraints.push_back({});
    HighLevelNode* raw = node.get();
    explored_.insert(raw);
    nodes_.push_back(std::move(node));
    return raw;
  }

  // Agents by decreasing priority, ties by index. From the parent's order in O(agents) rather than
  // by a sort (7% of the samples of a 10,000-agent search): the agents whose priority grew by one
  // keep their order (up to ties that rounding creates, mended by an insertion sort that costs
  // nothing when there are none), those whose priority did not change keep theirs exactly, and
  // only the few that reached a target are sorted; the three runs are then merged.
  void order_by_priority(HighLevelNode& node, const HighLevelNode* parent) {
    const std::vector<float>& priority = node.priority;
    const auto before = [&](int a, int b) { return priority[a] > priority[b] || (priority[a] == priority[b] && a < b); };
    node.order.resize(n_);
    if (!parent) {
      std::iota(node.order.begin(), node.order.end(), 0);
      std::sort(node.order.begin(), node.order.end(), before);
      return;
    }
    grown_.clear();
    kept_.clear();
    reset_.clear();
    for (int i : parent->order) {
      if (grew_[i]) {
        grown_.push_back(i);
      } else if (priority[i] == parent->priority[i]) {
        kept_.push_back(i);
      } else {
        reset_.push_back(i);
      }
    }
    for (size_t k = 1; k < grown_.size(); ++k) {
      for (size_t j = k; j > 0 && before(grown_[j], grown_[j - 1]); --j) std::swap(grown_[j], grown_[j - 1]);
    }
    std::sort(reset_.begin(), reset_.end(), before);
    merged_.clear();
    std::merge(grown_.begin(), grown_.end(), kept_.begin(), kept_.end(), std::back_inserter(merged_), before);
    std::merge(merged_.begin(), merged_.end(), reset_.begin(), reset_.end(), node.order.begin(), before);
  }

  // Lazily adds the children of `constraint`: the next agent in order fixed to each of its moves.
  void grow_constraints(HighLevelNode& node, const Constraint& constraint) {
    const int depth = static_cast<int>(constraint.who.size());
    if (depth >= n_) return;
    const int agent = node.order[depth];
    const Vertex here = node.config[agent];
    Moves moves;
    int count = 0;
    if (turning_) {
      count = turning_actions(node.config, agent, moves);
    } else {
      for (Vertex u : graph_.neighbours(here)) {
        if (!is_blocked(u)) moves[count++] = u;
      }
      moves[count++] = here;
    }
    std::shuffle(moves.begin(), moves.begin() + count, rng_);
    for (int k = 0; k < count; ++k) {
      Constraint child = constraint;
      child.who.push_back(agent);
      child.where.push_back(moves[k]);
      node.constraints.push_back(std::move(child));
    }
  }

  // PIBT configuration generator obeying `constraint`; false when no valid configuration results.
  bool generate(const HighLevelNode& node, const Constraint& constraint, Config& next) {
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

  bool plan_move(int agent) {
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

  // The rotation model: agent's actions in `config` as the poses they lead to (pose_code): forward
  // when there is a cell ahead, a quarter turn either way, a wait. Returns how many.
  int turning_actions(const Config& config, int agent, Moves& poses) const {
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

  // The rotation model: PIBT picks cells (plan_move), each neighbour costed with the turns needed to
  // face it and a wait costed as a step, as Extended-PIBT does with turns.
  int turning_cost(int agent, int progress, Vertex here, int facing, Vertex v) {
    if (v == here) return 1 + distance_to_goal(agent, progress, here, facing);
    const int towards = heading_towards(graph_, here, v);
    return turns_between(facing, towards) + 1 + distance_to_goal(agent, progress, v, towards);
  }

  // The rotation model: the cells PIBT picked (in `to`) become actions. The cell ahead is a forward
  // move; any other neighbour means staying and turning a quarter towards it (of a half round, the
  // quarter nearer the target). Whoever meant to enter the cell of an agent that stays waits too,
  // back along the chain; PIBT gave every cell one taker, so the step left is free of conflicts.
  // Constrained agents keep their actions; false when one of them would have to wait.
  bool take_rotation_actions(const Config& from, Config& to) {
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

  // Would `agent` moving into `v` close a cycle of agents each moving into the next one's cell? The
  // chain from v: its occupant's move, that cell's occupant's move, ..., back to `agent`. Checked
  // as each agent is planned, so the agent that would close a cycle (the last of it planned)
  // takes another move instead of the whole configuration being thrown away.
  bool closes_rotation(int agent, Vertex v) const {
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

  // Agents moving into cells left by agents that also move, closing a cycle.
  bool has_rotation(const Config& from, const Config& to) const {
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

  void claim(Vertex v, int agent) {
    occupied_next_[v] = agent;
    claimed_.push_back(v);
  }

  // LaCAM*: every node's cost from the start over every link recorded so far (Dijkstra), once,
  // when the first solution is found.
  void settle_costs() {
    using Entry = std::tuple<int64_t, int64_t, HighLevelNode*>;  // g, id, node
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    for (const std::unique_ptr<HighLevelNode>& node : nodes_) node->g = INT64_MAX;
    HighLevelNode* start = nodes_.front().get();
    start->g = 0;
    start->parent = nullptr;
    queue.push({0, start->id, start});
    while (!queue.empty()) {
      const auto [g, id, node] = queue.top();
      queue.pop();
      if (g > node->g) continue;
      for (HighLevelNode* next : node->neighbours) {
        const int64_t through = g + transition_cost(node->config, next->config);
        if (through < next->g) {
          next->g = through;
          next->parent = node;
          queue.push({through, next->id, next});
        }
      }
    }
  }

  // LaCAM*: a cheaper way into `to` was found through `from`; propagate cheaper costs (Dijkstra).
  void rewire(HighLevelNode* from, HighLevelNode* to) {
    from->neighbours.push_back(to);
    std::deque<HighLevelNode*> queue{from};
    while (!queue.empty()) {
      HighLevelNode* node = queue.front();
      queue.pop_front();
      for (HighLevelNode* next : node->neighbours) {
        const int64_t g = node->g + transition_cost(node->config, next->config);
        if (g < next->g) {
          next->g = g;
          next->parent = node;
          queue.push_back(next);
        }
      }
    }
  }

  const Graph& graph_;
  LacamConfig config_;
  std::mt19937& rng_;
  const Config goals_;
  const std::vector<char> blocked_;
  const int n_;
  GuidedDistances* const turning_;  // the rotation model's distances; null in the four-move model
  int progress_at_ = 0;             // where the agents' progress starts in a configuration
  int config_size_ = 0;
  HighLevelNode* goal_node_ = nullptr;
  int64_t reported_cost_ = INT64_MAX;  // of the solution run() last returned
  int64_t iterations_ = 0;
  bool augmented_ = false;          // some agent has waypoints: configurations carry progress
  std::vector<Vertex> targets_;     // per agent its waypoints then its goal, agent after agent
  std::vector<int> first_target_;   // agent -> its first slot in targets_
  std::vector<int> last_;           // agent -> its number of waypoints (the goal's index)
  std::vector<int> remaining_;      // per slot: the tour's length from that target to the goal
  std::vector<std::vector<int>> own_distances_;  // per target cell, around blocked cells (empty when none are)
  std::vector<int> own_index_;                   // per slot: its target's row in own_distances_
  std::vector<DistTable::Row> target_rows_;      // per slot, when nothing is blocked
  std::vector<std::unique_ptr<HighLevelNode>> nodes_;
  std::unordered_set<HighLevelNode*, NodeByConfig, SameConfig> explored_;  // looked up by configuration
  std::vector<HighLevelNode*> open_;
  std::vector<int> occupied_now_, occupied_next_;
  std::vector<Vertex> claimed_;  // every vertex written in occupied_next_ this generation
  std::vector<char> constrained_;  // agents fixed by the current constraint
  std::vector<char> grew_;  // make_node's: agents whose priority grew by one from the parent's
  std::vector<int> grown_, kept_, reset_, merged_;  // order_by_priority's scratch
  std::vector<int> staying_;                         // take_rotation_actions' scratch
  const Config* from_ = nullptr;
  Config* to_ = nullptr;
  CorridorSwap swap_;  // reads occupied_now_
};

LacamSearch::LacamSearch(const Graph& graph, DistTable& dist, const LacamConfig& config, std::mt19937& rng,
                         const Config& starts, const Config& goals, const std::vector<char>& blocked,
                         const Waypoints& waypoints, const Headings& start_headings)
    : state_(std::make_unique<State>(graph, dist, config, rng, starts, goals, blocked, waypoints, start_headings)) {}

LacamSearch::~LacamSearch() = default;

LacamResult LacamSearch::run(const Deadline& deadline) { return state_->run(deadline); }

Lacam::Lacam(const Graph& graph, DistTable& dist, const LacamConfig& config, std::mt19937& rng)
    : graph_(graph), dist_(dist), config_(config), rng_(rng) {}

LacamResult Lacam::solve(const Config& starts, const Config& goals, const std::vector<char>& blocked,
                         const Deadline& deadline, const Waypoints& waypoints) {
  LacamSearch search(graph_, dist_, config_, rng_, starts, goals, blocked, waypoints);
  return search.run(deadline);
}

}  // namespace planner_core
