// Runs under the league's 2026 rules (league_run.hpp): actions take agentCounter ticks, delayed
// robots stand still, the Action Dependency Graph carries the staged plan out, and the tick check
// finds no fault on the Start-Kit's own examples, delays on. And the 2026 output's segments.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string>

#include "planner_core/league_engine.hpp"
#include "planner_core/league_output.hpp"
#include "planner_core/league_run.hpp"
#include "planner_core/pibt_lifelong.hpp"
#include "tiny_lorr_problem.hpp"

namespace planner_core {
namespace {

const std::string k2026 = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2026/";

// The planner as the league run needs it: no rotations; one PIBT run a step, so runs repeat.
PibtLifelong executable_planner(const LorrProblem& problem, uint32_t seed = 0) {
  return PibtLifelong(*problem.graph, seed,
                      {.actions = ActionModel::kRotate, .forbid_rotations = true});
}

std::string execution(int counter, const std::string& delays = "") {
  return "\"version\": \"2026 LoRR\", \"agentCounter\": " + std::to_string(counter) +
         ", \"agentSize\": 1.0" + (delays.empty() ? "" : ", \"delayConfig\": " + delays);
}

// One robot in a corridor, facing east: its errand four cells east, then back at the west end.
TEST(LeagueRun, AnActionTakesAgentCounterTicks) {
  TinyProblem tiny({"....."}, {"1", "0"}, {"2", "4", "0"}, execution(3));
  const LorrProblem problem = load_lorr_problem(tiny.path());
  PibtLifelong planner = executable_planner(problem);
  LeagueRunSettings settings;
  settings.ticks = 40;
  const LeagueRunResult result = run_league(problem, planner, settings);
  EXPECT_EQ(result.faults, 0) << result.first_fault;
  ASSERT_EQ(result.tasks_per_tick.size(), 40u);
  // Four moves of 3 ticks: the errand at the end of tick 11; then two turns and four moves.
  EXPECT_EQ(result.tasks_per_tick[11], 1);
  EXPECT_EQ(result.tasks_per_tick[29], 1);
  EXPECT_EQ(result.tasks_finished, 2);
  EXPECT_EQ(std::accumulate(result.tasks_per_tick.begin(), result.tasks_per_tick.end(), 0), 2);
  // Then back towards the east end: two turns (ticks 30-35) and a move (36-38).
  EXPECT_EQ(result.moves_finished, 13);
  EXPECT_EQ(result.delayed_robot_ticks, 0);
}

TEST(LeagueRun, OneTickActionsFinishAsSoonAsTheMovesAllow) {
  TinyProblem tiny({"....."}, {"1", "0"}, {"1", "4"}, execution(1));
  const LorrProblem problem = load_lorr_problem(tiny.path());
  PibtLifelong planner = executable_planner(problem);
  LeagueRunSettings settings;
  settings.ticks = 6;
  const LeagueRunResult result = run_league(problem, planner, settings);
  EXPECT_EQ(result.faults, 0) << result.first_fault;
  // Four moves, ticks 0-3; the next task is on the same cell (the file is started over): one task
  // a tick from then on, as the league counts, however many the plan's waits reach at once.
  EXPECT_EQ(result.tasks_per_tick[2], 0);
  EXPECT_EQ(result.tasks_per_tick[3], 1);
  EXPECT_EQ(result.tasks_per_tick[4], 1);
  EXPECT_EQ(result.tasks_per_tick[5], 1);
  EXPECT_EQ(result.tasks_finished, 3);
}

// pDelay 1: a robot is delayed again as soon as a delay ends, so it never moves; with delays off
// the same problem runs as without a delayConfig.
TEST(LeagueRun, ADelayedRobotStandsStill) {
  const std::string always = R"({"seed": 3, "minDelay": 4, "maxDelay": 6, "eventModel": "bernoulli", "pDelay": 1.0,
      "durationModel": "uniform", "gaussMeanRatio": 0.5, "gaussStdRatio": 0.22})";
  TinyProblem tiny({"....."}, {"1", "0"}, {"2", "4", "0"}, execution(3, always));
  const LorrProblem problem = load_lorr_problem(tiny.path());
  LeagueRunSettings settings;
  settings.ticks = 40;
  {
    PibtLifelong planner = executable_planner(problem);
    const LeagueRunResult delayed = run_league(problem, planner, settings);
    EXPECT_EQ(delayed.moves_finished, 0);
    EXPECT_EQ(delayed.tasks_finished, 0);
    EXPECT_EQ(delayed.delayed_robot_ticks, 40);
    EXPECT_DOUBLE_EQ(delayed.delayed_share(), 1.0);
  }
  settings.delays = false;
  PibtLifelong planner = executable_planner(problem);
  const LeagueRunResult free = run_league(problem, planner, settings);
  EXPECT_EQ(free.tasks_finished, 2);
  EXPECT_EQ(free.delayed_robot_ticks, 0);
}

// The Start-Kit's examples with their own delays: the executor never lets two robots hold one
// cell, a delayed robot holds up only some, and the fleet finishes tasks.
TEST(LeagueRun, StartKitExamplesRunWithDelaysAndNoFault) {
  for (const char* file : {"random.domain/random-example_400.json", "maze.domain/maze-example_40.json",
                           "room.domain/room-example_150.json"}) {
    const LorrProblem problem = load_lorr_problem(k2026 + file);
    PibtLifelong planner = executable_planner(problem);
    LeagueRunSettings settings;
    settings.ticks = 300;
    LeagueLog log;
    settings.log = &log;
    const LeagueRunResult result = run_league(problem, planner, settings);
    EXPECT_EQ(result.faults, 0) << file << ": " << result.first_fault;
    EXPECT_EQ(result.invalid_steps, 0) << file << ": " << result.first_invalid;
    EXPECT_GT(result.tasks_finished, 0) << file;
    EXPECT_GT(result.delayed_robot_ticks, 0) << file;
    EXPECT_EQ(result.robot_ticks, 300 * static_cast<int64_t>(problem.starts.size())) << file;
    // Every robot's actions tick by tick, and each delay interval is spent standing still.
    ASSERT_EQ(log.actual.size(), problem.starts.size());
    for (size_t r = 0; r < log.actual.size(); ++r) {
      ASSERT_EQ(log.actual[r].size(), 300u);
      for (const auto& [first, last] : log.delay_intervals[r]) {
        for (int t = first; t <= std::min(last, 299); ++t) EXPECT_EQ(log.actual[r][t], 'W') << file << " robot " << r;
      }
    }
    int64_t events = 0;
    for (const LeagueLog::Event& event : log.events) events += event.errands_done >= 1 ? 1 : 0;
    EXPECT_EQ(events, result.errands_finished) << file;
  }
}

// Segments of 4 ticks, agentCounter 3: a move ends on its third F, a turn on its third R.
TEST(LeagueOutput, SegmentsCarryThePoseAndTheCounterOver) {
  const Graph graph(5, 1, {"....."});
  EXPECT_EQ(league_segments(graph, graph.vertex_at({0, 0}), 0, "FFFFFFWWRRR", 3, 4),
            "[(0,0,0,0,0):(F 4)][(4,0,1,0,1):(F 2,W 2)][(8,0,2,0,0):(R 3)]");
  EXPECT_EQ(league_segments(graph, graph.vertex_at({4, 0}), 2, "WWW", 3, 1000), "[(0,0,4,2,0):(W 3)]");
  EXPECT_EQ(league_segments(graph, graph.vertex_at({0, 0}), 0, "", 3, 1000), "");
}

TEST(LeagueOutput, TheFileHasTheLeaguesKeys) {
  const LorrProblem problem = load_lorr_problem(k2026 + "maze.domain/maze-example_40.json");
  PibtLifelong planner = executable_planner(problem);
  LeagueRunSettings settings;
  settings.ticks = 120;
  LeagueLog log;
  settings.log = &log;
  const LeagueRunResult result = run_league(problem, planner, settings);
  const std::string path = ::testing::TempDir() + "league-output.json";
  write_league_output(path, problem, settings, result, log, 50);
  std::ifstream file(path);
  const nlohmann::json out = nlohmann::json::parse(file);
  EXPECT_EQ(out["actionModel"], "MAPF_T");
  EXPECT_EQ(out["version"], "2026 LoRR");
  EXPECT_EQ(out["teamSize"], 40);
  EXPECT_EQ(out["numTaskFinished"], result.tasks_finished);
  EXPECT_EQ(out["makespan"], 120);
  EXPECT_EQ(out["agentMaxCounter"], 3);
  EXPECT_EQ(out["outputSegmentSize"], 50);
  for (const char* key : {"delayIntervals", "start", "actualPaths", "events", "tasks", "plannerTimes", "errors",
                          "actualSchedule"}) {
    ASSERT_TRUE(out.contains(key)) << key;
    EXPECT_EQ(out[key].is_array(), true) << key;
  }
  EXPECT_EQ(out["actualPaths"].size(), 40u);
  EXPECT_EQ(out["start"][0][2], "E");
  // Three segments of 50 ticks per robot.
  const std::string first = out["actualPaths"][0];
  EXPECT_EQ(std::count(first.begin(), first.end(), '['), 3);
  EXPECT_THROW(write_league_output("/nonexistent-dir/x.json", problem, settings, result, log), InputError);
}


// The engine keeps the staged plan `lead_steps` ahead of the median robot: planning again before
// robots finish moves adds nothing, and the plan grows as they carry it out.
TEST(LeagueEngine, TheStagedPlanStaysLeadStepsAheadOfTheMedianRobot) {
  const LorrProblem problem = load_lorr_problem(k2026 + "maze.domain/maze-example_40.json");
  PibtLifelong planner = executable_planner(problem);
  LeagueEngine engine(problem, planner, TaskScheduler::kWholeTaskReassign, 6);
  std::vector<int> finished(problem.starts.size(), 0);
  EXPECT_EQ(engine.plan(finished, 1.0).steps, 6);
  EXPECT_EQ(engine.staged().plan_steps(), 6);
  EXPECT_EQ(engine.plan(finished, 1.0).steps, 0);
  // Every robot carries out its moves of the first two steps: the median is at step 2.
  for (int r = 0; r < engine.robots(); ++r) {
    while (finished[r] < engine.staged().move_count(r) && engine.staged().move(r, finished[r]).plan_time <= 2) {
      ++finished[r];
    }
    EXPECT_GE(engine.executed_step(r, finished[r]), 2);
  }
  const LeagueEngine::PlanCall call = engine.plan(finished, 1.0);
  EXPECT_GE(call.steps, 2);
  EXPECT_EQ(call.invalid_steps, 0) << call.first_invalid;
  EXPECT_EQ(engine.staged().plan_steps(), 6 + call.steps);
  for (int r = 0; r < engine.robots(); ++r) EXPECT_GE(engine.task_of(r), 0);
}


// Robots held (seen delayed) stay where the staged plan leaves them for one plan(); then they go on.
TEST(LeagueEngine, HeldRobotsStayForOnePlanCall) {
  const LorrProblem problem = load_lorr_problem(k2026 + "maze.domain/maze-example_40.json");
  PibtLifelong planner = executable_planner(problem);
  LeagueEngine engine(problem, planner, TaskScheduler::kWholeTaskReassign, 6);
  std::vector<int> finished(problem.starts.size(), 0);
  engine.hold(std::vector<char>(problem.starts.size(), 1));
  ASSERT_EQ(engine.plan(finished, 1.0).steps, 6);
  int moves = 0;
  for (int r = 0; r < engine.robots(); ++r) moves += engine.staged().move_count(r);
  EXPECT_EQ(moves, 0);
  // Carried out (nothing to carry out): the median robot is at the plan's end, so it grows again.
  ASSERT_EQ(engine.plan(finished, 1.0).steps, 6);
  for (int r = 0; r < engine.robots(); ++r) moves += engine.staged().move_count(r);
  EXPECT_GT(moves, 0);
}

// Delays on, robots planned round those seen delayed or not: no fault either way.
TEST(LeagueRun, PlanningRoundDelayedRobotsOrNotNeverCausesAFault) {
  const LorrProblem problem = load_lorr_problem(k2026 + "room.domain/room-example_150.json");
  for (bool round : {true, false}) {
    PibtLifelong planner = executable_planner(problem);
    LeagueRunSettings settings;
    settings.ticks = 300;
    settings.plan_round_delayed = round;
    const LeagueRunResult result = run_league(problem, planner, settings);
    EXPECT_EQ(result.faults, 0) << result.first_fault;
    EXPECT_GT(result.tasks_finished, 0);
  }
}

}  // namespace
}  // namespace planner_core
