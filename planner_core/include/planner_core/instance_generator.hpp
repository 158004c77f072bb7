// Instance generator: random CTS-MAPF instances with the distribution of FORMATS.md
// (distinct starts, distinct goals, distinct task cells apart from starts and goals, each task
// given to k agents with k uniform in 1..min(kmax, N), every agent given a task when M >= N).
#pragma once

#include <cstdint>
#include <memory>

#include "planner_core/instance.hpp"

namespace planner_core {

struct GeneratorSettings {
  int agents = 10;
  int tasks = 20;
  int kmax = 3;
  uint32_t seed = 0;
};

// Throws InputError when the map's largest connected piece has too few cells.
Instance generate_instance(std::shared_ptr<const Graph> graph, const GeneratorSettings& settings);

}  // namespace planner_core
