#include <gtest/gtest.h>

#include <set>

#include "planner_core/input_error.hpp"
#include "planner_core/instance_generator.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

TEST(Generator, FollowsTheSuiteDistribution) {
  auto graph = std::make_shared<const Graph>(load_movingai_map(testing::data_path("maps/random-32-32-20.map")));
  for (uint32_t seed = 0; seed < 20; ++seed) {
    const GeneratorSettings settings{20, 40, 3, seed};
    const Instance instance = generate_instance(graph, settings);
    ASSERT_EQ(instance.agent_count(), 20);
    ASSERT_EQ(instance.task_count(), 40);
    const std::set<Vertex> starts(instance.starts.begin(), instance.starts.end());
    const std::set<Vertex> goals(instance.goals.begin(), instance.goals.end());
    EXPECT_EQ(starts.size(), 20u);
    EXPECT_EQ(goals.size(), 20u);
    std::set<Vertex> task_cells;
    for (const Task& task : instance.tasks) {
      EXPECT_TRUE(task_cells.insert(task.at).second);
      EXPECT_FALSE(starts.count(task.at) || goals.count(task.at));
      EXPECT_GE(task.agents.size(), 1u);
      EXPECT_LE(task.agents.size(), 4u);  // k <= kmax, plus the guaranteed agent
    }
    for (int a = 0; a < 20; ++a) EXPECT_FALSE(instance.tasks_of_agent[a].empty()) << "agent " << a;
    EXPECT_NO_THROW(check_reachability(instance));
  }
}

TEST(Generator, SameSeedSameInstance) {
  auto graph = std::make_shared<const Graph>(load_movingai_map(testing::data_path("maps/maze-32-32-2.map")));
  const Instance a = generate_instance(graph, {10, 15, 3, 99});
  const Instance b = generate_instance(graph, {10, 15, 3, 99});
  EXPECT_EQ(a.starts, b.starts);
  EXPECT_EQ(a.goals, b.goals);
  EXPECT_EQ(a.tasks_of_agent, b.tasks_of_agent);
}

TEST(Generator, TooManyAgentsForTheMapIsAnInputError) {
  auto graph = testing::grid_from_rows({"...", "..."});
  EXPECT_THROW(generate_instance(graph, {4, 1, 3, 0}), InputError);
}

}  // namespace
}  // namespace planner_core
