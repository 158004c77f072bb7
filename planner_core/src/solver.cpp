#include "planner_core/solver.hpp"

#include <stdexcept>

#include "planner_core/cts_pibt.hpp"
#include "planner_core/cts_pll.hpp"
#include "planner_core/lacam_solver.hpp"

namespace planner_core {

std::vector<std::string> solver_names() { return {"cts-pibt", "cts-pibt-anytime", "cts-pll-v1", "cts-pll-v2", "cts-pll-v3", "lacam", "lacam-star"}; }

std::unique_ptr<Solver> make_solver(const SolverConfig& config) {
  if (config.solver == "cts-pibt") return std::make_unique<CtsPibt>(config, false);
  if (config.solver == "cts-pibt-anytime") return std::make_unique<CtsPibt>(config, true);
  if (config.solver == "cts-pll-v1") return std::make_unique<CtsPll>(config, CtsPll::Variant::kV1);
  if (config.solver == "cts-pll-v2") return std::make_unique<CtsPll>(config, CtsPll::Variant::kV2);
  if (config.solver == "cts-pll-v3") return std::make_unique<CtsPll>(config, CtsPll::Variant::kV3);
  if (config.solver == "lacam") return std::make_unique<LacamSolver>(config, false);
  if (config.solver == "lacam-star") return std::make_unique<LacamSolver>(config, true);
  std::string known;
  for (const std::string& name : solver_names()) known += (known.empty() ? "" : ", ") + name;
  throw std::invalid_argument("unknown solver '" + config.solver + "' (known: " + known + ")");
}

}  // namespace planner_core
