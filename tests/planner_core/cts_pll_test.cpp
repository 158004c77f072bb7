#include <gtest/gtest.h>

#include <atomic>

#include "planner_core/joint_sequencer.hpp"
#include "planner_core/lns.hpp"
#include "planner_core/lock_release.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/safe_interval_planning.hpp"
#include "planner_core/validator.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

SolveResult solve_with(const Instance& instance, const std::string& solver, double seconds, int max_sequences = 0,
                       bool complete_fallback = true, bool swap = true) {
  SolverConfig config;
  config.solver = solver;
  config.pibt.swap = swap;
  config.max_sequences = max_sequences;
  config.complete_fallback = complete_fallback;
  return make_solver(config)->solve(instance, {Deadline::in_seconds(seconds), {}});
}

// Plain Extended-PIBT (the paper's, without the swap operation, which untangles some of these
// cases by itself) must fail and CTS-PLL-v1 must produce a valid plan.
void expect_lock_released(const Instance& instance) {
  const SolveResult baseline = solve_with(instance, "cts-pibt", 10, 0, /*complete_fallback=*/false, /*swap=*/false);
  EXPECT_FALSE(baseline.solved) << "this case no longer locks Extended-PIBT";
  const SolveResult pll = solve_with(instance, "cts-pll-v1", 10, 0, /*complete_fallback=*/false, /*swap=*/false);
  ASSERT_TRUE(pll.solved) << pll.failure_reason;
  const ValidationReport report = validate(instance, pll.solution);
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_GE(pll.lock_releases + pll.prioritized_completions, 1);
}

TEST(LockRelease, PaperFig2aAgentCannotYieldFromItsGoal) {
  // Agent 1 rests on its goal at the corridor end, which is agent 0's task; it can only make
  // room through the pocket at (1,0).
  expect_lock_released(testing::make_instance({"@.@@@", "....."}, {{{4, 1}, {3, 1}}, {{0, 1}, {0, 1}}},
                                              {{{0, 1}, {0}}}));
}

TEST(LockRelease, PaperFig2bAgentsParkedOnEachOthersGoals) {
  expect_lock_released(testing::make_instance({"@@@@.@@@@", "........."}, {{{3, 1}, {5, 1}}, {{5, 1}, {3, 1}}},
                                              {{{7, 1}, {0}}}));
}

TEST(LockRelease, GoalsInADeadEndFilledInTheWrongOrder) {
  // Agent 1 settles in the middle of the dead end before agent 0, whose goal is at the bottom.
  expect_lock_released(testing::make_instance({".....", ".....", ".....", "@@.@@", "@@.@@", "@@.@@"},
                                              {{{0, 0}, {2, 5}}, {{4, 2}, {2, 4}}}, {{{4, 0}, {0}}}));
}

// The complete search as a lock release: from where the stalled run stood at the lock time, every
// agent searched over augmented configurations; the plan keeps the run's prefix and is valid.
void expect_completed_from_the_lock(const Instance& instance) {
  DistTable dist(*instance.graph);
  JointSequencer sequencer(instance, dist, TaskOrderConfig{});
  const std::optional<JointSequence> sequence = sequencer.next();
  ASSERT_TRUE(sequence);
  std::mt19937 rng(1);
  PibtConfig config;
  config.swap = false;
  config.stall_window = 20;
  ExtendedPibt pibt(instance, dist, config, rng);
  pibt.reset(*sequence);
  ASSERT_NE(pibt.run(Deadline::in_seconds(10)), ExtendedPibt::Outcome::kSolved) << "this case no longer locks";
  const LockSet lock = detect_lock(pibt, dist);
  const std::optional<Solution> plan =
      complete_by_search(pibt, *sequence, lock, dist, rng, /*forbid_rotations=*/false, Deadline::in_seconds(10));
  ASSERT_TRUE(plan);
  const ValidationReport report = validate(instance, *plan);
  EXPECT_TRUE(report.ok()) << report.summary();
  for (int t = 0; t <= lock.lock_time; ++t) EXPECT_EQ((*plan)[t], pibt.plan()[t]) << "t=" << t;
}

TEST(LockRelease, TheCompleteSearchFromTheLockFinishesWhatThePaperFiguresLock) {
  expect_completed_from_the_lock(
      testing::make_instance({"@.@@@", "....."}, {{{4, 1}, {3, 1}}, {{0, 1}, {0, 1}}}, {{{0, 1}, {0}}}));
  expect_completed_from_the_lock(
      testing::make_instance({"@@@@.@@@@", "........."}, {{{3, 1}, {5, 1}}, {{5, 1}, {3, 1}}}, {{{7, 1}, {0}}}));
  expect_completed_from_the_lock(testing::make_instance({".....", ".....", ".....", "@@.@@", "@@.@@", "@@.@@"},
                                                        {{{0, 0}, {2, 5}}, {{4, 2}, {2, 4}}}, {{{4, 0}, {0}}}));
}

TEST(CtsPll, SolvesWhatThePibtBaselineCannotOnDenseInstances) {
  // maze N=50 M=180 #05: Extended-PIBT locks in the dead-end corridor at x=31 on the best sequence.
  const Instance instance = load_instance(testing::data_path("instances/maze-32-32-2-N50-M180-05.yaml"));
  EXPECT_FALSE(solve_with(instance, "cts-pibt", 10, 0, /*complete_fallback=*/false, /*swap=*/false).solved);
  const SolveResult pll = solve_with(instance, "cts-pll-v1", 60, 0, /*complete_fallback=*/false, /*swap=*/false);
  ASSERT_TRUE(pll.solved) << pll.failure_reason;
  EXPECT_TRUE(validate(instance, pll.solution).ok());
}

TEST(CtsPll, V3RefinesBelowTheFirstPlan) {
  const Instance instance = load_instance(testing::data_path("instances/maze-32-32-2-N50-M60-00.yaml"));
  const SolveResult result = solve_with(instance, "cts-pll-v3", 3, 3);
  ASSERT_TRUE(result.solved);
  const ValidationReport report = validate(instance, result.solution);
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(report.flowtime, result.flowtime);
  ASSERT_GE(result.improvements.size(), 2u) << "LNS found no improvement at all";
  EXPECT_LT(result.improvements.back().flowtime, result.improvements.front().flowtime);
  EXPECT_GT(result.lns_iterations, 0);
}

TEST(CtsPll, V2StopsAtTheFirstFeasiblePlan) {
  const Instance instance = load_instance(testing::data_path("instances/random-32-32-20-N10-M30-00.yaml"));
  const SolveResult result = solve_with(instance, "cts-pll-v2", 30);
  ASSERT_TRUE(result.solved);
  EXPECT_EQ(result.improvements.size(), 1u);
  EXPECT_TRUE(validate(instance, result.solution).ok());
}

TEST(CtsPll, InterruptStopsTheAnytimeLoop) {
  const Instance instance = load_instance(testing::data_path("instances/maze-32-32-2-N50-M60-00.yaml"));
  std::atomic<bool> interrupt{false};
  SolverConfig config;
  config.solver = "cts-pll-v3";
  SolveOptions options{Deadline::in_seconds(600, &interrupt), [&](const SolveResult&) { interrupt = true; }};
  const SolveResult result = make_solver(config)->solve(instance, options);
  ASSERT_TRUE(result.solved);
  EXPECT_LT(result.comp_time_ms, 60000);
}

TEST(CtsPll, WithoutAStallLimitV3RefinesUntilItsDeadline) {
  // Ten agents: the LNS runs out of gains fast, and by default stops after 300 repairs without one.
  // With no stall limit (the fleet's planner.lns_stall_iterations: 0) it uses the whole budget.
  const Instance instance = load_instance(testing::data_path("instances/random-32-32-20-N10-M30-00.yaml"));
  SolverConfig config;
  config.solver = "cts-pll-v3";
  config.lns.stall_iterations = 0;
  const SolveResult result = make_solver(config)->solve(instance, {Deadline::in_seconds(1), {}});
  ASSERT_TRUE(result.solved);
  EXPECT_GE(result.comp_time_ms, 990);
  EXPECT_GT(result.lns_iterations, 300);
  EXPECT_TRUE(validate(instance, result.solution).ok());
}

// SolveOptions::refine_share: refinement ends at that share of the budget, the first plan does
// not. With a share that ends before any plan can be found, v3 still finds its first plan, then
// stops without refining it; with the whole budget it refines.
TEST(CtsPll, RefineShareEndsTheRefinementButNotTheSearchForAFirstPlan) {
  const Instance instance = load_instance(testing::data_path("instances/maze-32-32-2-N50-M60-00.yaml"));
  SolverConfig config;
  config.solver = "cts-pll-v3";
  SolveOptions options{Deadline::in_seconds(60).with_work_budget(Deadline::work_of(1.0))};
  options.refine_share = 1e-9;
  const SolveResult cut = make_solver(config)->solve(instance, options);
  ASSERT_TRUE(cut.solved) << cut.failure_reason;
  EXPECT_EQ(cut.lns_iterations, 0);
  EXPECT_EQ(cut.sequences_tried, 1);
  EXPECT_TRUE(validate(instance, cut.solution).ok());
  options.refine_share = 1.0;
  const SolveResult whole = make_solver(config)->solve(instance, options);
  ASSERT_TRUE(whole.solved);
  EXPECT_GT(whole.lns_iterations, 0);
  EXPECT_LT(whole.flowtime, cut.flowtime);
}

TEST(CtsPll, ForbiddenRotationsNeverAppear) {
  for (const char* file : {"instances/random-32-32-20-N10-M30-00.yaml", "instances/maze-32-32-2-N50-M60-00.yaml",
                           "instances/empty-32-32-N05-M50-00.yaml"}) {
    const Instance instance = load_instance(testing::data_path(file));
    for (const char* solver : {"cts-pibt", "cts-pll-v1", "cts-pll-v3"}) {
      SolverConfig config;
      config.solver = solver;
      config.forbid_rotations = true;
      config.max_sequences = 2;
      const SolveResult result = make_solver(config)->solve(instance, {Deadline::in_seconds(2), {}});
      if (!result.solved) continue;  // cts-pibt may fail; the others are checked for success elsewhere
      const ValidationReport report = validate(instance, result.solution, {true});
      EXPECT_TRUE(report.ok()) << file << " " << solver << "\n" << report.summary();
    }
  }
}

TEST(Lns, RefinedPlanStaysValid) {
  const Instance instance = load_instance(testing::data_path("instances/random-32-32-20-N10-M30-00.yaml"));
  const SolveResult first = solve_with(instance, "cts-pibt", 10);
  ASSERT_TRUE(first.solved);
  std::mt19937 rng(5);
  DistTable dist(*instance.graph);
  LnsRefiner lns(instance, dist, LnsConfig{}, rng);
  Solution plan = first.solution;
  int64_t reported = first.flowtime;
  const LnsStats stats = lns.refine(plan, first.orders, Deadline::in_seconds(1), [&](int64_t f) { reported = f; });
  const ValidationReport report = validate(instance, plan);
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_LE(report.flowtime, first.flowtime);
  EXPECT_EQ(report.flowtime, reported);
  EXPECT_GT(stats.iterations, 0);
}

TEST(PathTable, AddingEveryPathAtOnceEqualsAddingThemOneByOne) {
  // A real plan: agents pass and wait on shared cells, so cells see several visits.
  const Instance instance = load_instance(testing::data_path("instances/random-32-32-20-N10-M30-00.yaml"));
  const SolveResult solved = solve_with(instance, "cts-pibt", 10);
  ASSERT_TRUE(solved.solved);
  const std::vector<int> arrival = arrival_times(solved.solution, instance.goals);
  std::vector<Path> paths(instance.agent_count());
  for (int a = 0; a < instance.agent_count(); ++a) {
    for (int t = 0; t <= arrival[a]; ++t) paths[a].push_back(solved.solution[t][a]);
  }
  PathTable one_by_one(instance.graph->vertex_count()), at_once(instance.graph->vertex_count());
  for (int a = 0; a < instance.agent_count(); ++a) one_by_one.add(a, paths[a]);
  at_once.add_all(paths);
  std::vector<PathTable::Interval> expected, got;
  const int horizon = static_cast<int>(solved.solution.size()) + 3;
  for (Vertex v = 0; v < instance.graph->vertex_count(); ++v) {
    EXPECT_EQ(at_once.last_visit(v), one_by_one.last_visit(v)) << "vertex " << v;
    for (int t = 0; t < horizon; ++t) ASSERT_EQ(at_once.occupant(v, t), one_by_one.occupant(v, t)) << v << " t=" << t;
    one_by_one.safe_intervals(v, expected);
    at_once.safe_intervals(v, got);
    ASSERT_EQ(got.size(), expected.size()) << "vertex " << v;
    for (size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].first, expected[k].first);
      EXPECT_EQ(got[k].last, expected[k].last);
      // The agents recorded next to an interval are those the table has there.
      EXPECT_EQ(got[k].occupant_before, got[k].first == 0 ? PathTable::kFree : at_once.occupant(v, got[k].first - 1))
          << "vertex " << v;
      EXPECT_EQ(got[k].occupant_after,
                got[k].last == PathTable::kForever ? PathTable::kFree : at_once.occupant(v, got[k].last + 1))
          << "vertex " << v;
      EXPECT_EQ(got[k].occupant_before, expected[k].occupant_before);
      EXPECT_EQ(got[k].occupant_after, expected[k].occupant_after);
    }
  }
  // And a path removed again leaves both the same.
  one_by_one.remove(3, paths[3]);
  at_once.remove(3, paths[3]);
  for (Vertex v = 0; v < instance.graph->vertex_count(); ++v) {
    for (int t = 0; t < horizon; ++t) ASSERT_EQ(at_once.occupant(v, t), one_by_one.occupant(v, t)) << v << " t=" << t;
  }
}

TEST(PathTable, VisitorsFromListTheLatestVisitorsFirst) {
  const Instance instance = testing::make_instance({"....."}, {{{0, 0}, {4, 0}}});
  const auto v = [&](int x) { return instance.graph->vertex_at({x, 0}); };
  PathTable table(instance.graph->vertex_count());
  table.add(0, {v(0), v(1), v(2)});              // rests on (2,0) from t=2
  table.add(1, {v(3), v(2), v(1), v(0)});         // on (2,0) at t=1
  table.add(2, {v(4), v(4), v(3), v(3), v(3), v(3), v(4)}, false);  // on (3,0) at t=2..5
  table.add(3, {v(3), v(4)}, false);                                  // on (3,0) at t=0
  std::vector<int> out;
  table.visitors_from(v(3), 1, PathTable::kFree, 5, out);
  EXPECT_EQ(out, (std::vector<int>{2}));  // agent 3 was there before t=1
  out.clear();
  table.visitors_from(v(3), 0, PathTable::kFree, 5, out);
  EXPECT_EQ(out, (std::vector<int>{2, 3}));  // the latest first, each agent once
  out.clear();
  table.visitors_from(v(3), 0, 2, 5, out);
  EXPECT_EQ(out, (std::vector<int>{3}));  // but not the one excepted
  out = {7};
  table.visitors_from(v(3), 0, PathTable::kFree, 1, out);
  EXPECT_EQ(out, (std::vector<int>{7, 2}));  // `count` more than `out` held
  out.clear();
  table.visitors_from(v(2), 0, 0, 5, out);
  EXPECT_EQ(out, (std::vector<int>{1}));  // the agent resting there is excepted
}

TEST(Lns, AnAgentWaitingForOthersToPassItsGoalArrivesEarly) {
  // Two lanes. Agent 0's goal (2,0) is 2 steps away, but in the given plan it waits at its start
  // while agent 1 walks along the top lane through (2,0): it arrives at t=6. Agent 1 can as well take
  // the bottom lane, and agent 0 then arrives at t=2: flowtime 8 instead of 12.
  const Instance instance = testing::make_instance({"......", "......"}, {{{0, 0}, {2, 0}}, {{5, 0}, {0, 1}}});
  const auto v = [&](int x, int y) { return instance.graph->vertex_at({x, y}); };
  const std::vector<Path> paths = {
      {v(0, 0), v(0, 0), v(0, 0), v(0, 0), v(0, 0), v(1, 0), v(2, 0)},
      {v(5, 0), v(4, 0), v(3, 0), v(2, 0), v(1, 0), v(1, 1), v(0, 1)}};
  Solution plan(7, Config(2));
  for (int t = 0; t < 7; ++t) plan[t] = {paths[0][t], paths[1][t]};
  ASSERT_TRUE(validate(instance, plan).ok());
  ASSERT_EQ(validate(instance, plan).flowtime, 12);
  std::mt19937 rng(1);
  DistTable dist(*instance.graph);
  LnsRefiner lns(instance, dist, LnsConfig{}, rng);
  lns.refine(plan, {{}, {}}, Deadline::in_seconds(2));
  const ValidationReport report = validate(instance, plan);
  ASSERT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(report.flowtime, 8);
}

TEST(SafeIntervalPlanning, WaitsForAPasserBeforeRestingOnItsGoal) {
  // Agent 1 passes through (2,0), agent 0's goal, at t=4; agent 0 may only settle after that.
  const Instance instance = testing::make_instance({".....", "....."}, {{{0, 0}, {2, 0}}});
  DistTable dist(*instance.graph);
  PathTable table(instance.graph->vertex_count());
  const auto v = [&](int x, int y) { return instance.graph->vertex_at({x, y}); };
  table.add(1, {v(4, 1), v(4, 0), v(3, 0), v(3, 1), v(2, 1), v(2, 0), v(1, 0), v(1, 1)});
  const Path path = plan_through_targets(*instance.graph, dist, table, v(0, 0), {v(2, 0)}, SpaceTimeLimits{});
  ASSERT_FALSE(path.empty());
  EXPECT_EQ(path.back(), v(2, 0));
  EXPECT_EQ(static_cast<int>(path.size()) - 1, 6);  // the passer is on (2,0) at t=5: arrive at t=6, not 2
  for (int t = 0; t < static_cast<int>(path.size()); ++t) {
    EXPECT_EQ(table.occupant(path[t], t), PathTable::kFree) << "t=" << t;
    if (t > 0) {
      const int other = table.occupant(path[t], t - 1);
      EXPECT_FALSE(other != PathTable::kFree && table.occupant(path[t - 1], t) == other) << "swap at t=" << t;
    }
  }
}

TEST(SafeIntervalPlanning, RotationFreePlansStillFollowAgentsAhead) {
  // Agent 1 walks right along a corridor just ahead of us; rotation-free plans may follow it step
  // by step (robots executing the plan in dependency order do), so we arrive as early as without.
  const Instance instance = testing::make_instance({"....."}, {{{0, 0}, {2, 0}}});
  DistTable dist(*instance.graph);
  PathTable table(instance.graph->vertex_count());
  const auto v = [&](int x) { return instance.graph->vertex_at({x, 0}); };
  table.add(1, {v(1), v(2), v(3), v(4)});
  SpaceTimeLimits limits;
  limits.forbid_rotations = true;
  const Path path = plan_through_targets(*instance.graph, dist, table, v(0), {v(2)}, limits);
  ASSERT_EQ(path.size(), 3u);  // (0,0) -> (1,0) at t=1 -> (2,0) at t=2, each cell left that very step
  EXPECT_EQ(path[1], v(1));
}

TEST(SafeIntervalPlanning, RotationFreePlansNeverCloseACycle) {
  // A 2x2 ring with three agents moving clockwise in one step (a -> b -> c -> d) and resting; we
  // start on d, which the third agent enters at t=1, and must get to a. Moving d -> a at t=1
  // closes the cycle a -> b -> c -> d -> a: allowed only when rotations are.
  const Instance instance = testing::make_instance({"..", ".."}, {{{0, 1}, {0, 0}}});
  DistTable dist(*instance.graph);
  const auto at = [&](int x, int y) { return instance.graph->vertex_at({x, y}); };
  const Vertex a = at(0, 0), b = at(1, 0), c = at(1, 1), d = at(0, 1);
  PathTable table(instance.graph->vertex_count());
  table.add(1, {a, b});
  table.add(2, {b, c});
  table.add(3, {c, d});
  const Path free_to_rotate = plan_through_targets(*instance.graph, dist, table, d, {a}, SpaceTimeLimits{});
  ASSERT_EQ(free_to_rotate.size(), 2u);
  EXPECT_EQ(free_to_rotate[1], a);
  SpaceTimeLimits limits;
  limits.forbid_rotations = true;
  EXPECT_TRUE(plan_through_targets(*instance.graph, dist, table, d, {a}, limits).empty())
      << "the only way out of d is the move that closes the rotation";
}

TEST(SafeIntervalPlanning, VisitsTargetsInOrder) {
  const Instance instance = testing::make_instance({"....."}, {{{2, 0}, {2, 0}}});
  DistTable dist(*instance.graph);
  PathTable table(instance.graph->vertex_count());
  const auto v = [&](int x) { return instance.graph->vertex_at({x, 0}); };
  const Path path = plan_through_targets(*instance.graph, dist, table, v(2), {v(4), v(0), v(2)}, SpaceTimeLimits{});
  EXPECT_EQ(path.size(), 2u + 4u + 2u + 1u);
  EXPECT_EQ(path[2], v(4));
  EXPECT_EQ(path[6], v(0));
}

}  // namespace
}  // namespace planner_core
