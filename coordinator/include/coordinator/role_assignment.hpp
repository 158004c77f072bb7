// Role assignment: binds robots to the mission's roles (its agents). A robot standing on a free
// role's start takes that role; the others are matched to the free roles by minimum total
// distance (Hungarian method, O(n^3)).
#pragma once

#include <cstdint>
#include <vector>

namespace coordinator {

// cost[r][k]: cost of giving role k to robot r. Returns, per robot, its role or -1 (when there
// are more robots than roles). Minimises the total cost over the assigned pairs.
std::vector<int> min_cost_assignment(const std::vector<std::vector<int64_t>>& cost);

}  // namespace coordinator
