// Window LNS (planner_core/window_lns.hpp): whatever it changes, every step of the window stays
// valid among the agents yet to reach their goals (the first step for all), the window starts
// where the agents stand, and the window's cost never grows, whichever neighbourhoods it picks; an
// agent left waiting is sent on its cheapest way, also on a map without crossings; one that has reached its goal holds no cell after; agents planned again keep out
// of the others' way; the lifelong run with it steps validly, also carrying its window on from
// step to step, but only from where the agents stand; with its work counted, a run is the same
// whatever the clock.
#include <gtest/gtest.h>

#include <cstdlib>
#include <numeric>
#include <random>

#include "planner_core/lifelong.hpp"
#include "planner_core/lifelong_auto_rules.hpp"
#include "planner_core/pibt_lifelong.hpp"
#include "planner_core/lorr_problem.hpp"
#include "planner_core/window_lns.hpp"
#include "tiny_lorr_problem.hpp"

namespace planner_core {
namespace {

const std::string kRandom = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2023/random.domain/";

constexpr WindowLns::Neighbourhoods kBothNeighbourhoods[] = {WindowLns::Neighbourhoods::kNearest,
                                                             WindowLns::Neighbourhoods::kAdaptive};

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
      for (WindowLns::Neighbourhoods kind : kBothNeighbourhoods) {
        SCOPED_TRACE(kind == WindowLns::Neighbourhoods::kNearest ? "nearest" : "adaptive neighbourhoods");
        GuidedDistances distances(graph, guidance, model);
        WindowLns lns(graph, distances, model);
        lns.neighbourhoods(kind);
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
}

TEST(WindowLns, AnAgentLeftWaitingIsSentOnItsCheapestWay) {
  const Graph graph(5, 1, {"....."});
  for (const Guidance guidance : {Guidance::kNone, Guidance::kRing}) {  // the ring: every cell on the edge
    for (const int stay_cost : {1, 3}) {  // turns cost what a wait costs (guided_distances.hpp)
      for (const auto& [heading, arrival] : {std::pair{0, 4}, std::pair{2, 6}}) {  // facing the goal, or away
        // Adaptive neighbourhoods too, on a map without crossings (the crossing kind finds no one).
        for (WindowLns::Neighbourhoods kind : kBothNeighbourhoods) {
          GuidedDistances distances(graph, guidance, ActionModel::kRotate, stay_cost);
          const int unit = guidance == Guidance::kRing ? GuidedDistances::kRingUnit : 1;
          const int discount = guidance == Guidance::kRing ? GuidedDistances::ring_discount_at(0) : 0;
          const int wait = stay_cost * unit - discount, move = unit - discount;  // row 0 runs east
          WindowLns lns(graph, distances, ActionModel::kRotate);
          lns.neighbourhoods(kind);
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
}

// On two lanes, agent 1's guide path takes the lower lane, out of the way of agent 0's, which
// comes the other way on the upper one. Agent 0 stands on agent 1's goal all window long (5 steps).
// Without guides agent 1 takes the upper lane (4 moves, a wait and 1 left: 6, against 5 moves and
// 2 left below); with guides followed a move off the guide costs a move more (10 above), and it
// takes the lower.
TEST(WindowLns, WithGuidesFollowedAnAgentKeepsToItsGuide) {
  const Graph graph(6, 2, {"......", "......"});
  const auto at = [&](int x, int y) { return graph.vertex_at({x, y}); };
  const Config goals{at(0, 0), at(5, 0)};
  GuidePaths guides(graph, {.on = true, .crowd_weight = 0});
  const GuidePaths::Heuristic manhattan = [&](Vertex goal, Vertex cell) {
    return std::abs(graph.cell_of(goal).x - graph.cell_of(cell).x) + std::abs(graph.cell_of(goal).y - graph.cell_of(cell).y);
  };
  guides.update({at(5, 0), at(0, 0)}, goals, manhattan, Deadline::in_seconds(10));
  ASSERT_EQ(guides.next(1, at(0, 0)), at(0, 1)) << "the guide takes the lower lane";
  for (const bool followed : {false, true}) {
    GuidedDistances distances(graph, Guidance::kNone, ActionModel::kMove4);
    WindowLns lns(graph, distances, ActionModel::kMove4);
    if (followed) lns.follow_guides(&guides, 1);
    std::vector<Poses> window = waiting_window({{at(5, 0), at(0, 0)}, {}}, 5);
    ASSERT_TRUE(lns.replan(window, goals, {1}));
    EXPECT_EQ(window[1].cells[1], followed ? at(0, 1) : at(1, 0)) << (followed ? "guides followed" : "no guides");
    EXPECT_EQ(lns.cost(window, goals), 10 + (followed ? 7 : 6)) << "agent 0: 5 waits and 5 moves left";
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

// A corridor's window where agent 1 drives east from cell 0 to cell 4 through cell 2, where agent
// 0 stood once it had arrived: it now has a new errand and is planned again.
std::vector<Poses> corridor_window_through(int agent0_at, ActionModel model) {
  std::vector<Poses> window;
  for (int t = 0; t <= 8; ++t) {
    Poses at{{agent0_at, std::min(t, 4)}, {}};
    if (model == ActionModel::kRotate) at.headings = {0, 0};  // both face east
    window.push_back(at);
  }
  return window;
}

TEST(WindowLns, AnAgentPlannedAgainKeepsOutOfTheOthersWay) {
  const Graph graph(5, 1, {"....."});
  for (ActionModel model : {ActionModel::kMove4, ActionModel::kRotate}) {
    GuidedDistances distances(graph, Guidance::kNone, model);
    WindowLns lns(graph, distances, model);
    // Ahead of agent 1 and heading the same way: it goes first and arrives at step 2.
    std::vector<Poses> window = corridor_window_through(2, model);
    const Config goals{4, 4};
    ASSERT_TRUE(lns.replan(window, goals, {0})) << to_string(model);
    EXPECT_EQ(window[1].cells, (Config{3, 1})) << to_string(model);
    EXPECT_EQ(window[2].cells, (Config{4, 2})) << to_string(model);
    EXPECT_EQ(window[4].cells[1], 4) << "agent 1's path stays as it was";
    EXPECT_EQ(find_pose_fault(graph, model, window[0], window[1]).what, "");
    for (size_t t = 2; t < window.size(); ++t) EXPECT_EQ(fault_among_travellers(graph, model, window, goals, t), "");
    EXPECT_EQ(lns.cost(window, goals), 2 + 4);
    // Its new errand behind agent 1: in a corridor it cannot get past, and it cannot wait where
    // agent 1 will drive, so no way is found.
    std::vector<Poses> blocked = corridor_window_through(2, model);
    EXPECT_FALSE(lns.replan(blocked, {0, 4}, {0})) << to_string(model);
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

TEST(WindowLns, TheLifelongRunKeepingItsWindowStepsValidly) {
  for (const std::string name : {"random_100.json", "random_400.json"}) {
    const LorrProblem problem = load_lorr_problem(kRandom + name);
    for (ActionModel model : {ActionModel::kMove4, ActionModel::kRotate}) {
      LifelongSettings settings{.steps = 30, .step_time_s = 0.3};
      settings.actions = model;
      const Guidance guidance = lifelong_guidance(*problem.graph, problem.starts.size(), true, model);
      PibtLifelong planner(*problem.graph, 2,
                           {.guidance = guidance,
                            .stay_cost = lifelong_stay_cost(guidance, true, model),
                            .actions = model,
                            .rollouts = 4,
                            .rollout_steps = 8,
                            .lns = true,
                            .keep_window = true,
                            .lns_neighbourhoods = lifelong_window(*problem.graph, problem.starts.size(), model)
                                                          .adaptive_neighbourhoods
                                                      ? WindowLns::Neighbourhoods::kAdaptive
                                                      : WindowLns::Neighbourhoods::kNearest});
      const LifelongResult result = run_lifelong(problem, planner, settings);
      EXPECT_EQ(result.invalid_steps, 0) << name << ", " << to_string(model) << ": " << result.first_invalid;
      EXPECT_GT(result.errands_finished, 0);
      EXPECT_GT(planner.windows_kept(), 0) << name << ", " << to_string(model);
      EXPECT_LE(planner.windows_kept(), planner.windows_carried_on());
    }
  }
}

// With the work counted (LNS rounds and rollouts per step), a run does not depend on the clock:
// with a step budget far too short (every step late, and taken all the same) or ample, the same
// seed gives the same steps.
TEST(WindowLns, ARunWithItsWorkCountedIsTheSameWhateverTheClock) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_100.json");
  for (ActionModel model : {ActionModel::kMove4, ActionModel::kRotate}) {
    std::vector<LifelongLog> logs;
    logs.reserve(2);  // each run writes through a pointer into it
    std::vector<LifelongResult> results;
    for (const double step_time_s : {1e-6, 5.0}) {
      LifelongSettings settings{.steps = 25, .step_time_s = step_time_s};
      settings.actions = model;
      settings.late_steps_taken = true;
      logs.emplace_back();
      settings.log = &logs.back();
      PibtLifelong planner(
          *problem.graph, 3,
          {.actions = model, .rollouts = 6, .rollout_steps = 8, .lns = true, .keep_window = true, .lns_rounds = 300});
      results.push_back(run_lifelong(problem, planner, settings));
      EXPECT_EQ(results.back().invalid_steps, 0) << results.back().first_invalid;
    }
    EXPECT_EQ(results[0].steps_over_budget, 25) << "every step late";
    EXPECT_EQ(results[1].steps_over_budget, 0);
    EXPECT_GT(results[0].errands_finished, 0);
    EXPECT_EQ(results[0].errands_per_step, results[1].errands_per_step) << to_string(model);
    EXPECT_TRUE(logs[0].actual == logs[1].actual) << to_string(model) << ": the agents' actions differ";
  }
}

// A step the run did not carry out (refused, or the robots did otherwise): the window it came
// from no longer starts where the agents stand, so the next step does not carry it on.
TEST(WindowLns, AWindowIsNotCarriedOnFromWhereTheAgentsDoNotStand) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_100.json");
  Poses now{problem.starts, Headings(problem.starts.size(), 0)};
  Config goals(problem.starts.size());
  for (size_t a = 0; a < goals.size(); ++a) goals[a] = problem.tasks[a].front();
  PibtLifelong planner(*problem.graph, 1,
                       {.actions = ActionModel::kRotate, .rollouts = 2, .rollout_steps = 8, .lns = true, .keep_window = true});
  planner.prepare(now, goals, Deadline::in_seconds(10));
  const Poses next = planner.next_step(now, goals, Deadline::in_seconds(0.2));
  ASSERT_NE(next.cells, now.cells);
  const Poses again = planner.next_step(now, goals, Deadline::in_seconds(0.2));  // as if `next` were not taken
  EXPECT_EQ(planner.windows_carried_on(), 0);
  planner.next_step(again, goals, Deadline::in_seconds(0.2));
  EXPECT_EQ(planner.windows_carried_on(), 1);
}

// An errand may follow one at the same cell (a task naming it twice, or the next task there): the
// agent then stands on its goal with the same errand, one step more. The kept window held its cell
// only until it arrived, so the others' kept paths may drive through it; it is planned again with
// the agents given a new errand, or the first step would put two agents on one cell.
TEST(WindowLns, AnAgentWhoseNextErrandIsWhereItStandsIsPlannedAgainInTheKeptWindow) {
  const std::vector<std::string> rows(6, std::string(10, '.'));
  std::vector<std::string> agents{"16"};
  for (int a = 0; a < 16; ++a) agents.push_back(std::to_string(a * 3 + (a / 4) % 2));
  std::vector<std::string> tasks{"200"};
  std::mt19937 draw(7);
  for (int k = 0; k < 200; ++k) {
    const std::string cell = std::to_string(std::uniform_int_distribution<int>(0, 59)(draw));
    tasks.push_back(cell + "," + cell);
  }
  TinyProblem tiny(rows, agents, tasks);
  const LorrProblem problem = load_lorr_problem(tiny.path());
  for (ActionModel model : {ActionModel::kMove4, ActionModel::kRotate}) {
    for (WindowLns::Neighbourhoods kind : kBothNeighbourhoods) {
      for (uint32_t seed : {1u, 2u, 3u}) {
        SCOPED_TRACE(kind == WindowLns::Neighbourhoods::kNearest ? "nearest" : "adaptive neighbourhoods");
        LifelongSettings settings{.steps = 60, .step_time_s = 1.0};
        settings.actions = model;
        settings.late_steps_taken = true;
        PibtLifelong planner(*problem.graph, seed,
                             {.actions = model,
                              .rollouts = 4,
                              .rollout_steps = 8,
                              .lns = true,
                              .keep_window = true,
                              .lns_neighbourhoods = kind,
                              .lns_rounds = 100});
        const LifelongResult result = run_lifelong(problem, planner, settings);
        EXPECT_EQ(result.invalid_steps, 0) << to_string(model) << ", seed " << seed << ": " << result.first_invalid;
        EXPECT_GT(result.errands_finished, 20) << to_string(model) << ", seed " << seed;
        EXPECT_GT(planner.windows_carried_on(), 0) << to_string(model) << ", seed " << seed;
      }
    }
  }
}

}  // namespace
}  // namespace planner_core
