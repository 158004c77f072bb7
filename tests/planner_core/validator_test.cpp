#include <gtest/gtest.h>

#include "planner_core/validator.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

using Kind = Violation::Kind;

// Map (x to the right, y down):   . . . . .
//                                 . @ . . .
class ValidatorTest : public ::testing::Test {
 protected:
  Instance instance = testing::make_instance({".....", ".@..."}, {{{0, 0}, {2, 0}}, {{4, 0}, {3, 0}}},
                                             {{{2, 1}, {0}}});
  Vertex at(int x, int y) const { return instance.graph->vertex_at({x, y}); }
  // Agent 0 goes (0,0) -> (2,0) via its task at (2,1); agent 1 steps to (3,0).
  Solution valid_plan() const {
    return {{at(0, 0), at(4, 0)}, {at(1, 0), at(3, 0)}, {at(2, 0), at(3, 0)}, {at(2, 1), at(3, 0)},
            {at(2, 0), at(3, 0)}};
  }
};

TEST_F(ValidatorTest, AcceptsValidPlanAndComputesCosts) {
  const ValidationReport report = validate(instance, valid_plan());
  EXPECT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(report.flowtime, 4 + 1);
  EXPECT_EQ(report.makespan, 4);
}

TEST_F(ValidatorTest, AWalledVertexIsABlockedCell) {
  // The same plan on the map with (1,0) walled (same vertex ids): agent 0 walks through the wall.
  instance.graph = std::make_shared<const Graph>(instance.graph->with_walls({at(1, 0)}));
  const ValidationReport report = validate(instance, valid_plan());
  ASSERT_TRUE(report.has(Kind::kBlockedCell)) << report.summary();
  EXPECT_EQ(report.violations.front().time, 1);
  EXPECT_EQ(report.violations.front().agent, 0);
}

TEST_F(ValidatorTest, Empty) { EXPECT_TRUE(validate(instance, {}).has(Kind::kEmpty)); }

TEST_F(ValidatorTest, AgentCount) {
  Solution plan = valid_plan();
  plan[2].pop_back();
  const ValidationReport report = validate(instance, plan);
  ASSERT_TRUE(report.has(Kind::kAgentCount));
  EXPECT_EQ(report.violations.front().time, 2);
}

TEST_F(ValidatorTest, WrongStart) {
  Solution plan = valid_plan();
  plan[0][1] = at(4, 1);
  const ValidationReport report = validate(instance, plan);
  ASSERT_TRUE(report.has(Kind::kWrongStart));
  EXPECT_EQ(report.violations.front().agent, 1);
}

TEST_F(ValidatorTest, BlockedCell) {
  Solution plan = valid_plan();
  plan[1][0] = kNoVertex;  // what the reader makes of (1,1), a wall
  const ValidationReport report = validate(instance, plan);
  ASSERT_TRUE(report.has(Kind::kBlockedCell));
  EXPECT_EQ(report.violations.front().time, 1);
}

TEST_F(ValidatorTest, VertexIdsOffTheMapAreBlockedCellsNotCrashes) {
  for (Vertex bogus : {-7, instance.graph->vertex_count(), 1 << 30}) {
    Solution plan = valid_plan();
    plan[2][1] = bogus;
    const ValidationReport report = validate(instance, plan);
    ASSERT_TRUE(report.has(Kind::kBlockedCell)) << bogus;
    EXPECT_FALSE(report.ok());
  }
}

TEST_F(ValidatorTest, ConflictsAreFoundAtEveryStepNotOnlyTheFirst) {
  // Both agents on one cell at t=2 and again at t=4; the per-step tables must be reset between.
  Solution plan = valid_plan();
  plan[2][1] = at(2, 0);
  plan[4][1] = at(2, 0);
  const ValidationReport report = validate(instance, plan);
  int conflicts = 0;
  for (const Violation& v : report.violations) conflicts += v.kind == Kind::kVertexConflict ? 1 : 0;
  EXPECT_EQ(conflicts, 2) << report.summary();
}

TEST_F(ValidatorTest, Jump) {
  Solution plan = valid_plan();
  plan[1][0] = at(2, 0);
  const ValidationReport report = validate(instance, plan);
  ASSERT_TRUE(report.has(Kind::kJump));
  EXPECT_EQ(report.violations.front().agent, 0);
  EXPECT_EQ(report.violations.front().time, 1);
}

TEST_F(ValidatorTest, VertexConflict) {
  Solution plan = valid_plan();
  plan[2][0] = at(3, 0);  // agent 0 "arrives" on agent 1's cell (and jumps; both are reported)
  const ValidationReport report = validate(instance, plan);
  ASSERT_TRUE(report.has(Kind::kVertexConflict));
}

TEST_F(ValidatorTest, SwapConflict) {
  const Instance corridor = testing::make_instance({"..."}, {{{0, 0}, {1, 0}}, {{1, 0}, {0, 0}}});
  const Vertex a = corridor.graph->vertex_at({0, 0}), b = corridor.graph->vertex_at({1, 0});
  const ValidationReport report = validate(corridor, {{a, b}, {b, a}});
  ASSERT_TRUE(report.has(Kind::kSwapConflict));
  EXPECT_EQ(report.violations.front().time, 1);
  EXPECT_EQ(report.violations.front().agent, 0);
  EXPECT_EQ(report.violations.front().other, 1);
}

TEST_F(ValidatorTest, NotOnGoal) {
  Solution plan = valid_plan();
  plan.pop_back();
  const ValidationReport report = validate(instance, plan);
  ASSERT_TRUE(report.has(Kind::kNotOnGoal));
  EXPECT_EQ(report.violations.front().agent, 0);
}

TEST_F(ValidatorTest, TaskMissed) {
  const Solution plan = {{at(0, 0), at(4, 0)}, {at(1, 0), at(3, 0)}, {at(2, 0), at(3, 0)}};
  const ValidationReport report = validate(instance, plan);
  ASSERT_TRUE(report.has(Kind::kTaskMissed));
  EXPECT_EQ(report.violations.front().other, 0);  // the task id
}

TEST_F(ValidatorTest, RotationOnlyWhenForbidden) {
  // Four agents turn around a 2x2 block in one step: allowed by FORMATS.md, not for robots.
  const Instance square = testing::make_instance({"..", ".."}, {{{0, 0}, {1, 0}}, {{1, 0}, {1, 1}}, {{1, 1}, {0, 1}},
                                                                  {{0, 1}, {0, 0}}});
  const auto v = [&](int x, int y) { return square.graph->vertex_at({x, y}); };
  const Solution plan = {{v(0, 0), v(1, 0), v(1, 1), v(0, 1)}, {v(1, 0), v(1, 1), v(0, 1), v(0, 0)}};
  EXPECT_TRUE(validate(square, plan).ok());
  const ValidationReport strict = validate(square, plan, {true});
  ASSERT_TRUE(strict.has(Kind::kRotation));
  EXPECT_EQ(strict.violations.size(), 1u);
  EXPECT_EQ(strict.violations.front().time, 1);
}

TEST_F(ValidatorTest, AFirstStretchNeedNotEndOnGoalsNorVisitTasksButKeepsEveryOtherRule) {
  const Solution plan = valid_plan();
  const Solution stretch(plan.begin(), plan.begin() + 2);  // agent 0 at (1,0), its task not visited yet
  EXPECT_TRUE(validate(instance, stretch).has(Kind::kNotOnGoal));
  EXPECT_TRUE(validate(instance, stretch).has(Kind::kTaskMissed));
  ValidationOptions first_stretch;
  first_stretch.first_stretch = true;
  EXPECT_TRUE(validate(instance, stretch, first_stretch).ok()) << validate(instance, stretch, first_stretch).summary();
  Solution conflict = stretch;
  conflict[1][1] = at(1, 0);  // both on (1,0): still refused
  EXPECT_TRUE(validate(instance, conflict, first_stretch).has(Kind::kVertexConflict));
}

}  // namespace
}  // namespace planner_core
