// League of Robot Runners problems read as the league writes them, and the lifelong run: every
// step valid, the errands counted as the rules say, the same seed the same run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "planner_core/input_error.hpp"
#include "planner_core/lifelong.hpp"
#include "planner_core/lifelong_auto_rules.hpp"
#include "planner_core/pibt_lifelong.hpp"
#include "planner_core/lorr_problem.hpp"
#include "tiny_lorr_problem.hpp"

namespace planner_core {
namespace {

namespace fs = std::filesystem;

const std::string kRandom = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2023/random.domain/";

TEST(LorrProblem, TheLeaguesExampleReadsWhole) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_20.json");
  EXPECT_EQ(problem.graph->width(), 32);
  EXPECT_EQ(problem.graph->height(), 32);
  EXPECT_EQ(problem.starts.size(), 20u);
  EXPECT_EQ(problem.tasks.size(), 2000u);
  EXPECT_EQ(problem.assignment, TaskAssignment::kRoundRobin);
  // The first agent: location 134 = row 4, column 6.
  EXPECT_EQ(problem.graph->cell_of(problem.starts[0]), (Cell{6, 4}));
}

TEST(LorrProblem, TasksMayHaveSeveralErrandsAndTheMapTheLeaguesSymbols) {
  TinyProblem tiny({"E...S", ".@@@.", "....."}, {"2", "0", "4"}, {"2", "2,10,14", "12"},
                   "\"numTasksReveal\": 1.5");
  const LorrProblem problem = load_lorr_problem(tiny.path());
  ASSERT_EQ(problem.tasks.size(), 2u);
  ASSERT_EQ(problem.tasks[0].size(), 3u);
  EXPECT_EQ(problem.graph->cell_of(problem.tasks[0][1]), (Cell{0, 2}));
  EXPECT_EQ(problem.tasks_revealed_per_agent, 1.5);
}

TEST(LorrProblem, EveryFaultNamesItsFileAndLine) {
  TinyProblem tiny({".....", ".@@@.", "....."}, {"2", "0", "4"}, {"2", "2", "12"});
  EXPECT_EQ(lorr_error_of(tiny.path()), "");
  tiny.write("tiny.agents", {"2", "0", "6"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("tiny.agents:3: location 6 (row 1, column 1) is a wall"), std::string::npos)
      << lorr_error_of(tiny.path());
  tiny.write("tiny.agents", {"2", "0", "15"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("tiny.agents:3: location 15 is off the 5x3 map"), std::string::npos);
  tiny.write("tiny.agents", {"2", "0", "0"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("tiny.agents:3: a second agent on location 0"), std::string::npos);
  tiny.write("tiny.agents", {"3", "0", "4"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("the first line says 3 but 2 lines follow"), std::string::npos);
  tiny.write("tiny.agents", {"1", "0"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("1 agents, but \"teamSize\" is 2"), std::string::npos);
  tiny.write("tiny.agents", {"2", "0", "four"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("tiny.agents:3: expected integers, found 'four'"), std::string::npos);
  tiny.write("tiny.agents", {"2", "0", "4"});
  tiny.write("tiny.tasks", {"0"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("tiny.tasks: no task"), std::string::npos);
  tiny.write("tiny.tasks", {"1", "7"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("tiny.tasks:2: location 7"), std::string::npos);
  tiny.write("tiny.tasks", {"1", "2"});
  tiny.write("tiny.map", {"type octile", "height 1", "width 3", "map", ".X."});
  EXPECT_NE(lorr_error_of(tiny.path()).find("unknown map symbol 'X'"), std::string::npos);
  tiny.write("tiny.map", {"type octile", "height 3", "width 5", "map", ".....", ".@@@.", "....."});
  tiny.write("tiny.json", {"{\"mapFile\": \"tiny.map\", \"agentFile\": \"tiny.agents\", \"taskFile\": \"tiny.tasks\"}"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("\"teamSize\" missing"), std::string::npos);
  tiny.write("tiny.json", {"{\"mapFile\": \"nowhere.map\""});
  EXPECT_NE(lorr_error_of(tiny.path()).find("tiny.json: not JSON"), std::string::npos);
  tiny.write("tiny.json", {"{\"mapFile\": \"nowhere.map\", \"teamSize\": 2}"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("nowhere.map"), std::string::npos);
  tiny.write("tiny.json", {"[1, 2]"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("not a JSON object"), std::string::npos);
}

// A map cut in two: an agent or an errand on the far side could never be reached.
TEST(LorrProblem, AStartOrErrandCutOffFromTheFloorIsNamed) {
  // Column 2 is a wall from top to bottom: cells 0-1 and 5-6 on the left, 3-4 and 8-9 on the right.
  TinyProblem tiny({"..@..", "..@.."}, {"2", "0", "5"}, {"2", "1", "6"});
  EXPECT_EQ(lorr_error_of(tiny.path()), "");
  tiny.write("tiny.tasks", {"2", "1", "8"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("tiny.tasks:3: location 8 (row 1, column 3) cannot be reached from the first "
                                       "agent's start"),
            std::string::npos)
      << lorr_error_of(tiny.path());
  tiny.write("tiny.tasks", {"1", "0,4"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("tiny.tasks:2: location 4"), std::string::npos) << lorr_error_of(tiny.path());
  tiny.write("tiny.tasks", {"1", "1"});
  tiny.write("tiny.agents", {"2", "0", "9"});
  EXPECT_NE(lorr_error_of(tiny.path()).find("tiny.agents:3: location 9 (row 1, column 4) cannot be reached"),
            std::string::npos)
      << lorr_error_of(tiny.path());
}

TEST(LorrProblem, BadSettingsAreNamed) {
  TinyProblem greedy({"....."}, {"1", "0"}, {"1", "4"}, "\"taskAssignmentStrategy\": \"greedy\"");
  EXPECT_EQ(load_lorr_problem(greedy.path()).assignment, TaskAssignment::kGreedy);
  TinyProblem unknown({"....."}, {"1", "0"}, {"1", "4"}, "\"taskAssignmentStrategy\": \"nearest\"");
  EXPECT_NE(lorr_error_of(unknown.path()).find("\"taskAssignmentStrategy\" must be"), std::string::npos);
  TinyProblem reveal({"....."}, {"1", "0"}, {"1", "4"}, "\"numTasksReveal\": 0");
  EXPECT_NE(lorr_error_of(reveal.path()).find("\"numTasksReveal\" must be a number in [1, 1000]"), std::string::npos);
}

TEST(LifelongStep, JumpsSharedCellsAndSwapsAreInvalid) {
  const Graph graph(4, 1, {"...."});
  const Config at{0, 1};
  EXPECT_EQ(invalid_step(graph, at, {1, 2}), "");  // a train moving on
  EXPECT_NE(invalid_step(graph, at, {2, 1}).find("jumps"), std::string::npos);
  EXPECT_NE(invalid_step(graph, at, {1, 1}).find("both on"), std::string::npos);
  EXPECT_NE(invalid_step(graph, at, {1, 0}).find("swap"), std::string::npos);
  EXPECT_NE(invalid_step(graph, at, {0}).find("a step for 1 agents"), std::string::npos);
}

TEST(LifelongStep, AgentsMovingInACycleAreFound) {
  // A 2 x 2 square: 0 1 / 2 3.
  const Config square{0, 1, 3, 2};  // agents around it clockwise
  EXPECT_NE(find_rotation(square, {1, 3, 2, 0}).what.find("move in a cycle of 4"), std::string::npos);
  EXPECT_EQ(find_rotation(square, {1, 3, 2, 2}).what, "");  // the last one stays: a train, blocked (no cycle)
  EXPECT_EQ(find_rotation({0, 1}, {1, 2}).what, "");          // a train moving on
  // The first agent outside the cycle, a train leading nowhere near it.
  EXPECT_NE(find_rotation({8, 0, 1, 3, 2}, {9, 1, 3, 2, 0}).what.find("agents 1, 2, ... move in a cycle of 4"),
            std::string::npos);
}

// A planner that counts the steps of the one it wraps in which agents move in a cycle.
class RotationCounter : public LifelongPlanner {
 public:
  explicit RotationCounter(LifelongPlanner& planner) : planner_(planner) {}
  Poses next_step(const Poses& now, const Config& goals, const Deadline& deadline) override {
    Poses next = planner_.next_step(now, goals, deadline);
    if (!find_rotation(now.cells, next.cells).what.empty()) ++rotations;
    return next;
  }
  int rotations = 0;

 private:
  LifelongPlanner& planner_;
};

TEST(Lifelong, WithoutRotationsNoStepMovesAgentsInACycle) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_800.json");
  PibtLifelong free_to_rotate(*problem.graph, 5), no_rotations(*problem.graph, 5, {.forbid_rotations = true});
  RotationCounter free_counter(free_to_rotate), no_counter(no_rotations);
  const LifelongResult free_run = run_lifelong(problem, free_counter, {150, 5.0});
  const LifelongResult no_run = run_lifelong(problem, no_counter, {150, 5.0});
  EXPECT_GT(free_counter.rotations, 0);  // this crowd rotates when it may: the check below can fail
  EXPECT_EQ(no_counter.rotations, 0);
  EXPECT_EQ(no_run.invalid_steps, 0) << no_run.first_invalid;
  EXPECT_GT(no_run.errands_finished, free_run.errands_finished / 2);
}

TEST(Lifelong, ErrandsAreCountedAsTheRulesSay) {
  // One agent on a corridor; tasks at 4, 0, 4 (then the file starts over: 4, 0, ...).
  TinyProblem tiny({"....."}, {"1", "0"}, {"3", "4", "0", "4"});
  const LorrProblem problem = load_lorr_problem(tiny.path());
  PibtLifelong planner(*problem.graph, 1);
  const LifelongResult result = run_lifelong(problem, planner, {16, 1.0});
  // At 4 after step 4, at 0 after 8, at 4 after 12; the next task is at 4 too: one errand per
  // step, so it is finished after step 13, where the agent waited; then 0 is 4 steps away.
  EXPECT_EQ(result.errands_finished, 4);
  EXPECT_EQ(result.tasks_finished, 4);
  EXPECT_EQ(result.errands_per_step[11], 1);
  EXPECT_EQ(result.errands_per_step[12], 1);
  EXPECT_EQ(result.moves, 15);
}

TEST(Lifelong, ATaskOfSeveralErrandsIsDoneWhenTheLastIs) {
  TinyProblem tiny({"....."}, {"1", "0"}, {"1", "2,4,3"});
  const LorrProblem problem = load_lorr_problem(tiny.path());
  PibtLifelong planner(*problem.graph, 1);
  const LifelongResult result = run_lifelong(problem, planner, {5, 1.0});
  EXPECT_EQ(result.errands_finished, 3);  // 2 after step 2, 4 after 4, 3 after 5
  EXPECT_EQ(result.tasks_finished, 1);
}

TEST(Lifelong, EightHundredAgentsStepValidlyAndTheSameSeedRunsTheSame) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_800.json");
  PibtLifelong first(*problem.graph, 7), second(*problem.graph, 7);
  const LifelongResult a = run_lifelong(problem, first, {200, 5.0});
  const LifelongResult b = run_lifelong(problem, second, {200, 5.0});
  EXPECT_EQ(a.invalid_steps, 0) << a.first_invalid;
  EXPECT_EQ(a.steps_over_budget, 0);
  EXPECT_GT(a.errands_finished, 200);
  EXPECT_EQ(a.errands_finished, b.errands_finished);
  EXPECT_EQ(a.errands_per_step, b.errands_per_step);
}

TEST(Lifelong, GreedyAssignmentRunsAndFinishesErrands) {
  LorrProblem problem = load_lorr_problem(kRandom + "random_100.json");
  problem.assignment = TaskAssignment::kGreedy;
  PibtLifelong planner(*problem.graph, 3);
  const LifelongResult greedy = run_lifelong(problem, planner, {300, 5.0});
  EXPECT_EQ(greedy.invalid_steps, 0) << greedy.first_invalid;
  EXPECT_GT(greedy.errands_finished, 300);
}

// Plain PIBT locks here when the agent that wants the dead end outranks the one inside it: both
// priorities grow alike, so it would for ever. Every seed must keep finishing errands.
TEST(Lifelong, AnAgentInADeadEndIsLetOutWhateverTheSeed) {
  // (0,0) is a dead end; agent 0 stands in it and must go to (4,1); agent 1 stands at its mouth
  // and must go into it. Tasks alternate between the two agents (round robin).
  TinyProblem tiny({".@...", "....."}, {"2", "0", "5"}, {"4", "9", "0", "3", "0"});
  const LorrProblem problem = load_lorr_problem(tiny.path());
  for (Guidance guidance : {Guidance::kNone, Guidance::kLanes}) {
    for (uint32_t seed = 0; seed < 20; ++seed) {
      PibtLifelong planner(*problem.graph, seed, {.guidance = guidance});
      const LifelongResult result = run_lifelong(problem, planner, {200, 1.0});
      EXPECT_EQ(result.invalid_steps, 0) << result.first_invalid;
      EXPECT_GE(result.errands_finished, 20) << "seed " << seed << ", guidance " << to_string(guidance);
    }
  }
}

// An agent stands still a while before it is drawn ahead of the others: 8 steps while free cells
// are at least as many as agents, 8 n / (V - n) for n agents on V free cells beyond.
TEST(Lifelong, AgentsWaitLongerBeforeTheyAreDrawnAheadTheFewerCellsAreFree) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_20.json");
  const Graph& graph = *problem.graph;
  ASSERT_EQ(graph.vertex_count(), 819);
  EXPECT_EQ(stuck_steps_for(graph, 0), 8);
  EXPECT_EQ(stuck_steps_for(graph, 400), 8);
  EXPECT_EQ(stuck_steps_for(graph, 410), 8);
  EXPECT_EQ(stuck_steps_for(graph, 600), 21);
  EXPECT_EQ(stuck_steps_for(graph, 800), 336);
  EXPECT_EQ(stuck_steps_for(graph, 819), 8 * 819);     // no cell free
  EXPECT_EQ(stuck_steps_for(graph, 2000), 8 * 2000);   // more agents than cells: as if one were free
  EXPECT_EQ(stuck_steps_for(graph, 10'000'000), 1'000'000);
  // Dead-end errands are parked when agents fill more than 90% of the free cells.
  EXPECT_FALSE(lifelong_parks_dead_ends(graph, 600));
  EXPECT_FALSE(lifelong_parks_dead_ends(graph, 737));
  EXPECT_TRUE(lifelong_parks_dead_ends(graph, 738));
  EXPECT_TRUE(lifelong_parks_dead_ends(graph, 800));
  // And there plans are held always, elsewhere in half the rollouts.
  EXPECT_EQ(lifelong_plan_holding(graph, 737), PlanHolding::kInHalfTheRollouts);
  EXPECT_EQ(lifelong_plan_holding(graph, 738), PlanHolding::kAlways);
  // Where plans are held always, rollouts without LNS look further ahead than one held plan; in
  // four moves nothing is held.
  EXPECT_EQ(lifelong_rollout_steps(graph, 737, ActionModel::kRotate), kRolloutSteps);
  EXPECT_EQ(lifelong_rollout_steps(graph, 738, ActionModel::kRotate), kRolloutStepsWhereHeld);
  EXPECT_EQ(lifelong_rollout_steps(graph, 800, ActionModel::kMove4), kRolloutSteps);
}

// An agent whose errand is a dead end (a cell with one neighbour) is parked: it stays where it
// stands and gives that errand up; unparked it goes there.
TEST(Lifelong, AnAgentWhoseErrandIsADeadEndIsParked) {
  // (1,0) = 1 is a dead end above the corridor (0,1)..(4,1) = 5..9; the agent stands at 8.
  TinyProblem tiny({"@.@@@", "....."}, {"1", "8"}, {"1", "1"});
  const LorrProblem problem = load_lorr_problem(tiny.path());
  for (ActionModel actions : {ActionModel::kMove4, ActionModel::kRotate}) {
    LifelongSettings settings{.steps = 20, .step_time_s = 1.0};
    settings.actions = actions;
    PibtLifelong free_to_go(*problem.graph, 1, {.actions = actions});
    EXPECT_GT(run_lifelong(problem, free_to_go, settings).errands_finished, 0);
    EXPECT_EQ(free_to_go.parked_agents(), 0);
    PibtLifelong parking(*problem.graph, 1, {.actions = actions, .park_dead_end_errands = true});
    const LifelongResult parked = run_lifelong(problem, parking, settings);
    EXPECT_EQ(parked.invalid_steps, 0) << parked.first_invalid;
    EXPECT_EQ(parked.errands_finished, 0);
    EXPECT_EQ(parked.moves, 0);
    EXPECT_EQ(parking.parked_agents(), 1);
  }
}

// Two parked agents fill a spur off a loop, the outer one in its dead end; a third agent's errand
// is the inner one's cell, which it cannot leave but through that agent. Once that one has been
// stuck, the inner parked agent is let go for its own errand and they get past each other,
// whatever the seed. Without it they would lock for ever, finishing nothing.
TEST(Lifelong, AParkedAgentInTheWayOfAnErrandIsLetGo) {
  // A loop of rows 0 and 2 through columns 0 and 5; the spur 14 -> 20 -> 26 (a dead end) below
  // it, and the dead end 23 off 17. Agents 0 and 1 stand at 26 and 20 with errands at 23 (both
  // parked); agent 2 stands at 0 with its errand at 20.
  TinyProblem tiny({"......", ".@@@@.", "......", "@@.@@.", "@@.@@@"}, {"3", "26", "20", "0"},
                   {"6", "23", "23", "20", "23", "23", "0"});
  const LorrProblem problem = load_lorr_problem(tiny.path());
  for (ActionModel actions : {ActionModel::kMove4, ActionModel::kRotate}) {
    LifelongSettings settings{.steps = 200, .step_time_s = 1.0};
    settings.actions = actions;
    for (uint32_t seed = 0; seed < 10; ++seed) {
      PibtLifelong planner(*problem.graph, seed,
                           {.actions = actions, .hold_plans = PlanHolding::kAlways, .park_dead_end_errands = true});
      const LifelongResult result = run_lifelong(problem, planner, settings);
      EXPECT_EQ(result.invalid_steps, 0) << result.first_invalid;
      EXPECT_GE(result.errands_finished, 2) << "seed " << seed << ", " << to_string(actions);
    }
  }
}

// On a map nearly full of agents, parking and the longer wait before an agent is drawn ahead
// keep every step valid, and the same seed runs the same.
TEST(RotationLifelong, EightHundredAgentsParkedAndHeldStepValidlyAndTheSameSeedRunsTheSame) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_800.json");
  const PibtLifelongSettings crowded{.guidance = Guidance::kLanes,
                                     .actions = ActionModel::kRotate,
                                     .rollouts = 8,
                                     .hold_plans = PlanHolding::kAlways,
                                     .park_dead_end_errands = true};
  PibtLifelong first(*problem.graph, 4, crowded), second(*problem.graph, 4, crowded);
  LifelongSettings settings{.steps = 150, .step_time_s = 60};
  settings.actions = ActionModel::kRotate;
  const LifelongResult a = run_lifelong(problem, first, settings);
  const LifelongResult b = run_lifelong(problem, second, settings);
  EXPECT_EQ(a.invalid_steps, 0) << a.first_invalid;
  EXPECT_GT(a.errands_finished, 150);
  EXPECT_GT(first.parked_agents(), 0);
  EXPECT_EQ(a.errands_per_step, b.errands_per_step);
}

TEST(Lifelong, AnInterruptEndsTheRunAtOnce) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_20.json");
  PibtLifelong planner(*problem.graph, 1);
  std::atomic<bool> interrupt{true};
  LifelongSettings settings;
  settings.steps = 1'000'000;
  settings.interrupt = &interrupt;
  const LifelongResult result = run_lifelong(problem, planner, settings);
  EXPECT_TRUE(result.interrupted);
  EXPECT_TRUE(result.step_ms.empty());
}

// A planner that breaks the rules is overruled: everyone waits, and the fault is named.
class JumpingPlanner : public LifelongPlanner {
 public:
  Poses next_step(const Poses& now, const Config&, const Deadline&) override {
    Poses next = now;
    next.cells[0] = now.cells[1];
    return next;
  }
};

TEST(Lifelong, AnInvalidStepIsReplacedByWaiting) {
  TinyProblem tiny({"....."}, {"2", "0", "4"}, {"1", "2"});
  const LorrProblem problem = load_lorr_problem(tiny.path());
  JumpingPlanner planner;
  const LifelongResult result = run_lifelong(problem, planner, {3, 1.0});
  EXPECT_EQ(result.invalid_steps, 3);
  EXPECT_EQ(result.moves, 0);
  EXPECT_NE(result.first_invalid.find("step 0: agent 0 jumps"), std::string::npos) << result.first_invalid;
}

TEST(Lifelong, WithLanesEightHundredAgentsStepValidlyAndTheSameSeedRunsTheSame) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_800.json");
  PibtLifelong first(*problem.graph, 9, {.guidance = Guidance::kLanes}),
      second(*problem.graph, 9, {.guidance = Guidance::kLanes});
  LifelongSettings settings;
  settings.steps = 200;
  settings.step_time_s = 5;
  const LifelongResult a = run_lifelong(problem, first, settings);
  const LifelongResult b = run_lifelong(problem, second, settings);
  EXPECT_EQ(a.invalid_steps, 0) << a.first_invalid;
  EXPECT_GT(a.errands_finished, 200);
  EXPECT_EQ(a.errands_per_step, b.errands_per_step);
}

// "auto" window for window LNS in the rotation model: 16 steps while agents number at most a
// quarter of the free cells (random-32-32-20 has 819), else 8, kept from step to step, except
// for more agents than LNS reaches in a step; in four moves 8 planned afresh. Paths of equal cost
// are kept with the 16-step window only; neighbourhoods are adaptive wherever the window is kept.
TEST(Lifelong, AutoWindowIsLongWhileTurningAgentsAreFewAndKeptUnlessTooMany) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_100.json");
  const Graph& graph = *problem.graph;
  ASSERT_EQ(graph.vertex_count(), 819);
  for (size_t agents : {1, 100, 204}) {
    const LifelongWindow turning = lifelong_window(graph, agents, ActionModel::kRotate);
    EXPECT_EQ(turning.steps, 16) << agents;
    EXPECT_TRUE(turning.kept) << agents;
    EXPECT_TRUE(turning.equal_cost_kept) << agents;
    EXPECT_TRUE(turning.adaptive_neighbourhoods) << agents;
    const LifelongWindow four_way = lifelong_window(graph, agents, ActionModel::kMove4);
    EXPECT_EQ(four_way.steps, 8) << agents;
    EXPECT_FALSE(four_way.kept) << agents;
    EXPECT_FALSE(four_way.equal_cost_kept) << agents;
    EXPECT_FALSE(four_way.adaptive_neighbourhoods) << agents;
  }
  for (size_t agents : {205, 400, 800}) {
    EXPECT_EQ(lifelong_window(graph, agents, ActionModel::kRotate).steps, 8) << agents;
    EXPECT_TRUE(lifelong_window(graph, agents, ActionModel::kRotate).kept) << agents;
    EXPECT_EQ(lifelong_window(graph, agents, ActionModel::kMove4).steps, 8) << agents;
    EXPECT_FALSE(lifelong_window(graph, agents, ActionModel::kMove4).kept) << agents;
    EXPECT_FALSE(lifelong_window(graph, agents, ActionModel::kRotate).equal_cost_kept) << agents;
    EXPECT_TRUE(lifelong_window(graph, agents, ActionModel::kRotate).adaptive_neighbourhoods) << agents;
    EXPECT_FALSE(lifelong_window(graph, agents, ActionModel::kMove4).adaptive_neighbourhoods) << agents;
  }
  // On a large map, few but too many for LNS to reach in a step: 8 steps planned afresh.
  const LorrProblem large = load_lorr_problem(std::string(CTSFLEET_BENCHMARKS_DIR) +
                                              "/lorr-2023/warehouse.domain/warehouse_large_8000.json");
  ASSERT_EQ(large.graph->vertex_count(), 38'586);
  EXPECT_TRUE(lifelong_window(*large.graph, kMostAgentsForLongWindows, ActionModel::kRotate).kept);
  EXPECT_EQ(lifelong_window(*large.graph, kMostAgentsForLongWindows + 1, ActionModel::kRotate).steps, 8);
  EXPECT_FALSE(lifelong_window(*large.graph, 8000, ActionModel::kRotate).kept);
  EXPECT_TRUE(lifelong_window(*large.graph, kMostAgentsForLongWindows, ActionModel::kRotate).equal_cost_kept);
  EXPECT_FALSE(lifelong_window(*large.graph, 8000, ActionModel::kRotate).equal_cost_kept);
  EXPECT_TRUE(lifelong_window(*large.graph, kMostAgentsForLongWindows, ActionModel::kRotate).adaptive_neighbourhoods);
  EXPECT_FALSE(lifelong_window(*large.graph, 8000, ActionModel::kRotate).adaptive_neighbourhoods);
}

// "auto" guidance: shortest paths only with window LNS while agents number at most a quarter of
// the free cells (random-32-32-20 has 819) and at most 2,000 of them, else lanes, with a ring road
// in the rotation model with LNS on small maps.
TEST(Lifelong, AutoGuidanceTakesShortestPathsOnlyWithLnsWhileAgentsAreFew) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_100.json");
  const Graph& graph = *problem.graph;
  ASSERT_EQ(graph.vertex_count(), 819);
  constexpr ActionModel kRotate = ActionModel::kRotate;
  constexpr ActionModel kMove4 = ActionModel::kMove4;
  for (ActionModel actions : {kMove4, kRotate}) {
    const Guidance crowded_with_lns = actions == kRotate ? Guidance::kRing : Guidance::kLanes;
    EXPECT_EQ(lifelong_guidance(graph, 100, true, actions), Guidance::kNone);
    EXPECT_EQ(lifelong_guidance(graph, 204, true, actions), Guidance::kNone);
    EXPECT_EQ(lifelong_guidance(graph, 205, true, actions), crowded_with_lns);
    EXPECT_EQ(lifelong_guidance(graph, 400, true, actions), crowded_with_lns);
    EXPECT_EQ(lifelong_guidance(graph, 800, true, actions), crowded_with_lns);
    EXPECT_EQ(lifelong_guidance(graph, 100, false, actions), Guidance::kLanes);
    EXPECT_EQ(lifelong_guidance(graph, 1, false, actions), Guidance::kLanes);
    EXPECT_EQ(lifelong_guidance(graph, 800, false, actions), Guidance::kLanes);
  }
  // The ring road only where its 12 cells from each edge cover most of the map (the shorter side
  // at most 36 cells): warehouse_small (33 by 57) yes, warehouse_large (140 by 500) no.
  const std::string warehouse = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2023/warehouse.domain/";
  const LorrProblem small = load_lorr_problem(warehouse + "warehouse_small_800.json");
  EXPECT_EQ(lifelong_guidance(*small.graph, 800, true, kRotate), Guidance::kRing);
  const LorrProblem large = load_lorr_problem(warehouse + "warehouse_large_8000.json");
  ASSERT_EQ(large.graph->vertex_count(), 38'586);
  EXPECT_EQ(lifelong_guidance(*large.graph, 10'000, true, kRotate), Guidance::kLanes);
  // Few by fill (a quarter: 9,646) and by count (2,000): on warehouse_large lanes from 2,001 on.
  EXPECT_EQ(lifelong_guidance(*large.graph, 9'646, true, kRotate), Guidance::kLanes);
  EXPECT_EQ(lifelong_guidance(*large.graph, kMostAgentsOnShortestPaths + 1, true, kRotate), Guidance::kLanes);
  EXPECT_EQ(lifelong_guidance(*large.graph, kMostAgentsOnShortestPaths, true, kRotate), Guidance::kNone);
  // Waits and turns cost 3 with guidance and LNS in the rotation model, else 1.
  EXPECT_EQ(lifelong_stay_cost(lifelong_guidance(graph, 100, true, kRotate), true, kRotate), 1);
  EXPECT_EQ(lifelong_stay_cost(lifelong_guidance(graph, 400, true, kRotate), true, kRotate), 3);
  EXPECT_EQ(lifelong_stay_cost(Guidance::kLanes, true, kRotate), 3);
  EXPECT_EQ(lifelong_stay_cost(lifelong_guidance(graph, 400, false, kRotate), false, kRotate), 1);
  EXPECT_EQ(lifelong_stay_cost(lifelong_guidance(graph, 400, true, kMove4), true, kMove4), 1);
  EXPECT_EQ(lifelong_stay_cost(Guidance::kNone, true, kRotate), 1);
}

// Rollouts pick among PIBT runs: every step still valid, and with time to spare for every run the
// same seed gives the same run.
TEST(Lifelong, WithRolloutsEveryStepIsValidAndTheSameSeedRunsTheSame) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_400.json");
  const PibtLifelongSettings rollouts{.guidance = Guidance::kLanes, .rollouts = 16, .rollout_steps = 3};
  PibtLifelong first(*problem.graph, 2, rollouts), second(*problem.graph, 2, rollouts);
  LifelongSettings settings;
  settings.steps = 60;
  settings.step_time_s = 60;
  const LifelongResult a = run_lifelong(problem, first, settings);
  const LifelongResult b = run_lifelong(problem, second, settings);
  EXPECT_EQ(a.invalid_steps, 0) << a.first_invalid;
  EXPECT_GT(a.errands_finished, 60);
  EXPECT_EQ(a.errands_per_step, b.errands_per_step);
}

// However many runs are asked for, they stop within their share of the step's budget.
TEST(Lifelong, RolloutsStopWithinTheirShareOfTheBudget) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_400.json");
  PibtLifelong planner(*problem.graph, 2, {.guidance = Guidance::kLanes, .rollouts = 1'000'000});
  LifelongSettings settings;
  settings.steps = 5;
  settings.step_time_s = 2;  // runs get 1 s; a run of 3 steps of 400 agents takes about 0.3 ms
  const LifelongResult result = run_lifelong(problem, planner, settings);
  EXPECT_EQ(result.steps_over_budget, 0);
  EXPECT_EQ(result.invalid_steps, 0) << result.first_invalid;
}

// 10,000 robots touch tens of thousands of goals in a run: tables of goals nobody heads for are
// freed beyond the budget, and the run is the same.
TEST(Lifelong, DistanceTablesStayWithinTheirBudget) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_20.json");
  const size_t per_table = problem.graph->vertex_count() * sizeof(uint16_t);
  PibtLifelong lean(*problem.graph, 4, {.distance_bytes = 30 * per_table});
  PibtLifelong roomy(*problem.graph, 4);
  LifelongSettings settings;
  settings.steps = 400;
  const LifelongResult lean_run = run_lifelong(problem, lean, settings);
  const LifelongResult roomy_run = run_lifelong(problem, roomy, settings);
  EXPECT_LE(lean.distance_tables(), 30);
  EXPECT_GT(roomy.distance_tables(), 60);  // without the budget many more are held
  EXPECT_GT(lean_run.errands_finished, 100);
  EXPECT_EQ(lean_run.errands_per_step, roomy_run.errands_per_step);
}

}  // namespace
}  // namespace planner_core
