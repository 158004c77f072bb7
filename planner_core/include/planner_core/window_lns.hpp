// Large Neighbourhood Search over a window of the lifelong plan (the idea of the League of Robot
// Runners' 2023 winner, Jiang et al., "Scaling Lifelong Multi-Agent Path Finding to More Realistic
// Settings", 2024): PIBT proposes the next `window` steps of every agent; then, while time is
// left, a few agents (around one that is late, or as `neighbourhoods` picks) are taken out and
// each is planned again by space-time A* through the others' reserved cells, and the new paths are
// kept if they cost less together (or, with keep_equal_cost, no more). Only the window's first
// step is carried out; the next step plans afresh.
//
// An agent's cost over the window: the cost of its actions until it first stands on its goal
// (a move its guided cost, a turn or a wait 1), or, if it does not get there, that sum plus its
// guided distance from where the window leaves it. An agent holds cells only until it first
// stands on its goal: there the league gives it its next errand, which takes it on, so the others
// may plan through that cell later in the window (the window shows it standing there; when the
// next errand is at the same cell, PibtLifelong::kept_window plans the agent again). Paths are
// kept free of shared cells and swaps at every step among the agents yet to arrive, in either
// action model; the first step, the one carried out, is valid for all.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "planner_core/action_model.hpp"
#include "planner_core/deadline.hpp"
#include "planner_core/guide_paths.hpp"
#include "planner_core/guided_distances.hpp"

namespace planner_core {

struct WindowLnsStats {
  int64_t iterations = 0;
  int64_t improvements = 0;  // rounds whose new paths cost less
  int64_t cost_before = 0;
  int64_t cost_after = 0;
  // Adaptive neighbourhoods: rounds and improvements by kind (nearest, crossing, random).
  std::array<int64_t, 3> rounds_by_kind{};
  std::array<int64_t, 3> improvements_by_kind{};
};

class WindowLns {
 public:
  static constexpr int kNeighbourhood = 8;  // agents planned again together
  // Adaptive neighbourhoods: how far a gain pulls a kind's weight, and how much a failure shrinks it.
  static constexpr double kKindReaction = 0.01;
  static constexpr double kKindDecay = 0.01;
  static constexpr double kLeastKindWeight = 1e-12;  // weights stay above 0 through long runs of failures

  WindowLns(const Graph& graph, GuidedDistances& distances, ActionModel actions);

  // Improves `window` (window[0]: the poses now; window[t]: after t steps; every step valid) for
  // agents heading for `goals`, until the deadline or after `rounds` rounds.
  WindowLnsStats improve(std::vector<Poses>& window, const Config& goals, const Deadline& deadline, std::mt19937& rng,
                         int64_t rounds = std::numeric_limits<int64_t>::max());

  // Plans `agents` again by space-time A* through the others' cells in `window` (valid among the
  // others), in the order given; false when one finds every way blocked (then named in `blocked`;
  // the window is partly planned).
  bool replan(std::vector<Poses>& window, const Config& goals, const std::vector<int>& agents, int* blocked = nullptr);

  // The window's cost: the sum of its agents' costs, as improve counts them.
  int64_t cost(const std::vector<Poses>& window, const Config& goals);

  // Whether a round whose new paths cost the same as the old ones keeps them: the search then
  // wanders over plateaus of equal cost instead of staying on the first it reaches. Off by
  // default. Where agents are few the window's LNS finds all it can within a step, and wandering
  // gained a little (lifelong_window); where it has more to find than time, it cost.
  void keep_equal_cost(bool keep) { keep_equal_cost_ = keep; }

  // How a round picks the agents it plans again. kNearest: a late agent and those standing nearest
  // it now. kAdaptive: one of three kinds, each round, by weights that grow with the kind's recent
  // gains and shrink when it fails (adaptive LNS, as the 2023 winner picks): the nearest as above;
  // those whose paths in the window pass a crossing (a cell with more than two neighbours) or the
  // crossings nearest it; any agents at random.
  enum class Neighbourhoods { kNearest, kAdaptive };
  void neighbourhoods(Neighbourhoods kind) { neighbourhoods_ = kind; }

  // With guide paths (guide_paths.hpp): a move onto a cell off the agent's guide costs
  // `off_guide_cost` more (in the distances' cost units), so that the window's search keeps to the
  // guides PIBT was steered by rather than take the shortest way back through the jam. An agent
  // without a guide pays nothing. nullptr: off.
  void follow_guides(const GuidePaths* guides, int off_guide_cost) {
    guides_ = guides;
    off_guide_cost_ = off_guide_cost;
  }

 private:
  struct Node {
    int64_t f;
    int64_t g;
    int t;
    Vertex cell;
    int heading;
    int parent;  // index in nodes_, -1 for the start
  };
  int64_t path_cost(const std::vector<Poses>& window, int agent, Vertex goal);
  // Sizes the tables for `window`, every cell free.
  void clear_reservations(const std::vector<Poses>& window);
  // Marks `agent`'s cells in `window` as `who`'s (-1: free), up to the step it first stands on `goal`.
  void reserve(const std::vector<Poses>& window, int agent, Vertex goal, int who);
  bool free_at(int t, Vertex cell) const { return occupied_[static_cast<size_t>(t) * cells_ + cell] == -1; }
  int occupant(int t, Vertex cell) const { return occupied_[static_cast<size_t>(t) * cells_ + cell]; }
  // Space-time A* for `agent` from window[0] through the reserved cells; writes its path into
  // `window`. False when every way is blocked.
  bool plan_agent(std::vector<Poses>& window, int agent, Vertex goal);
  int heuristic(Vertex goal, Vertex cell, int heading);
  // Marks the cells of `agent`'s guide the window can reach (none without guides).
  void mark_guide(int agent);
  // What a move from `from` to `to` costs beyond its guided cost: off_guide_cost_ when the marked
  // guide does not hold `to`.
  int off_guide(Vertex from, Vertex to) const {
    return to != from && guide_marked_ && guide_mark_[to] != guide_stamp_ ? off_guide_cost_ : 0;
  }
  enum Kind { kNearestKind, kCrossingKind, kRandomKind, kKinds };  // as WindowLnsStats counts them
  static constexpr size_t kMostCellsWalked = 64;
  // Visits the cells breadth first from `start` (each cell's neighbours in a random order when
  // `order` is given) while `group` is short of kNeighbourhood, up to about kMostCellsWalked cells.
  template <typename Visit>
  void walk_until_full(Vertex start, const std::vector<int>& group, std::mt19937* order, Visit visit);
  std::vector<int> nearest(const std::vector<Poses>& window, int late, std::mt19937& rng);
  std::vector<int> through_crossing(std::mt19937& rng);
  std::vector<int> random_agents(int agents, std::mt19937& rng);
  // Adds to `group` the agents whose reserved cells include `cell` at some step, up to kNeighbourhood.
  void add_agents_through(Vertex cell, std::vector<int>& group);
  Kind pick_kind(std::mt19937& rng);
  // A round of `kind` over `agents` agents cut the cost by `gain` (0 or less: it failed).
  void weigh(Kind kind, int64_t gain, size_t agents);

  const Graph& graph_;
  GuidedDistances& distances_;
  ActionModel actions_;
  bool keep_equal_cost_ = false;
  Neighbourhoods neighbourhoods_ = Neighbourhoods::kNearest;
  std::vector<Vertex> crossings_;   // cells with more than two neighbours
  std::array<double, kKinds> kind_weights_{1.0, 1.0, 1.0};  // reset every improve
  size_t cells_;
  int steps_ = 0;
  std::vector<int> occupied_;      // (t, cell) -> agent there at step t, or -1
  std::vector<uint32_t> seen_;     // (t, cell, heading) -> search stamp when reached
  std::vector<int64_t> best_g_;    // (t, cell, heading) -> cheapest cost reached with, this search
  uint32_t stamp_ = 0;
  std::vector<Node> nodes_;
  const GuidePaths* guides_ = nullptr;
  int off_guide_cost_ = 0;
  std::vector<uint32_t> guide_mark_;  // cell -> guide_stamp_ when on the marked guide
  uint32_t guide_stamp_ = 0;
  bool guide_marked_ = false;         // the agent marked last has a guide
};

}  // namespace planner_core
