#include "planner_core/solver.hpp"

#include <stdexcept>

#include "planner_core/cts_pibt.hpp"

namespace planner_core {

std::vector<std::string> solver_names() { return {"cts-pibt", "cts-pibt-anytime"}; }

std::unique_ptr<Solver> make_solver(const SolverConfig& config) {
  if (config.solver == "cts-pibt") return std::make_unique<CtsPibt>(config, false);
  if (config.solver == "cts-pibt-anytime") return std::make_unique<CtsPibt>(config, true);
  std::string known;
  for (const std::string& name : solver_names()) known += (known.empty() ? "" : ", ") + name;
  throw std::invalid_argument("unknown solver '" + config.solver + "' (known: " + known + ")");
}

}  // namespace planner_core
