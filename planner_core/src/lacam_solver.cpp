#include "planner_core/lacam_solver.hpp"

#include <algorithm>
#include <chrono>
#include <random>
#include <stdexcept>

#include "planner_core/scatter.hpp"
#include "planner_core/validator.hpp"

namespace planner_core {

namespace {

// LaCAM*'s time between its search and the LNS refiner: the search's share grows while it finds
// cheaper plans than the refiner's and shrinks while it does not (at scale it never does).
constexpr double kRefinerSliceS = 1.0;
constexpr double kFirstSearchSliceS = 0.25;
constexpr double kMinSearchSliceS = 0.02;
constexpr double kMaxSearchSliceS = 4.0;

// Of the time left after the first plan: at most kScatterTimeShare for the scatter paths, and as
// much again for the guided search's first plan.

// Agents' paths spread over the map, at most a quarter of the time left: LaCAM's first plan sends
// crowds down the same shortest corridors (warehouse aisles), and a search whose generator
// follows these paths finds a far cheaper plan (docs/results/HISTORY.md, section 6).
std::unique_ptr<Scatter> spread_out(const Instance& instance, DistTable& dist, uint32_t seed, const Deadline& deadline) {
  auto scatter = std::make_unique<Scatter>(*instance.graph, dist, instance.starts, instance.goals, kScatterMargin, seed);
  scatter->build(deadline.slice(deadline.budget_left_s() * kScatterTimeShare));
  return scatter;
}

// lacam3's recursive LaCAM: a fresh LaCAM from a configuration of `plan` picked at random, its plan
// spliced after the part of `plan` that led there. Returns the spliced plan, or an empty one when
// none was found in time.
Solution replan_tail(const Instance& instance, DistTable& dist, const Solution& plan, bool forbid_rotations,
                     std::mt19937& rng, const Deadline& deadline) {
  if (plan.size() < 4) return {};
  const size_t from = std::uniform_int_distribution<size_t>(1, plan.size() - 3)(rng);
  const LacamConfig config{/*refine=*/false, forbid_rotations, /*swap=*/true, /*prefer_free_cells=*/true};
  Lacam lacam(*instance.graph, dist, config, rng);
  const LacamResult found = lacam.solve(plan[from], instance.goals, {}, deadline);
  if (!found.solved) return {};
  Solution spliced(plan.begin(), plan.begin() + static_cast<std::ptrdiff_t>(from));
  spliced.insert(spliced.end(), found.solution.begin(), found.solution.end());
  return spliced;
}

}  // namespace

SolveResult LacamSolver::solve(const Instance& instance, const SolveOptions& options) {
  const Clock::time_point started = options.started;
  const Deadline& deadline = options.deadline;
  SolveResult result;
  DistTable dist(*instance.graph);
  if (instance.task_count() > 0) {
    result.failure_reason = "lacam solves plain MAPF; this instance has tasks (use a cts-* solver)";
    result.comp_time_ms = elapsed_ms(started);
    return result;
  }
  std::mt19937 rng(config_.seed);
  const std::vector<std::vector<int>> no_tasks(instance.agent_count());
  // The first node needs every agent's distance to its goal: the searches from the goals run at
  // least that far. Done here, on every core, looking at the clock between goals.
  std::vector<DistTable::Query> to_goals;
  for (int a = 0; a < instance.agent_count(); ++a) to_goals.push_back({instance.goals[a], instance.starts[a]});
  if (!dist.prepare(to_goals, deadline)) {
    result.failure_reason = "deadline reached while computing distances to the goals";
    result.preprocessing_ms = result.comp_time_ms = elapsed_ms(started);
    return result;
  }
  result.preprocessing_ms = elapsed_ms(started);
  const LacamConfig lacam_config{refine_, config_.forbid_rotations, /*swap=*/true, /*prefer_free_cells=*/true};
  std::unique_ptr<Scatter> scatter;  // guides `search` once set (declared first: outlives it)
  auto search = std::make_unique<LacamSearch>(*instance.graph, dist, lacam_config, rng, instance.starts, instance.goals);
  LacamResult found = search->run(deadline);
  result.sequences_tried = 1;
  if (!found.solved) {
    result.failure_reason = found.exhausted ? "no solution exists (LaCAM searched every reachable configuration)"
                                            : "deadline reached before LaCAM found a solution";
    result.comp_time_ms = elapsed_ms(started);
    return result;
  }
  keep_if_better(result, instance, found.solution, no_tasks, 0, started, options, "LaCAM");
  // Alongside the search: the searches from the goals have already reached every start.
  for (int a = 0; a < instance.agent_count(); ++a) result.lower_bound += dist.get(instance.goals[a], instance.starts[a]);

  if (refine_) {
    bool search_done = found.exhausted;
    if (config_.scatter && !found.exhausted && result.flowtime > result.lower_bound) {
      // The guided search is a LaCAM* search too (as complete: only its generator's first
      // choices differ), so it takes over; the first one goes, with its nodes (memory at 10,000
      // agents).
      search.reset();
      scatter = spread_out(instance, dist, config_.seed, deadline);
      LacamConfig guided = lacam_config;
      guided.guide = scatter.get();
      search = std::make_unique<LacamSearch>(*instance.graph, dist, guided, rng, instance.starts, instance.goals);
      found = search->run(deadline.slice(deadline.budget_left_s() * kScatterTimeShare));
      if (found.solved) keep_if_better(result, instance, found.solution, no_tasks, 0, started, options, "LaCAM along scatter");
      search_done = found.exhausted;
    }
    refine_until_deadline(instance, dist, *search, search_done, config_, rng, no_tasks, 0, options, result, "LaCAM*");
  }
  result.comp_time_ms = elapsed_ms(started);
  return result;
}

void refine_until_deadline(const Instance& instance, DistTable& dist, LacamSearch& search, bool search_done,
                           const SolverConfig& config, std::mt19937& rng, const std::vector<std::vector<int>>& orders,
                           int sequence_index, const SolveOptions& options, SolveResult& result,
                           const std::string& name) {
  const Deadline& deadline = options.deadline;
  LnsConfig lns_config = config.lns;
  lns_config.search.forbid_rotations = lns_config.search.forbid_rotations || config.forbid_rotations;
  lns_config.stall_iterations = 0;  // the slice ends it
  LnsRefiner refiner(instance, dist, lns_config, rng);
  double search_slice_s = kFirstSearchSliceS;
  // The refiner's own plan: it accepts changes of equal cost too, so it is not always the one
  // kept in `result`; handing it back lets the refiner go on without rebuilding its tables.
  Solution refined = result.solution;
  // An exhausted LaCAM* search has proved its plan optimal (for plain MAPF; for a joint sequence,
  // optimal among plans that follow it, which the refiner may still beat).
  const bool plain_mapf = instance.task_count() == 0;
  const bool optimal_when_exhausted = plain_mapf;
  if (search_done && optimal_when_exhausted) return;
  // Some steps cannot look at the clock: checking a plan found, loading it into the refiner,
  // writing the refiner's plan back (each O(agents x makespan), up to a second at 10,000 agents on
  // a loaded machine). The longest such stretch measured so far is held back from every slice, so
  // that the solver returns close to its deadline rather than one stretch after it.
  // With a work budget the shares are counted in work and nothing is held back (the same plan on
  // every run).
  double unclocked_s = 0;
  const bool clocked = !deadline.shares_in_work;
  const auto slice = [&](double seconds) {
    return deadline.slice(std::min(seconds, deadline.budget_left_s() - unclocked_s));
  };
  const auto measure_overrun = [&](const Deadline& slice_deadline) {
    if (!clocked) return;
    unclocked_s = std::max(unclocked_s, std::chrono::duration<double>(Clock::now() - slice_deadline.at).count());
  };
  const auto keep_timed = [&](const Solution& plan, const std::string& by) {
    const Clock::time_point begin = Clock::now();
    keep_if_better(result, instance, plan, orders, sequence_index, options.started, options, by);
    if (clocked) unclocked_s = std::max(unclocked_s, std::chrono::duration<double>(Clock::now() - begin).count());
  };
  while (deadline.budget_left_s() > unclocked_s && result.flowtime > result.lower_bound) {
    if (!search_done) {
      const Deadline search_deadline = slice(search_slice_s);
      const LacamResult found = search.run(search_deadline);
      search_done = found.exhausted;
      const bool cheaper = found.solved && flowtime(found.solution, instance.goals) < result.flowtime;
      if (cheaper) {
        keep_timed(found.solution, name);
        refined = result.solution;
      }
      measure_overrun(search_deadline);
      search_slice_s = std::clamp(search_slice_s * (cheaper ? 2.0 : 0.5), kMinSearchSliceS, kMaxSearchSliceS);
      if (search_done && optimal_when_exhausted) break;
      if (deadline.budget_left_s() <= unclocked_s) break;
    }
    if (plain_mapf && config.recursive_lacam_rate > 0 &&
        std::uniform_real_distribution<double>(0, 1)(rng) < config.recursive_lacam_rate) {
      const Deadline recursion_deadline = slice(kRefinerSliceS);
      const Solution spliced =
          replan_tail(instance, dist, result.solution, config.forbid_rotations, rng, recursion_deadline);
      if (!spliced.empty() && flowtime(spliced, instance.goals) < result.flowtime) {
        keep_timed(spliced, name + " recursive LaCAM");
        refined = result.solution;
      }
      measure_overrun(recursion_deadline);
      continue;
    }
    const Deadline refiner_deadline = slice(kRefinerSliceS);
    const LnsStats stats = refiner.refine(refined, orders, refiner_deadline);
    result.lns_iterations += stats.iterations;
    keep_timed(refined, name + " refiner");
    measure_overrun(refiner_deadline);
  }
}

}  // namespace planner_core
