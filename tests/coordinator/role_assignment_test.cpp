#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "coordinator/role_assignment.hpp"

namespace coordinator {
namespace {

int64_t brute_force(const std::vector<std::vector<int64_t>>& cost) {
  const int robots = static_cast<int>(cost.size()), roles = static_cast<int>(cost[0].size());
  std::vector<int> columns(roles);
  std::iota(columns.begin(), columns.end(), 0);
  int64_t best = INT64_MAX;
  do {
    int64_t total = 0;
    if (robots <= roles) {
      for (int r = 0; r < robots; ++r) total += cost[r][columns[r]];
    } else {
      continue;
    }
    best = std::min(best, total);
  } while (std::next_permutation(columns.begin(), columns.end()));
  return best;
}

TEST(RoleAssignment, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const int robots = 1 + trial % 5, roles = robots + trial % 3;
    std::vector<std::vector<int64_t>> cost(robots, std::vector<int64_t>(roles));
    for (auto& row : cost) {
      for (auto& c : row) c = std::uniform_int_distribution<int>(0, 50)(rng);
    }
    const std::vector<int> assignment = min_cost_assignment(cost);
    int64_t total = 0;
    std::vector<int> used;
    for (int r = 0; r < robots; ++r) {
      ASSERT_GE(assignment[r], 0);
      total += cost[r][assignment[r]];
      used.push_back(assignment[r]);
    }
    std::sort(used.begin(), used.end());
    EXPECT_EQ(std::unique(used.begin(), used.end()), used.end()) << "a role given twice";
    EXPECT_EQ(total, brute_force(cost)) << "trial " << trial;
  }
}

TEST(RoleAssignment, MoreRobotsThanRolesLeavesTheCostliestOut) {
  const std::vector<std::vector<int64_t>> cost = {{5}, {1}, {9}};
  EXPECT_EQ(min_cost_assignment(cost), (std::vector<int>{-1, 0, -1}));
}

}  // namespace
}  // namespace coordinator
