// CTS-MAPF plans in the rotation model (forward, quarter turn or wait): the validator's rules for
// headings, headings in the instance and solution files, four-way plans carried out with turns,
// the lower bound with turns, and CTS-PIBT planning with turns on the benchmark instances.
#include <gtest/gtest.h>

#include "planner_core/cts_lacam.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/lns.hpp"
#include "planner_core/safe_interval_planning.hpp"
#include "planner_core/turned_solver.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/task_order.hpp"
#include "planner_core/turning_execution.hpp"
#include "planner_core/validator.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

using Kind = Violation::Kind;
constexpr int kEast = 0, kSouth = 1, kWest = 2, kNorth = 3;

// Map (x to the right, y down):   . . . . .
//                                 . @ . . .
// Agent 0 from (0,0) to (2,0) by its task at (2,1); agent 1 from (4,0) to (3,0). Both face east.
class TurningValidatorTest : public ::testing::Test {
 protected:
  void SetUp() override { instance.actions = ActionModel::kRotate; }
  Instance instance = testing::make_instance({".....", ".@..."}, {{{0, 0}, {2, 0}}, {{4, 0}, {3, 0}}},
                                             {{{2, 1}, {0}}});
  Vertex at(int x, int y) const { return instance.graph->vertex_at({x, y}); }
  // Agent 0: forward, forward, turn south, forward, turn and turn north, forward.
  // Agent 1: turn, turn (to face west), forward.
  Solution cells() const {
    return {{at(0, 0), at(4, 0)}, {at(1, 0), at(4, 0)}, {at(2, 0), at(4, 0)}, {at(2, 0), at(3, 0)},
            {at(2, 1), at(3, 0)}, {at(2, 1), at(3, 0)}, {at(2, 1), at(3, 0)}, {at(2, 0), at(3, 0)}};
  }
  HeadingPlan headings() const {
    return {{kEast, kEast}, {kEast, kSouth}, {kEast, kWest}, {kSouth, kWest},
            {kSouth, kWest}, {kEast, kWest}, {kNorth, kWest}, {kNorth, kWest}};
  }
};

TEST_F(TurningValidatorTest, AcceptsForwardMovesQuarterTurnsAndWaits) {
  const ValidationReport report = validate(instance, cells(), {}, headings());
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(report.flowtime, 7 + 3);
}

TEST_F(TurningValidatorTest, NamesEachBrokenRule) {
  {  // no headings at all
    const ValidationReport report = validate(instance, cells());
    EXPECT_TRUE(report.has(Kind::kHeading)) << report.summary();
  }
  {  // one timestep short of headings
    HeadingPlan short_one = headings();
    short_one.pop_back();
    EXPECT_TRUE(validate(instance, cells(), {}, short_one).has(Kind::kHeading));
  }
  {  // a heading out of range
    HeadingPlan bad = headings();
    bad[3][1] = 4;
    const ValidationReport report = validate(instance, cells(), {}, bad);
    ASSERT_TRUE(report.has(Kind::kHeading));
    EXPECT_EQ(report.violations.front().time, 3);
    EXPECT_EQ(report.violations.front().agent, 1);
  }
  {  // the wrong start heading
    instance.start_headings = {kEast, kNorth};
    const ValidationReport report = validate(instance, cells(), {}, headings());
    ASSERT_TRUE(report.has(Kind::kHeading));
    EXPECT_NE(report.summary().find("agent 1 starts facing E, not N"), std::string::npos) << report.summary();
    instance.start_headings.clear();
  }
  {  // a move sideways: agent 0 steps south at t=3 still facing east
    HeadingPlan sideways = headings();
    sideways[3][0] = kEast;
    sideways[4][0] = kEast;
    const ValidationReport report = validate(instance, cells(), {}, sideways);
    ASSERT_TRUE(report.has(Kind::kAction)) << report.summary();
    EXPECT_NE(report.summary().find("only the cell ahead can be entered"), std::string::npos) << report.summary();
  }
  {  // a half turn in one step: agent 1 from east to west at t=1
    HeadingPlan half = headings();
    half[1][1] = kWest;
    const ValidationReport report = validate(instance, cells(), {}, half);
    ASSERT_TRUE(report.has(Kind::kAction));
    EXPECT_NE(report.summary().find("turns half round"), std::string::npos) << report.summary();
  }
  {  // moving and turning in one step: agent 0 enters (2,1) already facing east
    HeadingPlan both = headings();
    both[4][0] = kEast;
    const ValidationReport report = validate(instance, cells(), {}, both);
    ASSERT_TRUE(report.has(Kind::kAction));
    EXPECT_NE(report.summary().find("moves and turns in one step"), std::string::npos) << report.summary();
  }
  {  // the four-way model ignores headings, wrong or not
    instance.actions = ActionModel::kMove4;
    EXPECT_TRUE(validate(instance, cells()).ok());
  }
}

TEST(TurningFiles, InstanceHeadingsAreReadWrittenAndCheckedByName) {
  const std::string map = testing::write_temp_file("turning.map", "type octile\nheight 2\nwidth 5\nmap\n.....\n.@...\n");
  const std::string good = testing::write_temp_file(
      "turning.yaml", "map: turning.map\nagents:\n  - {start: [0, 0], goal: [2, 0], heading: S}\n"
                      "  - {start: [4, 0], goal: [3, 0]}\ntasks: []\n");
  const Instance instance = load_instance(good);
  EXPECT_EQ(instance.start_heading(0), kSouth);
  EXPECT_EQ(instance.start_heading(1), kEast);
  const std::string again = testing::write_temp_file("turning-again.yaml", instance_to_yaml(instance, "turning.map"));
  EXPECT_EQ(load_instance(again).start_headings, instance.start_headings);
  const std::string bad = testing::write_temp_file(
      "turning-bad.yaml", "map: turning.map\nagents:\n  - {start: [0, 0], goal: [2, 0], heading: up}\n");
  try {
    load_instance(bad);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("turning-bad.yaml:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("agents[0].heading: \"up\" is no heading (E, S, W or N)"), std::string::npos)
        << e.what();
  }
}

TEST_F(TurningValidatorTest, SolutionFilesKeepHeadingsAndRefuseMixedLines) {
  SolutionFile file;
  file.solution = cells();
  file.headings = headings();
  const std::string text = format_solution(*instance.graph, file);
  EXPECT_NE(text.find("3:(2,0,S),(3,0,W),"), std::string::npos) << text;
  const SolutionFile read = read_solution(testing::write_temp_file("turning-solution.txt", text), *instance.graph);
  EXPECT_EQ(read.solution, file.solution);
  EXPECT_EQ(read.headings, file.headings);
  const auto refused = [&](const std::string& body, const std::string& expected) {
    try {
      read_solution(testing::write_temp_file("turning-bad-solution.txt", "solution=\n" + body), *instance.graph);
      ADD_FAILURE() << "no error for " << body;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  refused("0:(0,0,E),(4,0),\n", "turning-bad-solution.txt:2: some cells have a heading and some do not");
  refused("0:(0,0,E),(4,0,E),\n1:(1,0),(4,0),\n", ":3: no headings, as the lines before have");
  refused("0:(0,0,X),(4,0,E),\n", ":2: \"X\" is no heading");
}

TEST_F(TurningValidatorTest, AFourWayPlanCarriedOutWithTurnsIsValid) {
  // Agent 0's four-way plan: east, east, south, north; agent 1 west. Agent 1's turn (two steps)
  // delays nobody; agent 0 turns before each change of direction.
  const Solution four_way = {{at(0, 0), at(4, 0)}, {at(1, 0), at(3, 0)}, {at(2, 0), at(3, 0)},
                             {at(2, 1), at(3, 0)}, {at(2, 0), at(3, 0)}};
  instance.actions = ActionModel::kMove4;
  ASSERT_TRUE(validate(instance, four_way, ValidationOptions{true}).ok());
  instance.actions = ActionModel::kRotate;
  const std::optional<TurningPlan> turned = execute_with_turns(instance, four_way, false);
  ASSERT_TRUE(turned);
  const ValidationReport report = validate(instance, turned->cells, {}, turned->headings);
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(report.flowtime, 7 + 3);  // as the hand-made plan above: two turns for each
}

// SIPP over cell and heading: agent 0 of the map above, facing east, around agent 1's reserved
// path (two turns, then west). Its earliest arrival is the hand-made plan's: forward twice, a turn
// south, forward onto the task, two turns north, forward. Guided by distances with turns or by
// cells alone, the arrival is the same; the joint plan is valid with both agents' headings.
TEST_F(TurningValidatorTest, SafeIntervalsWithTurnsFindTheEarliestArrival) {
  PathTable table(instance.graph->vertex_count());
  const Path other = {at(4, 0), at(4, 0), at(4, 0), at(3, 0)};
  table.add(1, other);
  DistTable dist(*instance.graph);
  GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
  SafeIntervalPlanner planner(*instance.graph);
  for (GuidedDistances* guide : {&turning, static_cast<GuidedDistances*>(nullptr)}) {
    SCOPED_TRACE(guide ? "guided with turns" : "guided by cells");
    std::vector<int> path_headings;
    const Path path = planner.plan_with_turns(dist, guide, table, at(0, 0), kEast, {at(2, 1), at(2, 0)},
                                              SpaceTimeLimits{}, path_headings);
    ASSERT_EQ(path.size(), 8u);
    ASSERT_EQ(path_headings.size(), path.size());
    Solution cells;
    HeadingPlan headings;
    const std::vector<int> other_headings = {kEast, kSouth, kWest, kWest, kWest, kWest, kWest, kWest};
    for (size_t t = 0; t < path.size(); ++t) {
      cells.push_back({path[t], other[std::min(t, other.size() - 1)]});
      headings.push_back({path_headings[t], other_headings[t]});
    }
    const ValidationReport report = validate(instance, cells, {}, headings);
    EXPECT_TRUE(report.ok()) << report.summary();
    EXPECT_EQ(report.flowtime, 7 + 3);
  }
  // Facing west at the start costs two more turns.
  std::vector<int> path_headings;
  const Path path = planner.plan_with_turns(dist, &turning, table, at(0, 0), kWest, {at(2, 1), at(2, 0)},
                                            SpaceTimeLimits{}, path_headings);
  EXPECT_EQ(path.size(), 10u);
  EXPECT_EQ(path_headings.front(), kWest);
}

// LNS over cell and heading refines a four-way plan carried out with turns: its plan stays valid
// with headings, from the instance's start headings, and costs less than the plan it started from.
TEST(TurningLns, RefinesATurnedPlanBelowItsStart) {
  Instance instance = load_instance(testing::data_path("instances/random-32-32-20-N10-M30-00.yaml"));
  Instance four_way = instance;
  instance.actions = ActionModel::kRotate;
  instance.start_headings.assign(instance.agent_count(), kNorth);
  SolverConfig config;
  config.solver = "cts-pibt";
  const SolveResult planned = make_solver(config)->solve(four_way, SolveOptions{Deadline::in_seconds(60)});
  ASSERT_TRUE(planned.solved);
  const std::optional<TurningPlan> turned = execute_with_turns(instance, planned.solution, false);
  ASSERT_TRUE(turned);
  const int64_t turned_flowtime = validate(instance, turned->cells, {}, turned->headings).flowtime;
  Solution cells = turned->cells;
  HeadingPlan headings = turned->headings;
  DistTable dist(*instance.graph);
  GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
  std::mt19937 rng(1);
  LnsRefiner lns(instance, dist, LnsConfig{}, rng);
  const LnsStats stats = lns.refine_with_turns(cells, headings, planned.orders, &turning,
                                               Deadline::in_seconds(60).with_work_budget(Deadline::work_of(0.5)));
  EXPECT_GT(stats.accepted, 0);
  const ValidationReport report = validate(instance, cells, {}, headings);
  ASSERT_TRUE(report.ok()) << report.summary();
  EXPECT_LT(report.flowtime, turned_flowtime);
  EXPECT_EQ(headings.front(), Headings(instance.agent_count(), kNorth));
}

TEST(TurningExecution, KeepsTheOrderOfPassageThroughACell) {
  // A corridor: agent 0 at (1,0) facing west must turn round before it can lead the way east; in
  // the four-way plan agent 1 follows it at once. Carried out with turns, agent 1 waits.
  Instance instance = testing::make_instance({"....."}, {{{1, 0}, {4, 0}}, {{0, 0}, {3, 0}}});
  const auto at = [&](int x) { return instance.graph->vertex_at({x, 0}); };
  instance.start_headings = {kWest, kEast};
  instance.actions = ActionModel::kRotate;
  const Solution four_way = {{at(1), at(0)}, {at(2), at(1)}, {at(3), at(2)}, {at(4), at(3)}};
  const std::optional<TurningPlan> turned = execute_with_turns(instance, four_way, false);
  ASSERT_TRUE(turned);
  const ValidationReport report = validate(instance, turned->cells, {}, turned->headings);
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(turned->cells[1][1], at(0)) << "agent 1 must wait while agent 0 turns";
  EXPECT_EQ(arrival_times(turned->cells, instance.goals), (std::vector<int>{5, 5}));
}

TEST(TurningExecution, AgentsInACycleMoveTogetherOrThePlanIsRefused) {
  // Four agents going round a 2x2 block in one step wait on each other: together, or for ever
  // when cycles are not allowed.
  Instance instance = testing::make_instance({"..", ".."}, {{{0, 0}, {1, 0}}, {{1, 0}, {1, 1}},
                                                            {{1, 1}, {0, 1}}, {{0, 1}, {0, 0}}});
  instance.actions = ActionModel::kRotate;
  instance.start_headings = {kEast, kSouth, kWest, kNorth};
  const Solution cycle = {instance.starts, instance.goals};
  EXPECT_FALSE(execute_with_turns(instance, cycle, false));
  const std::optional<TurningPlan> together = execute_with_turns(instance, cycle, true);
  ASSERT_TRUE(together);
  EXPECT_EQ(together->cells, cycle);
  EXPECT_TRUE(validate(instance, together->cells, {}, together->headings).ok());
  // Agent 3 facing away first: it turns twice while the others wait, then all four move.
  instance.start_headings = {kEast, kSouth, kWest, kSouth};
  const std::optional<TurningPlan> later = execute_with_turns(instance, cycle, true);
  ASSERT_TRUE(later);
  EXPECT_EQ(later->cells.size(), 4u);
  EXPECT_TRUE(validate(instance, later->cells, {}, later->headings).ok());
}

TEST(TurningLowerBound, CountsTheTurnsEveryTourNeeds) {
  // From (0,0) facing west to the goal (2,0) by a task at (2,1): a half turn (2), two moves, a
  // turn south, a move, a half turn... any heading at the task: (2,1) -> (2,0) is a turn or two and
  // a move. The bound takes the best heading at the task: 2 + 2 + 1 + 1 + 1 = 7 at least.
  Instance instance = testing::make_instance({".....", ".@..."}, {{{0, 0}, {2, 0}}}, {{{2, 1}, {0}}});
  instance.actions = ActionModel::kRotate;
  instance.start_headings = {kWest};
  DistTable dist(*instance.graph);
  GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
  EXPECT_EQ(tour_lower_bound(instance, dist, TaskOrderConfig{}), 4);
  EXPECT_EQ(tour_lower_bound(instance, turning, TaskOrderConfig{}), 7);
}

TEST(TurningLowerBound, WithNoTimeLeftTheFourWayBoundStands) {
  Instance instance = load_instance(testing::data_path("instances/random-32-32-20-N10-M30-00.yaml"));
  instance.actions = ActionModel::kRotate;
  GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
  EXPECT_EQ(turning_lower_bound(instance, turning, TaskOrderConfig{}, 1234, Deadline::in_seconds(0)), 1234);
  const int64_t with_turns = turning_lower_bound(instance, turning, TaskOrderConfig{}, 1234, Deadline::in_seconds(60));
  DistTable dist(*instance.graph);
  EXPECT_GT(with_turns, tour_lower_bound(instance, dist, TaskOrderConfig{}));
}

// A solver falling back on turned four-way plans hands over the tables with turns it searched:
// the TurnedSolver reports their bound, the same one it finds on its own, and plans validly.
TEST(TurningLowerBound, ATurnedSolverHandedTheTablesKeepsTheirBound) {
  Instance instance = load_instance(testing::data_path("instances/random-32-32-20-N10-M30-00.yaml"));
  instance.actions = ActionModel::kRotate;
  GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
  const int64_t bound = turning_lower_bound(instance, turning, TaskOrderConfig{}, 0, Deadline::in_seconds(60));
  DistTable dist(*instance.graph);
  ASSERT_GT(bound, tour_lower_bound(instance, dist, TaskOrderConfig{}));
  SolverConfig config;
  config.solver = "cts-lacam";
  for (const bool handed : {false, true}) {
    TurnedSolver solver(std::make_unique<CtsLacam>(config), config);
    if (handed) solver.use_turning_tables(turning, bound);
    const SolveResult result =
        solver.solve(instance, SolveOptions{Deadline::in_seconds(60).with_work_budget(Deadline::work_of(0.3))});
    ASSERT_TRUE(result.solved) << result.failure_reason;
    EXPECT_EQ(result.lower_bound, bound) << (handed ? "handed" : "its own");
    EXPECT_TRUE(validate(instance, result.solution, {}, result.headings).ok());
  }
}

// Plans for robots (--no-rotations) in the rotation model: no agents moving round a cycle in one
// step, whichever way the plan was made; and the same seed gives the same plan.
TEST(TurningSolvers, PlansForRobotsHaveNoCyclesAndRepeatWithTheSeed) {
  Instance with_tasks = load_instance(testing::data_path("instances/maze-32-32-2-N50-M60-00.yaml"));
  with_tasks.actions = ActionModel::kRotate;
  // LaCAM and LaCAM* plan plain MAPF: an instance without tasks.
  Instance plain = load_instance(std::string(CTSFLEET_BENCHMARKS_DIR) + "/mapf/maze-32-32-2-N50-0.yaml");
  plain.actions = ActionModel::kRotate;
  for (const std::string solver : {"cts-pibt", "cts-pibt-anytime", "cts-pll-v3", "cts-lacam", "lacam", "lacam-star"}) {
    const bool lacam = solver.rfind("lacam", 0) == 0;
    const Instance& instance = lacam ? plain : with_tasks;
    for (const std::string turns : {"planned", "added", "both"}) {
      if (turns == "both" && !plans_with_turns(solver)) continue;
      SolverConfig config;
      config.solver = solver;
      config.forbid_rotations = true;
      config.max_sequences = 2;
      config.plan_with_turns = turns != "added";
      config.add_turns = turns != "planned";
      const auto solve = [&] {
        return make_solver(config)->solve(instance, SolveOptions{Deadline::in_seconds(60).with_work_budget(Deadline::work_of(0.3))});
      };
      const SolveResult first = solve();
      ASSERT_TRUE(first.solved) << solver << " " << turns << ": " << first.failure_reason;
      const ValidationReport report = validate(instance, first.solution, ValidationOptions{true}, first.headings);
      EXPECT_TRUE(report.ok()) << solver << " " << turns << ": " << report.summary();
      const SolveResult second = solve();
      EXPECT_EQ(second.solution, first.solution) << solver << " " << turns;
      EXPECT_EQ(second.headings, first.headings) << solver << " " << turns;
    }
  }
}

// CTS-PIBT in the rotation model on benchmark instances: solved, valid with headings, no lower
// than the bound; the four-way model's plans unchanged by the option's existence.
TEST(TurningCtsPibt, SolvesBenchmarkInstancesWithValidTurningPlans) {
  for (const char* name : {"empty-32-32-N05-M50-00.yaml", "random-32-32-20-N10-M30-00.yaml",
                           "maze-32-32-2-N50-M60-00.yaml"}) {
    Instance instance = load_instance(testing::data_path(std::string("instances/") + name));
    instance.actions = ActionModel::kRotate;
    for (const std::string solver : {"cts-pibt", "cts-pibt-anytime"}) {
      SolverConfig config;
      config.solver = solver;
      config.max_sequences = 3;
      const SolveResult result = make_solver(config)->solve(instance, SolveOptions{Deadline::in_seconds(60)});
      ASSERT_TRUE(result.solved) << name << " " << solver << ": " << result.failure_reason;
      const ValidationReport report = validate(instance, result.solution, {}, result.headings);
      EXPECT_TRUE(report.ok()) << name << ": " << report.summary();
      EXPECT_GE(result.flowtime, result.lower_bound) << name;
      Instance four_way = instance;
      four_way.actions = ActionModel::kMove4;
      DistTable dist(*instance.graph);
      EXPECT_GT(result.lower_bound, tour_lower_bound(four_way, dist, TaskOrderConfig{})) << name << ": turns count";
    }
  }
}

// The other solvers plan four-way moves and get turns added: valid plans in the rotation model,
// and no cheaper than what CTS-PIBT's bound allows. LaCAM and LaCAM* plan plain MAPF (no tasks).
TEST(TurningSolvers, EverySolverPlansInTheRotationModel) {
  Instance with_tasks = load_instance(testing::data_path("instances/random-32-32-20-N10-M30-00.yaml"));
  with_tasks.actions = ActionModel::kRotate;
  with_tasks.start_headings.assign(with_tasks.agent_count(), kNorth);
  Instance without_tasks = with_tasks;
  without_tasks.tasks.clear();
  without_tasks.index_tasks();
  for (const std::string& solver : solver_names()) {
    const Instance& instance = solver.rfind("lacam", 0) == 0 ? without_tasks : with_tasks;
    SolverConfig config;
    config.solver = solver;
    config.max_sequences = 3;
    const SolveResult result = make_solver(config)->solve(instance, SolveOptions{Deadline::in_seconds(1)});
    ASSERT_TRUE(result.solved) << solver << ": " << result.failure_reason;
    const ValidationReport report = validate(instance, result.solution, {}, result.headings);
    EXPECT_TRUE(report.ok()) << solver << ": " << report.summary();
    EXPECT_EQ(result.flowtime, report.flowtime) << solver;
    EXPECT_GE(result.flowtime, result.lower_bound) << solver;
    EXPECT_GT(result.first_solution_ms, 0) << solver;
  }
  // In the four-way model the same solvers give plans with no headings, as before.
  with_tasks.actions = ActionModel::kMove4;
  SolverConfig config;
  config.solver = "cts-pll-v3";
  const SolveResult four_way = make_solver(config)->solve(with_tasks, SolveOptions{Deadline::in_seconds(1)});
  ASSERT_TRUE(four_way.solved);
  EXPECT_TRUE(four_way.headings.empty());
  EXPECT_TRUE(validate(with_tasks, four_way.solution).ok());
}

// LaCAM in the rotation model plans with turns (a search over cell and heading) and adds turns to
// its four-way plan, and keeps the cheaper: with a one-shot search, exactly the cheaper of the two
// plans it makes alone.
TEST(TurningSolvers, LacamKeepsTheCheaperOfItsPlanWithTurnsAndItsTurnedPlan) {
  for (const char* name : {"den520d-N500-0.yaml", "random-32-32-20-N200-0.yaml"}) {
    Instance instance = load_instance(std::string(CTSFLEET_BENCHMARKS_DIR) + "/mapf/" + name);
    instance.actions = ActionModel::kRotate;
    const auto solve = [&](bool planned, bool added) {
      SolverConfig config;
      config.solver = "lacam";
      config.plan_with_turns = planned;
      config.add_turns = added;
      const SolveResult result = make_solver(config)->solve(instance, SolveOptions{Deadline::in_seconds(60)});
      EXPECT_TRUE(result.solved) << name << ": " << result.failure_reason;
      EXPECT_TRUE(validate(instance, result.solution, {}, result.headings).ok()) << name;
      return result.flowtime;
    };
    const int64_t with_turns = solve(true, false);
    const int64_t turned = solve(false, true);
    EXPECT_NE(with_turns, turned) << name;  // two different plans
    EXPECT_EQ(solve(true, true), std::min(with_turns, turned)) << name;
  }
}

// Where the search over cell and heading finds no plan (one-cell warehouse aisles, 300 agents: none
// in 10 s, docs/RESULTS.md),
// LaCAM and LaCAM* still plan, by turns added to their four-way plans; and LaCAM* keeps refining.
TEST(TurningSolvers, LacamPlansWhereTheSearchWithTurnsFindsNoPlan) {
  Instance instance =
      load_instance(std::string(CTSFLEET_BENCHMARKS_DIR) + "/mapf/warehouse-10-20-10-2-1-N300-0.yaml");
  instance.actions = ActionModel::kRotate;
  SolverConfig config;
  for (const std::string solver : {"lacam", "lacam-star"}) {
    config.solver = solver;
    const SolveResult result = make_solver(config)->solve(instance, SolveOptions{Deadline::in_seconds(4)});
    ASSERT_TRUE(result.solved) << solver << ": " << result.failure_reason;
    const ValidationReport report = validate(instance, result.solution, {}, result.headings);
    EXPECT_TRUE(report.ok()) << solver << ": " << report.summary();
    EXPECT_GT(result.flowtime, result.lower_bound) << solver;
    if (solver == "lacam-star") {
      EXPECT_LT(result.flowtime, result.improvements.front().flowtime) << "refined";
    }
  }
}

}  // namespace
}  // namespace planner_core
