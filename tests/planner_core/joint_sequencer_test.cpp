#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <set>

#include "planner_core/joint_sequencer.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

Instance three_agents() {
  return testing::make_instance({"........", "..@@....", "........", "....@...", "........"},
                                {{{0, 0}, {7, 4}}, {{7, 0}, {0, 4}}, {{3, 2}, {5, 0}}},
                                {{{2, 0}, {0, 1}}, {{6, 2}, {0}}, {{1, 4}, {1, 2}}, {{7, 2}, {1}}, {{0, 2}, {2}},
                                 {{5, 4}, {0, 2}}});
}

TEST(JointSequencer, EnumeratesAllCombinationsInNonDecreasingCostWithoutDuplicates) {
  const Instance instance = three_agents();
  DistTable dist(*instance.graph);
  // Brute force: every per-agent order cost, every combination.
  std::vector<std::vector<int>> per_agent_costs(instance.agent_count());
  for (int a = 0; a < instance.agent_count(); ++a) {
    KBestOrders orders(instance, a, dist, TaskOrderConfig{});
    for (int k = 0; orders.get(k); ++k) per_agent_costs[a].push_back(orders.get(k)->cost);
  }
  std::vector<int64_t> expected;
  for (int c0 : per_agent_costs[0]) {
    for (int c1 : per_agent_costs[1]) {
      for (int c2 : per_agent_costs[2]) expected.push_back(c0 + c1 + c2);
    }
  }
  std::sort(expected.begin(), expected.end());

  JointSequencer sequencer(instance, dist, TaskOrderConfig{});
  std::vector<int64_t> produced;
  std::set<std::vector<std::vector<int>>> seen;
  while (auto sequence = sequencer.next()) {
    EXPECT_EQ(sequence->index, static_cast<int>(produced.size()));
    EXPECT_TRUE(seen.insert(sequence->orders).second) << "duplicate joint sequence " << sequence->index;
    int64_t cost = 0;
    for (int a = 0; a < instance.agent_count(); ++a) cost += sequencer.orders_of(a).get(sequence->ranks[a])->cost;
    EXPECT_EQ(cost, sequence->cost);
    produced.push_back(sequence->cost);
  }
  EXPECT_EQ(produced, expected);
  EXPECT_EQ(sequencer.lower_bound(), expected.front());
}

TEST(JointSequencer, ThousandSequencesOfDenseInstance) {
  const Instance instance = load_instance(testing::data_path("instances/maze-32-32-2-N50-M60-00.yaml"));
  DistTable dist(*instance.graph);
  JointSequencer sequencer(instance, dist, TaskOrderConfig{});
  int64_t previous = 0;
  std::set<std::vector<int>> seen;
  for (int i = 0; i < 1000; ++i) {
    const auto sequence = sequencer.next();
    ASSERT_TRUE(sequence.has_value());
    EXPECT_GE(sequence->cost, previous);
    EXPECT_TRUE(seen.insert(sequence->ranks).second);
    previous = sequence->cost;
  }
}

}  // namespace
}  // namespace planner_core
