#include <gtest/gtest.h>

#include "planner_core/input_error.hpp"
#include "planner_core/solution.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

TEST(SolutionIo, WritesAndReadsBack) {
  const Instance instance = testing::make_instance({"....", ".@.."}, {{{0, 0}, {3, 0}}, {{3, 1}, {2, 1}}});
  const auto v = [&](int x, int y) { return instance.graph->vertex_at({x, y}); };
  SolutionFile file;
  file.header = {{"solver", "cts-pibt"}, {"flowtime", "4"}, {"order_0", "3,1"}};
  file.solution = {{v(0, 0), v(3, 1)}, {v(1, 0), v(2, 1)}, {v(2, 0), v(2, 1)}, {v(3, 0), v(2, 1)}};
  const std::string text = format_solution(*instance.graph, file);
  EXPECT_NE(text.find("solution=\n0:(0,0),(3,1),\n1:(1,0),(2,1),"), std::string::npos) << text;
  const SolutionFile back = read_solution(testing::write_temp_file("io/ok.txt", text), *instance.graph);
  EXPECT_EQ(back.solution, file.solution);
  EXPECT_EQ(back.value("order_0"), "3,1");
  EXPECT_EQ(back.value("missing"), "");
  EXPECT_EQ(flowtime(back.solution, instance.goals), 3 + 1);
  EXPECT_EQ(makespan(back.solution, instance.goals), 3);
  EXPECT_EQ(sum_of_loss(back.solution, instance.goals), 3 + 1);
}

TEST(SolutionIo, BlockedCellsBecomeNoVertex) {
  const Instance instance = testing::make_instance({"..", ".@"}, {{{0, 0}, {1, 0}}});
  const SolutionFile file =
      read_solution(testing::write_temp_file("io/wall.txt", "solution=\n0:(0,0),\n1:(1,1),\n2:(5,-3),\n"),
                    *instance.graph);
  ASSERT_EQ(file.solution.size(), 3u);
  EXPECT_EQ(file.solution[1][0], kNoVertex);
  EXPECT_EQ(file.solution[2][0], kNoVertex);
}

TEST(SolutionIo, OutOfOrderTimestepNamesLine) {
  const Instance instance = testing::make_instance({".."}, {{{0, 0}, {1, 0}}});
  try {
    read_solution(testing::write_temp_file("io/gap.txt", "solved=1\nsolution=\n0:(0,0),\n2:(1,0),\n"), *instance.graph);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gap.txt:4"), std::string::npos) << e.what();
  }
}

TEST(SolutionIo, ACoordinatePastIntIsRefusedNamingTheLine) {
  const Instance instance = testing::make_instance({".."}, {{{0, 0}, {1, 0}}});
  try {
    read_solution(testing::write_temp_file("io/huge.txt", "solution=\n0:(0,0),\n1:(4294967296,0),\n"), *instance.graph);
    FAIL() << "a coordinate past int was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("huge.txt:3"), std::string::npos) << e.what();
  }
}

TEST(SolutionIo, MissingSolutionLine) {
  const Instance instance = testing::make_instance({".."}, {{{0, 0}, {1, 0}}});
  EXPECT_THROW(read_solution(testing::write_temp_file("io/none.txt", "solved=0\n"), *instance.graph), InputError);
}

}  // namespace
}  // namespace planner_core
