// LaCAM's search state (LacamSearch::State), private to planner_core: the high-level search over
// configurations in lacam_search.cpp, its configuration generator (PIBT under constraints, and in
// the rotation model the actions that carry its cells out) in lacam_generator.cpp.
#pragma once

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
#include "planner_core/lacam.hpp"

namespace planner_core {

namespace lacam_detail {

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
inline Vertex pose_code(Vertex cell, int heading) { return cell * kHeadings + heading; }
inline Vertex cell_of_pose(Vertex pose) { return pose / kHeadings; }
inline int heading_of_pose(Vertex pose) { return pose % kHeadings; }

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

}  // namespace lacam_detail

using namespace lacam_detail;  // NOLINT: the search's own private names, in its own files only

class LacamSearch::State {
 public:
  State(const Graph& graph, DistTable& dist, const LacamConfig& config, std::mt19937& rng, const Config& starts,
        const Config& goals, const std::vector<char>& blocked, const Waypoints& waypoints,
        const Headings& start_headings);

  // Searches until the deadline, until the whole space has been searched, or until it holds a
  // solution cheaper than the one it last returned; a later call goes on from there.
  LacamResult run(const Deadline& deadline);

 private:
  std::vector<int> bfs_around_blocked(Vertex target) const;

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

  HighLevelNode* make_node(const Config& config, HighLevelNode* parent);

  // Agents by decreasing priority, ties by index. From the parent's order in O(agents) rather than
  // by a sort (7% of the samples of a 10,000-agent search): the agents whose priority grew by one
  // keep their order (up to ties that rounding creates, mended by an insertion sort that costs
  // nothing when there are none), those whose priority did not change keep theirs exactly, and
  // only the few that reached a target are sorted; the three runs are then merged.
  void order_by_priority(HighLevelNode& node, const HighLevelNode* parent);

  // Lazily adds the children of `constraint`: the next agent in order fixed to each of its moves.
  void grow_constraints(HighLevelNode& node, const Constraint& constraint);

  // PIBT configuration generator obeying `constraint`; false when no valid configuration results.
  bool generate(const HighLevelNode& node, const Constraint& constraint, Config& next);

  bool plan_move(int agent);

  // The rotation model: agent's actions in `config` as the poses they lead to (pose_code): forward
  // when there is a cell ahead, a quarter turn either way, a wait. Returns how many.
  int turning_actions(const Config& config, int agent, Moves& poses) const;

  // The rotation model: PIBT picks cells (plan_move), each neighbour costed with the turns needed to
  // face it and a wait costed as a step, as Extended-PIBT does with turns.
  int turning_cost(int agent, int progress, Vertex here, int facing, Vertex v);

  // The rotation model: the cells PIBT picked (in `to`) become actions. The cell ahead is a forward
  // move; any other neighbour means staying and turning a quarter towards it (of a half round, the
  // quarter nearer the target). Whoever meant to enter the cell of an agent that stays waits too,
  // back along the chain; PIBT gave every cell one taker, so the step left is free of conflicts.
  // Constrained agents keep their actions; false when one of them would have to wait.
  bool take_rotation_actions(const Config& from, Config& to);

  // Would `agent` moving into `v` close a cycle of agents each moving into the next one's cell? The
  // chain from v: its occupant's move, that cell's occupant's move, ..., back to `agent`. Checked
  // as each agent is planned, so the agent that would close a cycle (the last of it planned)
  // takes another move instead of the whole configuration being thrown away.
  bool closes_rotation(int agent, Vertex v) const;

  // Agents moving into cells left by agents that also move, closing a cycle.
  bool has_rotation(const Config& from, const Config& to) const;

  void claim(Vertex v, int agent) {
    occupied_next_[v] = agent;
    claimed_.push_back(v);
  }

  // LaCAM*: every node's cost from the start over every link recorded so far (Dijkstra), once,
  // when the first solution is found.
  void settle_costs();

  // LaCAM*: a cheaper way into `to` was found through `from`; propagate cheaper costs (Dijkstra).
  void rewire(HighLevelNode* from, HighLevelNode* to);

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

}  // namespace planner_core
