// The rotation model (forward, quarter turns, wait; planner_core/action_model.hpp) in the lifelong
// run: distances per cell and heading against a plain Bellman-Ford, which steps are valid, and
// PIBT that turns before it moves: every step valid, agents that meet head on get past each
// other, the same seed runs the same.
#include <gtest/gtest.h>

#include <stdexcept>

#include "planner_core/guided_distances.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/lifelong.hpp"
#include "planner_core/lifelong_auto_rules.hpp"
#include "planner_core/pibt_lifelong.hpp"
#include "planner_core/lorr_problem.hpp"
#include "tiny_lorr_problem.hpp"

namespace planner_core {
namespace {

const std::string kRandom = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2023/random.domain/";
constexpr int kEast = 0, kSouth = 1, kWest = 2, kNorth = 3;

TEST(ActionModel, NamesAndHeadings) {
  EXPECT_EQ(parse_action_model("move4", "--actions"), ActionModel::kMove4);
  EXPECT_EQ(parse_action_model("rotate", "--actions"), ActionModel::kRotate);
  try {
    parse_action_model("diagonal", "--actions");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--actions: \"diagonal\" is no action model"), std::string::npos);
  }
  const Graph graph(3, 2, {"...", ".@."});  // row 0: 0 1 2; row 1: 3 (0,1), 4 (2,1)
  const Vertex middle = graph.vertex_at({1, 0});
  EXPECT_EQ(ahead(graph, middle, kEast), graph.vertex_at({2, 0}));
  EXPECT_EQ(ahead(graph, middle, kWest), graph.vertex_at({0, 0}));
  EXPECT_EQ(ahead(graph, middle, kSouth), kNoVertex);  // a wall
  EXPECT_EQ(ahead(graph, middle, kNorth), kNoVertex);  // the edge
  EXPECT_EQ(heading_towards(graph, graph.vertex_at({0, 0}), graph.vertex_at({0, 1})), kSouth);
  EXPECT_EQ(turned_clockwise(kNorth), kEast);
  EXPECT_EQ(turned_counter_clockwise(kEast), kNorth);
  EXPECT_EQ(heading_letter(kSouth), 'S');
}

TEST(RotationDistances, TurnsCountAsSteps) {
  const Graph graph(5, 1, {"....."});
  GuidedDistances distances(graph, Guidance::kNone, ActionModel::kRotate);
  const Vertex left = graph.vertex_at({0, 0});
  const Vertex right = graph.vertex_at({4, 0});
  EXPECT_EQ(distances.get(right, left, kEast), 4);
  EXPECT_EQ(distances.get(right, left, kSouth), 5);
  EXPECT_EQ(distances.get(right, left, kNorth), 5);
  EXPECT_EQ(distances.get(right, left, kWest), 6);
  for (int h = 0; h < kHeadings; ++h) EXPECT_EQ(distances.get(right, right, h), 0);  // any heading at the goal
  EXPECT_EQ(distances.get_after_turning(right, left, kWest), 5);
  EXPECT_EQ(distances.bytes_per_target(), 5u * 4 * 2);
}

// Every state's cost against a plain Bellman-Ford over cells and headings, with lanes and with a
// ring road (where a turn costs its cell's stay cost).
TEST(RotationDistances, MatchBellmanFordOverCellAndHeading) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_20.json");
  const Graph& graph = *problem.graph;
  for (Guidance guidance : {Guidance::kNone, Guidance::kLanes, Guidance::kRing}) {
    GuidedDistances distances(graph, guidance, ActionModel::kRotate);
    for (Vertex target : {Vertex{0}, graph.vertex_count() / 2, graph.vertex_count() - 1}) {
      const int n = graph.vertex_count() * kHeadings;
      std::vector<int> cost(n, GuidedDistances::kUnreachable);
      for (int h = 0; h < kHeadings; ++h) cost[target * kHeadings + h] = 0;
      for (bool changed = true; changed;) {
        changed = false;
        for (Vertex v = 0; v < graph.vertex_count(); ++v) {
          for (int h = 0; h < kHeadings; ++h) {
            int best = cost[v * kHeadings + h];
            best = std::min(best, cost[v * kHeadings + turned_clockwise(h)] + distances.stay_cost(v));
            best = std::min(best, cost[v * kHeadings + turned_counter_clockwise(h)] + distances.stay_cost(v));
            const Vertex next = ahead(graph, v, h);
            if (next != kNoVertex && cost[next * kHeadings + h] < GuidedDistances::kUnreachable) {
              best = std::min(best, cost[next * kHeadings + h] + distances.move_cost(v, next));
            }
            if (best < cost[v * kHeadings + h]) cost[v * kHeadings + h] = best, changed = true;
          }
        }
      }
      for (Vertex v = 0; v < graph.vertex_count(); ++v) {
        for (int h = 0; h < kHeadings; ++h) {
          ASSERT_EQ(distances.get(target, v, h), cost[v * kHeadings + h])
              << to_string(guidance) << ", target " << target << ", from " << v << " facing " << h;
        }
      }
    }
  }
}

TEST(RotationStep, OnlyForwardMovesAndQuarterTurnsAreValid) {
  const Graph graph(5, 2, {".....", "....."});  // row 0: 0..4, row 1: 5..9
  const auto at = [&](int x, int y) { return graph.vertex_at({x, y}); };
  const Poses now{{at(0, 0), at(4, 0)}, {kEast, kWest}};
  const auto fault = [&](const Poses& next) { return find_pose_fault(graph, ActionModel::kRotate, now, next).what; };
  EXPECT_EQ(fault({{at(1, 0), at(3, 0)}, {kEast, kWest}}), "");                            // both forward
  EXPECT_EQ(fault({{at(0, 0), at(4, 0)}, {kSouth, kSouth}}), "");                          // quarter turns
  EXPECT_EQ(fault({{at(0, 0), at(4, 0)}, {kEast, kWest}}), "");                            // waits
  EXPECT_NE(fault({{at(0, 0), at(4, 0)}, {kWest, kWest}}).find("agent 0 turns half round"), std::string::npos);
  EXPECT_NE(fault({{at(0, 1), at(4, 0)}, {kEast, kWest}}).find("agent 0 facing E moves from (0,0) other than forward"),
            std::string::npos);
  EXPECT_NE(fault({{at(1, 0), at(4, 0)}, {kSouth, kWest}}).find("other than forward"), std::string::npos);  // moves and turns
  EXPECT_NE(fault({{at(0, 0), at(4, 0)}, {kEast, 7}}).find("agent 1 faces no heading"), std::string::npos);
  EXPECT_NE(fault({{at(0, 0), at(4, 0)}, {}}).find("without a heading"), std::string::npos);
  // Cells as in the four-move model: two agents on one cell, a swap.
  const Poses facing{{at(1, 0), at(3, 0)}, {kEast, kWest}};
  EXPECT_NE(find_pose_fault(graph, ActionModel::kRotate, facing, {{at(2, 0), at(2, 0)}, {kEast, kWest}}).what.find("both on"),
            std::string::npos);
  const Poses touching{{at(1, 0), at(2, 0)}, {kEast, kWest}};
  EXPECT_NE(find_pose_fault(graph, ActionModel::kRotate, touching, {{at(2, 0), at(1, 0)}, {kEast, kWest}}).what.find("swap"),
            std::string::npos);
  // The four-move model takes no heading into account.
  EXPECT_EQ(find_pose_fault(graph, ActionModel::kMove4, {{at(0, 0)}, {}}, {{at(0, 1)}, {}}).what, "");
}

TEST(RotationLifelong, APlannerAskedWithoutHeadingsRefuses) {
  const Graph graph(5, 1, {"....."});
  PibtLifelong planner(graph, 1, {.actions = ActionModel::kRotate});
  EXPECT_THROW(planner.next_step({{0, 4}, {}}, {4, 0}, Deadline::in_seconds(1)), std::invalid_argument);
}

TEST(RotationLifelong, FourHundredAgentsStepValidlyAndTheSameSeedRunsTheSame) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_400.json");
  LifelongSettings settings{.steps = 200, .step_time_s = 5.0};
  settings.actions = ActionModel::kRotate;
  for (Guidance guidance : {Guidance::kNone, Guidance::kLanes}) {
    const PibtLifelongSettings pibt{.guidance = guidance, .actions = ActionModel::kRotate};
    PibtLifelong first(*problem.graph, 11, pibt), second(*problem.graph, 11, pibt);
    const LifelongResult a = run_lifelong(problem, first, settings);
    const LifelongResult b = run_lifelong(problem, second, settings);
    EXPECT_EQ(a.invalid_steps, 0) << a.first_invalid;
    EXPECT_GT(a.errands_finished, 100) << to_string(guidance);
    EXPECT_EQ(a.errands_per_step, b.errands_per_step);
    EXPECT_EQ(a.moves, b.moves);
  }
}

TEST(RotationLifelong, WithRolloutsEveryStepIsValid) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_100.json");
  LifelongSettings settings{.steps = 60, .step_time_s = 5.0};
  settings.actions = ActionModel::kRotate;
  PibtLifelong planner(*problem.graph, 3, {.guidance = Guidance::kLanes, .actions = ActionModel::kRotate, .rollouts = 16});
  const LifelongResult result = run_lifelong(problem, planner, settings);
  EXPECT_EQ(result.invalid_steps, 0) << result.first_invalid;
  EXPECT_GT(result.errands_finished, 0);
}

// Two agents that meet head on in a corridor with one pocket, again and again (their tasks send
// them to each other's end), and an agent let out of a dead end: whatever the seed, they keep
// finishing errands. With kept targets they pass more slowly in the corridor (8-14 errands in 200
// steps over these seeds, against 16-18 without), which is why keep_targets is off by default;
// a lock would leave them at 2 or fewer.
TEST(RotationLifelong, AgentsThatMeetHeadOnGetPastEachOther) {
  TinyProblem corridor({".......", "@@@.@@@"}, {"2", "0", "6"}, {"4", "6", "0", "0", "6"});
  TinyProblem dead_end({".@...", "....."}, {"2", "0", "5"}, {"4", "9", "0", "3", "0"});
  for (const TinyProblem* tiny : {&corridor, &dead_end}) {
    const LorrProblem problem = load_lorr_problem(tiny->path());
    LifelongSettings settings{.steps = 200, .step_time_s = 1.0};
    settings.actions = ActionModel::kRotate;
    for (Guidance guidance : {Guidance::kNone, Guidance::kLanes}) {
      for (PlanHolding holding : {PlanHolding::kNever, PlanHolding::kAlways}) {
        for (bool keep_targets : {false, true}) {
          for (uint32_t seed = 0; seed < 20; ++seed) {
            PibtLifelong planner(*problem.graph, seed,
                                 {.guidance = guidance,
                                  .actions = ActionModel::kRotate,
                                  .keep_targets = keep_targets,
                                  .hold_plans = holding});
            const LifelongResult result = run_lifelong(problem, planner, settings);
            EXPECT_EQ(result.invalid_steps, 0) << result.first_invalid;
            EXPECT_GE(result.errands_finished, keep_targets ? 6 : 10)
                << tiny->path() << ", seed " << seed << ", " << to_string(guidance) << ", held "
                << to_string(holding) << (keep_targets ? ", targets kept" : "");
          }
        }
      }
    }
  }
}

TEST(RotationLifelong, HeldPlansAndKeptTargetsStepValidlyAndTheSameSeedRunsTheSame) {
  for (const char* name : {"random_400.json", "random_800.json"}) {
    const LorrProblem problem = load_lorr_problem(kRandom + name);
    LifelongSettings settings{.steps = 80, .step_time_s = 5.0};
    settings.actions = ActionModel::kRotate;
    for (PlanHolding holding : {PlanHolding::kNever, PlanHolding::kInHalfTheRollouts, PlanHolding::kAlways}) {
      for (bool keep_targets : {false, true}) {
        const PibtLifelongSettings pibt{.guidance = Guidance::kLanes,
                                        .actions = ActionModel::kRotate,
                                        .rollouts = 4,
                                        .keep_targets = keep_targets,
                                        .hold_plans = holding};
        PibtLifelong first(*problem.graph, 7, pibt), second(*problem.graph, 7, pibt);
        const LifelongResult a = run_lifelong(problem, first, settings);
        const LifelongResult b = run_lifelong(problem, second, settings);
        const std::string what = std::string(name) + ", held " + to_string(holding) + (keep_targets ? ", kept" : "");
        EXPECT_EQ(a.invalid_steps, 0) << what << ": " << a.first_invalid;
        EXPECT_EQ(a.steps_over_budget, 0) << what;
        EXPECT_GT(a.errands_finished, 0) << what;
        EXPECT_EQ(a.errands_per_step, b.errands_per_step) << what;
        EXPECT_EQ(a.moves, b.moves) << what;
      }
    }
  }
}

// Kept targets and held plans are rotation-model remedies: in four moves they change nothing.
TEST(RotationLifelong, KeptTargetsAndHeldPlansLeaveFourMovesAlone) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_400.json");
  const LifelongSettings settings{.steps = 100, .step_time_s = 5.0};
  PibtLifelong plain(*problem.graph, 4,
                     {.guidance = Guidance::kLanes, .rollouts = 4, .keep_targets = false, .hold_plans = PlanHolding::kNever});
  PibtLifelong both(*problem.graph, 4,
                    {.guidance = Guidance::kLanes, .rollouts = 4, .keep_targets = true, .hold_plans = PlanHolding::kAlways});
  const LifelongResult a = run_lifelong(problem, plain, settings);
  const LifelongResult b = run_lifelong(problem, both, settings);
  EXPECT_GT(a.errands_finished, 0);
  EXPECT_EQ(a.errands_per_step, b.errands_per_step);
  EXPECT_EQ(a.moves, b.moves);
}

// Window LNS rewrites the chosen rollout's steps, so a held plan may meet agents LNS sent onto a
// cell another still heads for: no step may be invalid for it (the first version had 319 of 500).
TEST(RotationLifelong, HeldPlansWithWindowLnsStepValidly) {
  for (const char* name : {"random_400.json", "random_800.json"}) {
    const LorrProblem problem = load_lorr_problem(kRandom + name);
    LifelongSettings settings{.steps = 40, .step_time_s = 0.2};
    settings.actions = ActionModel::kRotate;
    for (PlanHolding holding : {PlanHolding::kInHalfTheRollouts, PlanHolding::kAlways}) {
      PibtLifelong planner(*problem.graph, 2,
                           {.guidance = Guidance::kRing,  // as ctsfleet-bench runs it (lifelong_guidance)
                            .stay_cost = 3,               // (lifelong_stay_cost)
                            .actions = ActionModel::kRotate,
                            .rollouts = 16,
                            .rollout_steps = 8,
                            .lns = true,
                            .keep_targets = true,
                            .hold_plans = holding});
      const LifelongResult result = run_lifelong(problem, planner, settings);
      EXPECT_EQ(result.invalid_steps, 0) << name << ", held " << to_string(holding) << ": " << result.first_invalid;
      EXPECT_GT(result.errands_finished, 0) << name;
    }
  }
}

// A moves east along the top row while B, below, turns north towards its goal. Holding PIBT's
// cells as a plan, A (on its cell after one step) waits the step B takes to move; deciding afresh,
// A goes on at once.
TEST(RotationLifelong, AHeldPlanWaitsUntilEveryAgentStandsOnItsCell) {
  const Graph graph(5, 3, {".....", ".....", "....."});
  const auto at = [&](int x, int y) { return graph.vertex_at({x, y}); };
  const Config goals{at(4, 0), at(0, 1)};
  for (PlanHolding holding : {PlanHolding::kNever, PlanHolding::kAlways}) {
    PibtLifelong planner(graph, 3, {.actions = ActionModel::kRotate, .hold_plans = holding});
    const Poses first = planner.next_step({{at(0, 0), at(0, 2)}, {kEast, kEast}}, goals, Deadline::in_seconds(5));
    ASSERT_EQ(first.cells, (Config{at(1, 0), at(0, 2)}));
    ASSERT_EQ(first.headings, (std::vector<int>{kEast, kNorth}));
    const Poses second = planner.next_step(first, goals, Deadline::in_seconds(5));
    EXPECT_EQ(second.cells[1], at(0, 1)) << "B moves onto the cell it turned towards";
    EXPECT_EQ(second.cells[0], holding == PlanHolding::kAlways ? at(1, 0) : at(2, 0)) << to_string(holding);
    const Poses third = planner.next_step(second, goals, Deadline::in_seconds(5));
    EXPECT_EQ(third.cells[0], holding == PlanHolding::kAlways ? at(2, 0) : at(3, 0)) << "the plan is done: A goes on";
  }
}

// B turns north towards the cell on its way; then C, beside that cell, is given it as its goal and
// is nearer its goal than B. With kept targets B, short of its cell, goes first and takes it;
// without, C (first by distance) does and B stays.
TEST(RotationLifelong, AnAgentShortOfItsTargetTakesItFirst) {
  const Graph graph(3, 3, {"...", "...", "..."});
  const auto at = [&](int x, int y) { return graph.vertex_at({x, y}); };
  for (bool keep_targets : {false, true}) {
    PibtLifelong planner(graph, 5,
                         {.actions = ActionModel::kRotate, .keep_targets = keep_targets, .hold_plans = PlanHolding::kNever});
    const Poses start{{at(1, 2), at(0, 1)}, {kEast, kEast}};
    const Poses first = planner.next_step(start, {at(1, 0), at(0, 1)}, Deadline::in_seconds(5));
    ASSERT_EQ(first.cells, start.cells);
    ASSERT_EQ(first.headings, (std::vector<int>{kNorth, kEast})) << "B turns towards (1, 1)";
    const Poses second = planner.next_step(first, {at(1, 0), at(1, 1)}, Deadline::in_seconds(5));
    if (keep_targets) {
      EXPECT_EQ(second.cells, (Config{at(1, 1), at(0, 1)}));
    } else {
      EXPECT_EQ(second.cells, (Config{at(1, 2), at(1, 1)}));
    }
  }
}

TEST(RotationLifelong, HoldingPlansIsNamedOnCommandLines) {
  EXPECT_EQ(parse_plan_holding("never", "--hold-plans"), PlanHolding::kNever);
  EXPECT_EQ(parse_plan_holding("half", "--hold-plans"), PlanHolding::kInHalfTheRollouts);
  EXPECT_EQ(parse_plan_holding("always", "--hold-plans"), PlanHolding::kAlways);
  for (PlanHolding holding : {PlanHolding::kNever, PlanHolding::kInHalfTheRollouts, PlanHolding::kAlways}) {
    EXPECT_EQ(parse_plan_holding(to_string(holding), "x"), holding);
  }
  try {
    parse_plan_holding("sometimes", "--hold-plans");
    FAIL() << "accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("--hold-plans: \"sometimes\""), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace planner_core
