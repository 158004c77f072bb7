// Every solver keeps a short time limit on a 10,000-agent instance (the mapf-scale suite's
// warehouse): distances, task orders and the search all look at the clock. The bound is generous
// for a loaded test machine; the exact overshoot figures are measured by ctsfleet-bench
// --experiment mapf-scale.
#include <gtest/gtest.h>

#include <string>

#include "planner_core/instance.hpp"
#include "planner_core/solver.hpp"

namespace planner_core {
namespace {

constexpr double kLimitS = 1.0;
constexpr double kAllowedOvershootS = 1.5;

const Instance& warehouse_10000() {
  static const Instance instance =
      load_instance(std::string(CTSFLEET_BENCHMARKS_DIR) + "/mapf-scale/warehouse-20-40-10-2-2-N10000.yaml");
  return instance;
}

class DeadlineAtScale : public ::testing::TestWithParam<std::string> {};

TEST_P(DeadlineAtScale, ReturnsWithinTheLimit) {
  const Instance& instance = warehouse_10000();
  ASSERT_EQ(instance.agent_count(), 10000);
  SolverConfig config;
  config.solver = GetParam();
  SolveOptions options;
  options.started = Clock::now();
  options.deadline = Deadline::in_seconds(kLimitS);
  const SolveResult result = make_solver(config)->solve(instance, options);
  const double wall_s = elapsed_ms(options.started) / 1000.0;
  EXPECT_LT(wall_s, kLimitS + kAllowedOvershootS) << config.solver << " took " << wall_s << " s";
  EXPECT_LE(result.comp_time_ms / 1000.0, wall_s);
  EXPECT_GE(result.preprocessing_ms, 0.0);
  if (!result.solved) {
    EXPECT_FALSE(result.failure_reason.empty());
  } else {
    EXPECT_LE(result.first_solution_ms, result.comp_time_ms);
  }
}

TEST(WorkDeadline, AWorkSliceEndsAfterItsUnitsWhateverTheClock) {
  const Deadline solve = Deadline::in_seconds(1000);
  solve.spend(500);
  const Deadline slice = solve.within_work(100);  // counted from the 500 already done
  EXPECT_FALSE(slice.expired());
  slice.spend(99);
  EXPECT_FALSE(slice.expired());
  slice.spend(1);
  EXPECT_TRUE(slice.expired());
  EXPECT_FALSE(solve.expired()) << "the solve's own limit is the clock's";
  EXPECT_EQ(solve.work_done(), 600) << "a slice counts on the solve's meter";
  // A slice never outlasts the deadline it was cut from.
  const Deadline budget = Deadline::in_seconds(1000).with_work_budget(50);
  EXPECT_EQ(budget.within_work(1000).work_at, budget.work_at);
}

TEST(WorkDeadline, WithAWorkBudgetTheSolversSharesAreCountedInWork) {
  const Deadline clocked = Deadline::for_limits(1000, 0);
  EXPECT_FALSE(clocked.shares_in_work);
  EXPECT_EQ(clocked.slice(0.5).work_at, kNoWorkLimit) << "without a budget a share is time";
  EXPECT_DOUBLE_EQ(clocked.budget_s, 1000);

  const Deadline budgeted = Deadline::for_limits(1000, 10);  // 10 iterations
  ASSERT_TRUE(budgeted.shares_in_work);
  EXPECT_EQ(budgeted.work_at, 10 * kWorkPerIteration);
  EXPECT_NEAR(budgeted.budget_s, 0.01, 1e-12);
  EXPECT_NEAR(budgeted.budget_left_s(), 0.01, 1e-12);
  const Deadline share = budgeted.slice(0.004);
  EXPECT_EQ(share.work_at, Deadline::work_of(0.004));
  budgeted.spend(Deadline::work_of(0.004));
  EXPECT_TRUE(share.expired());
  EXPECT_FALSE(budgeted.expired());
  EXPECT_NEAR(budgeted.budget_left_s(), 0.006, 1e-9);
  budgeted.spend(10 * kWorkPerIteration);
  EXPECT_TRUE(budgeted.expired());
  EXPECT_EQ(budgeted.budget_left_s(), 0);
}

TEST(WorkDeadline, HugeBudgetsDoNotOverflow) {
  const Deadline budget = Deadline::for_limits(1, kMaxIterations);
  EXPECT_GT(budget.work_at, 0);
  EXPECT_EQ(Deadline::work_of(1e30), kNoWorkLimit);
  EXPECT_EQ(Deadline::in_seconds(1).within_work(kNoWorkLimit).work_at, kNoWorkLimit);
  EXPECT_EQ(Deadline::work_of(-1), 0);
}

// Two solves of one instance with the same seed make the same plan in-process too, with a work
// budget for the anytime one (the test of the programs: cli.same_seed_same_plan).
TEST(WorkDeadline, AnAnytimeSolveWithAWorkBudgetRepeatsItsPlan) {
  const Instance instance = load_instance(std::string(CTSFLEET_BENCHMARKS_DIR) + "/dense/maze-32-32-2-N50-M120-07.yaml");
  SolverConfig config;
  config.solver = "cts-pll-v3";
  config.seed = 3;
  const auto solve = [&] {
    SolveOptions options;
    options.deadline = Deadline::for_limits(120, 300);
    return make_solver(config)->solve(instance, options);
  };
  const SolveResult first = solve();
  const SolveResult second = solve();
  ASSERT_TRUE(first.solved);
  EXPECT_GT(first.lns_iterations, 0);
  EXPECT_EQ(first.lns_iterations, second.lns_iterations);
  EXPECT_EQ(first.flowtime, second.flowtime);
  EXPECT_TRUE(first.solution == second.solution);
}

INSTANTIATE_TEST_SUITE_P(EverySolver, DeadlineAtScale, ::testing::ValuesIn(solver_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

}  // namespace
}  // namespace planner_core
