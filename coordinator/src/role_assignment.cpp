#include "coordinator/role_assignment.hpp"

#include <limits>

namespace coordinator {

std::vector<int> min_cost_assignment(const std::vector<std::vector<int64_t>>& cost) {
  const int robots = static_cast<int>(cost.size());
  if (robots == 0) return {};
  const int roles = static_cast<int>(cost[0].size());
  if (robots > roles) {
    // Transpose: assign robots to roles from the roles' side.
    std::vector<std::vector<int64_t>> transposed(roles, std::vector<int64_t>(robots));
    for (int r = 0; r < robots; ++r) {
      for (int k = 0; k < roles; ++k) transposed[k][r] = cost[r][k];
    }
    const std::vector<int> robot_of_role = min_cost_assignment(transposed);
    std::vector<int> role_of_robot(robots, -1);
    for (int k = 0; k < roles; ++k) role_of_robot[robot_of_role[k]] = k;
    return role_of_robot;
  }
  // Hungarian method with potentials (rows = robots <= columns = roles), 1-based internally.
  const int64_t inf = std::numeric_limits<int64_t>::max() / 4;
  std::vector<int64_t> u(robots + 1, 0), v(roles + 1, 0);
  std::vector<int> match(roles + 1, 0), way(roles + 1, 0);
  for (int i = 1; i <= robots; ++i) {
    match[0] = i;
    int j0 = 0;
    std::vector<int64_t> min_v(roles + 1, inf);
    std::vector<char> used(roles + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = match[j0];
      int64_t delta = inf;
      int j1 = 0;
      for (int j = 1; j <= roles; ++j) {
        if (used[j]) continue;
        const int64_t current = cost[i0 - 1][j - 1] - u[i0] - v[j];
        if (current < min_v[j]) {
          min_v[j] = current;
          way[j] = j0;
        }
        if (min_v[j] < delta) {
          delta = min_v[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= roles; ++j) {
        if (used[j]) {
          u[match[j]] += delta;
          v[j] -= delta;
        } else {
          min_v[j] -= delta;
        }
      }
      j0 = j1;
    } while (match[j0] != 0);
    do {
      const int j1 = way[j0];
      match[j0] = match[j1];
      j0 = j1;
    } while (j0);
  }
  std::vector<int> role_of_robot(robots, -1);
  for (int j = 1; j <= roles; ++j) {
    if (match[j]) role_of_robot[match[j] - 1] = j - 1;
  }
  return role_of_robot;
}

}  // namespace coordinator
