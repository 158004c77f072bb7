// Window LNS (planner_core/window_lns.hpp): whatever it changes, every step of the window stays
// valid among the agents yet to reach their goals (the first step for all), the window starts
// where the agents stand, and the window's cost never grows; an agent left waiting is sent on its
// cheapest way; one that has reached its goal holds no cell after; the lifelong run with it steps
// validly.
#include <gtest/gtest.h>

#include <numeric>

#include "planner_core/lifelong.hpp"
#include "planner_core/lorr_problem.hpp"
#include "planner_core/window_lns.hpp"

namespace planner_core {
namespace {

const std::string kRandom = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2023/random.domain/";

// Every agent waits where it stands for `steps` steps.
std::vector<Poses> waiting_window(const Poses& now, int steps) { return std::vector<Poses>(steps + 1, now); }

// What is wrong with step t of `window` among the agents that have not stood on their goals
// before it ("" when nothing); an agent arriving at step t still counts.
std::string fault_among_travellers(const Graph& graph, ActionModel model, const std::vector<Poses>& window,
                                   const Config& goals, size_t t) {
  Poses before, after;
  for (size_t a = 0; a < goals.size(); ++a) {
    bool arrived = false;
    for (size_t s = 1; s < t; ++s) arrived = arrived || window[s].cells[a] == goals[a];
    if (arrived) continue;
    before.cells.push_back(window[t - 1].cells[a]);
    after.cells.push_back(window[t].cells[a]);
    if (model == ActionModel::kRotate) {
      before.headings.push_back(window[t - 1].headings[a]);
      after.headings.push_back(window[t].headings[a]);
    }
  }
  return find_pose_fault(graph, model, before, after).what;
}

TEST(WindowLns, FourHundredAgentsKeepEveryStepValidAndTheCostNeverGrows) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_400.json");
  const Graph& graph = *problem.graph;
  Config goals(problem.starts.size());
  for (size_t a = 0; a < goals.size(); ++a) goals[a] = problem.tasks[a][0];
  for (ActionModel model : {ActionModel::kMove4, ActionModel::kRotate}) {
    for (Guidance guidance : {Guidance::kNone, Guidance::kLanes, Guidance::kRing}) {
      GuidedDistances distances(graph, guidance, model);
      WindowLns lns(graph, distances, model);
      Poses now{problem.starts, {}};
      if (model == ActionModel::kRotate) now.headings.assign(now.cells.size(), 0);
      std::vector<Poses> window = waiting_window(now, 8);
      std::mt19937 rng(4);
      const WindowLnsStats stats = lns.improve(window, goals, Deadline::in_seconds(0.3), rng);
      EXPECT_GT(stats.improvements, 0);
      EXPECT_LT(stats.cost_after, stats.cost_before);
      EXPECT_EQ(window.front(), now);
      ASSERT_EQ(find_pose_fault(graph, model, window[0], window[1]).what, "")
          << to_string(model) << ", " << to_string(guidance) << ", the first step";
      for (size_t t = 2; t < window.size(); ++t) {
        ASSERT_EQ(fault_among_travellers(graph, model, window, goals, t), "")
            << to_string(model) << ", " << to_string(guidance) << ", step " << t;
      }
      // The figure it reports is the window's cost as it stands: a second pass starts from it.
      const WindowLnsStats again = lns.improve(window, goals, Deadline::in_seconds(0.05), rng);
      EXPECT_EQ(again.cost_before, stats.cost_after);
      EXPECT_LE(again.cost_after, again.cost_before);
    }
  }
}

TEST(WindowLns, AnAgentLeftWaitingIsSentOnItsCheapestWay) {
  const Graph graph(5, 1, {"....."});
  for (const Guidance guidance : {Guidance::kNone, Guidance::kRing}) {  // the ring: every cell on the edge
    for (const int stay_cost : {1, 3}) {  // turns cost what a wait costs (guided_distances.hpp)
      for (const auto& [heading, arrival] : {std::pair{0, 4}, std::pair{2, 6}}) {  // facing the goal, or away
        GuidedDistances distances(graph, guidance, ActionModel::kRotate, stay_cost);
        const int unit = guidance == Guidance::kRing ? GuidedDistances::kRingUnit : 1;
        const int discount = guidance == Guidance::kRing ? GuidedDistances::ring_discount_at(0) : 0;
        const int wait = stay_cost * unit - discount, move = unit - discount;  // row 0 runs east
        WindowLns lns(graph, distances, ActionModel::kRotate);
        std::vector<Poses> window = waiting_window({{0}, {heading}}, 8);
        std::mt19937 rng(1);
        const WindowLnsStats stats = lns.improve(window, {4}, Deadline::in_seconds(0.2), rng);
        EXPECT_EQ(stats.cost_before, 8 * wait + distances.get(4, 0, heading)) << "waiting, facing " << heading;
        EXPECT_EQ(stats.cost_after, 4 * move + (arrival - 4) * wait) << "facing " << heading << ", " << to_string(guidance);
        EXPECT_EQ(window[arrival].cells[0], 4);
        EXPECT_NE(window[arrival - 1].cells[0], 4);
        EXPECT_EQ(window.back().cells[0], 4);  // and waits there
      }
    }
  }
}

// In a corridor, agent 0 reaches its goal in the middle at the first step; agent 1, behind it,
// heads for the far end. Were agent 0 to hold its goal for the rest of the window, agent 1 could
// not pass it; its next errand takes it on, so agent 1 plans straight through.
TEST(WindowLns, AnAgentThatHasReachedItsGoalHoldsNoCellAfter) {
  const Graph graph(5, 1, {"....."});
  for (ActionModel model : {ActionModel::kMove4, ActionModel::kRotate}) {
    for (uint32_t seed = 0; seed < 10; ++seed) {
      GuidedDistances distances(graph, Guidance::kNone, model);
      WindowLns lns(graph, distances, model);
      Poses now{{1, 0}, {}};
      if (model == ActionModel::kRotate) now.headings = {0, 0};  // both facing east, along the corridor
      std::vector<Poses> window = waiting_window(now, 8);
      const Config goals{2, 4};
      std::mt19937 rng(seed);
      const WindowLnsStats stats = lns.improve(window, goals, Deadline::in_seconds(0.2), rng);
      EXPECT_EQ(stats.cost_after, 1 + 4) << to_string(model) << ", seed " << seed;
      EXPECT_EQ(window[1].cells, (Config{2, 1})) << to_string(model) << ", seed " << seed;
      EXPECT_EQ(window[4].cells[1], 4) << to_string(model) << ", seed " << seed;
      EXPECT_EQ(find_pose_fault(graph, model, window[0], window[1]).what, "");
      for (size_t t = 2; t < window.size(); ++t) EXPECT_EQ(fault_among_travellers(graph, model, window, goals, t), "");
    }
  }
}

TEST(WindowLns, TheLifelongRunWithItStepsValidly) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_100.json");
  for (ActionModel model : {ActionModel::kMove4, ActionModel::kRotate}) {
    LifelongSettings settings{.steps = 30, .step_time_s = 0.2};
    settings.actions = model;
    PibtLifelong planner(*problem.graph, 2,
                         {.guidance = Guidance::kLanes, .actions = model, .rollouts = 4, .rollout_steps = 8, .lns = true});
    const LifelongResult result = run_lifelong(problem, planner, settings);
    EXPECT_EQ(result.invalid_steps, 0) << result.first_invalid;
    EXPECT_GT(result.errands_finished, 0);
    EXPECT_GT(planner.lns_totals().iterations, 0);
  }
}

}  // namespace
}  // namespace planner_core
