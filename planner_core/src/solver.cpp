#include "planner_core/solver.hpp"

#include <stdexcept>

#include "planner_core/cts_lacam.hpp"
#include "planner_core/cts_pibt.hpp"
#include "planner_core/cts_pll.hpp"
#include "planner_core/lacam_solver.hpp"
#include "planner_core/turned_solver.hpp"
#include "planner_core/validator.hpp"

namespace planner_core {

void keep_if_better(SolveResult& result, const Instance& instance, const Solution& plan,
                    const std::vector<std::vector<int>>& orders, int sequence_index, Clock::time_point started,
                    const SolveOptions& options, const std::string& solver, const HeadingPlan& headings) {
  const int64_t cost = flowtime(plan, instance.goals);
  if (result.solved && cost >= result.flowtime) return;
  const ValidationReport report = validate(instance, plan, {}, headings);
  if (!report.ok()) throw std::logic_error(solver + " produced an invalid plan:\n" + report.summary());
  result.solved = true;
  result.solution = plan;
  result.headings = headings;
  result.orders = orders;
  result.flowtime = cost;
  result.makespan = report.makespan;
  result.sum_of_loss = sum_of_loss(plan, instance.goals);
  const double now = elapsed_ms(started);
  if (result.first_solution_ms < 0) result.first_solution_ms = now;
  // The anytime LNS may already have logged this flowtime as it found it.
  if (result.improvements.empty() || result.improvements.back().flowtime > cost) {
    result.improvements.push_back({now, cost, sequence_index});
  }
  if (options.on_solution) options.on_solution(result);
}

std::vector<std::string> solver_names() { return {"cts-pibt", "cts-pibt-anytime", "cts-pll-v1", "cts-pll-v2", "cts-pll-v3", "cts-lacam", "lacam", "lacam-star"}; }

bool plans_with_turns(const std::string& solver) {
  return solver == "cts-pibt" || solver == "cts-pibt-anytime" || solver == "cts-lacam" || solver == "lacam" ||
         solver == "lacam-star";
}

namespace {

std::unique_ptr<Solver> make_four_way_solver(const SolverConfig& config) {
  if (config.solver == "cts-pll-v1") return std::make_unique<CtsPll>(config, CtsPll::Variant::kV1);
  if (config.solver == "cts-pll-v2") return std::make_unique<CtsPll>(config, CtsPll::Variant::kV2);
  if (config.solver == "cts-pll-v3") return std::make_unique<CtsPll>(config, CtsPll::Variant::kV3);
  return nullptr;
}

}  // namespace

std::unique_ptr<Solver> make_solver(const SolverConfig& config) {
  if (config.solver == "cts-pibt") return std::make_unique<CtsPibt>(config, false);
  if (config.solver == "cts-pibt-anytime") return std::make_unique<CtsPibt>(config, true);
  if (config.solver == "cts-lacam") return std::make_unique<CtsLacam>(config);
  if (config.solver == "lacam") return std::make_unique<LacamSolver>(config, false);
  if (config.solver == "lacam-star") return std::make_unique<LacamSolver>(config, true);
  if (std::unique_ptr<Solver> four_way = make_four_way_solver(config)) {
    return std::make_unique<TurnedSolver>(std::move(four_way), config);
  }
  std::string known;
  for (const std::string& name : solver_names()) known += (known.empty() ? "" : ", ") + name;
  throw std::invalid_argument("unknown solver '" + config.solver + "' (known: " + known + ")");
}

}  // namespace planner_core
