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

INSTANTIATE_TEST_SUITE_P(EverySolver, DeadlineAtScale, ::testing::ValuesIn(solver_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

}  // namespace
}  // namespace planner_core
