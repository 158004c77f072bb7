#include "planner_core/lacam_solver.hpp"

#include <algorithm>
#include <chrono>
#include <optional>
#include <random>
#include <stdexcept>

#include "planner_core/guided_distances.hpp"
#include "planner_core/scatter.hpp"
#include "planner_core/turned_solver.hpp"
#include "planner_core/turning_execution.hpp"
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

// Searches from every goal until they reach its agent's start (the first node needs each agent's
// distance), on every core, looking at the clock between goals. False, with the reason in
// `result`, when the deadline came first.
bool prepare_distances_to_goals(const Instance& instance, DistTable& dist, const Deadline& deadline,
                                Clock::time_point started, SolveResult& result) {
  std::vector<DistTable::Query> to_goals;
  for (int a = 0; a < instance.agent_count(); ++a) to_goals.push_back({instance.goals[a], instance.starts[a]});
  if (dist.prepare(to_goals, deadline)) return true;
  result.failure_reason = "deadline reached while computing distances to the goals";
  result.preprocessing_ms = result.comp_time_ms = elapsed_ms(started);
  return false;
}

}  // namespace

Headings start_headings_of(const Instance& instance) {
  Headings headings(instance.agent_count());
  for (int a = 0; a < instance.agent_count(); ++a) headings[a] = instance.start_heading(a);
  return headings;
}

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
  if (instance.actions == ActionModel::kRotate) return solve_with_turns(instance, options);
  std::mt19937 rng(config_.seed);
  const std::vector<std::vector<int>> no_tasks(instance.agent_count());
  if (!prepare_distances_to_goals(instance, dist, deadline, started, result)) return result;
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

namespace {
// LaCAM in the rotation model: the share of the time left after the turned plan that the search
// over cell and heading gets for its first plan (when it finds one, it took 5-520 ms on the plain
// MAPF suite; on its crowded maps it found none in 10 s).
constexpr double kFirstPlanWithTurnsShare = 0.25;
}  // namespace

SolveResult LacamSolver::solve_with_turns(const Instance& instance, const SolveOptions& options) {
  const Clock::time_point started = options.started;
  const Deadline& deadline = options.deadline;
  GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
  // Turns added only (--turns added, or too many goals to hold their tables): a four-way LaCAM(*)
  // plan carried out with turns, as for every other solver (turned_solver.hpp).
  if (!config_.plan_with_turns || !turning_tables_fit(instance, turning)) {
    TurnedSolver turned(std::make_unique<LacamSolver>(config_, refine_), config_);
    return turned.solve(instance, options);
  }
  SolveResult result;
  DistTable dist(*instance.graph);
  // The four-way distances to the goals (on both cores) first; the goals' tables with turns (and
  // the bound with turns they give) after the turned plan, which does not need them.
  if (!prepare_distances_to_goals(instance, dist, deadline, started, result)) return result;
  int64_t four_way_bound = 0;
  for (int a = 0; a < instance.agent_count(); ++a) four_way_bound += dist.get(instance.goals[a], instance.starts[a]);
  result.lower_bound = four_way_bound;
  result.preprocessing_ms = elapsed_ms(started);
  const std::vector<std::vector<int>> no_tasks(instance.agent_count());

  // Turns added to a four-way plan: every four-way plan can be carried out with turns (unless its
  // agents move in a cycle and cycles are forbidden), so this is as sure to find a plan as four-way
  // LaCAM, and quick; the search over cell and heading fails on crowded maps more often.
  bool cycles = false;
  if (config_.add_turns) {
    // The same search and random numbers as four-way LaCAM's first plan (and as --turns added).
    const LacamConfig four_way_config{false, config_.forbid_rotations, /*swap=*/true, /*prefer_free_cells=*/true};
    std::mt19937 four_way_rng(config_.seed);
    Lacam four_way(*instance.graph, dist, four_way_config, four_way_rng);
    const LacamResult planned = four_way.solve(instance.starts, instance.goals, {}, deadline);
    const std::optional<TurningPlan> turned =
        planned.solved ? execute_with_turns(instance, planned.solution, !config_.forbid_rotations) : std::nullopt;
    cycles = planned.solved && !turned;
    if (turned) {
      keep_if_better(result, instance, turned->cells, no_tasks, 0, started, options, "LaCAM (turned)", turned->headings);
    }
  }
  const auto finish = [&](const LacamResult& searched) {
    if (!result.solved) {
      result.failure_reason = searched.exhausted ? "no solution exists (LaCAM searched every reachable configuration)"
                              : cycles ? "the four-way plan has agents moving in a cycle, which robots that turn cannot follow"
                                       : "deadline reached before LaCAM found a solution";
    }
    result.sequences_tried = 1;
    result.comp_time_ms = elapsed_ms(started);
    return result;
  };
  result.lower_bound = turning_lower_bound(instance, turning, config_.task_order, four_way_bound, deadline);
  // The search over cell and heading. Where it finds a plan it is the cheaper one (a fifth less
  // flowtime on the plain MAPF suite's open maps, docs/RESULTS.md), but on crowded maps it often
  // finds none: with a turned plan in hand it gets kFirstPlanWithTurnsShare of the time left.
  LacamConfig lacam_config{refine_, config_.forbid_rotations, /*swap=*/false, /*prefer_free_cells=*/true};
  lacam_config.turning = &turning;
  std::mt19937 rng(config_.seed);  // its own: the same plan with or without the turned one
  LacamSearch search(*instance.graph, dist, lacam_config, rng, instance.starts, instance.goals, {}, {},
                     start_headings_of(instance));
  const LacamResult found =
      search.run(result.solved ? deadline.slice(kFirstPlanWithTurnsShare * deadline.budget_left_s()) : deadline);
  if (found.solved) {
    keep_if_better(result, instance, found.solution, no_tasks, 0, started, options, "LaCAM with turns", found.headings);
  }
  if (!refine_ || !result.solved) return finish(found);
  if (found.solved) {
    // LaCAM*: the search goes on between LNS rounds with turns on the best plan of either kind.
    refine_until_deadline(instance, dist, search, found.exhausted, config_, rng, no_tasks, 0, options, result,
                          "LaCAM* with turns", &turning);
  } else {
    // No plan with turns: LaCAM* refines four-way plans for the rest of the time, the best turned
    // at the end (the way every four-way solver plans for robots that turn).
    SolveOptions rest = options;
    rest.on_solution = nullptr;  // its plans are reported here, when cheaper
    TurnedSolver turned_solver(std::make_unique<LacamSolver>(config_, refine_), config_);
    turned_solver.use_turning_tables(turning, result.lower_bound);
    const SolveResult turned = turned_solver.solve(instance, rest);
    result.lns_iterations += turned.lns_iterations;
    if (turned.solved) {
      keep_if_better(result, instance, turned.solution, no_tasks, 0, started, options, "LaCAM* (turned)",
                     turned.headings);
    }
  }
  return finish(found);
}

void refine_until_deadline(const Instance& instance, DistTable& dist, LacamSearch& search, bool search_done,
                           const SolverConfig& config, std::mt19937& rng, const std::vector<std::vector<int>>& orders,
                           int sequence_index, const SolveOptions& options, SolveResult& result,
                           const std::string& name, GuidedDistances* turning) {
  const Deadline& deadline = options.deadline;
  LnsConfig lns_config = config.lns;
  lns_config.search.forbid_rotations = lns_config.search.forbid_rotations || config.forbid_rotations;
  lns_config.stall_iterations = 0;  // the slice ends it
  LnsRefiner refiner(instance, dist, lns_config, rng);
  double search_slice_s = kFirstSearchSliceS;
  // The refiner's own plan: it accepts changes of equal cost too, so it is not always the one
  // kept in `result`; handing it back lets the refiner go on without rebuilding its tables.
  Solution refined = result.solution;
  HeadingPlan refined_headings = result.headings;
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
  const auto keep_timed = [&](const Solution& plan, const HeadingPlan& headings, const std::string& by) {
    const Clock::time_point begin = Clock::now();
    keep_if_better(result, instance, plan, orders, sequence_index, options.started, options, by, headings);
    if (clocked) unclocked_s = std::max(unclocked_s, std::chrono::duration<double>(Clock::now() - begin).count());
  };
  while (deadline.budget_left_s() > unclocked_s && result.flowtime > result.lower_bound) {
    if (!search_done) {
      const Deadline search_deadline = slice(search_slice_s);
      const LacamResult found = search.run(search_deadline);
      search_done = found.exhausted;
      const bool cheaper = found.solved && flowtime(found.solution, instance.goals) < result.flowtime;
      if (cheaper) {
        keep_timed(found.solution, found.headings, name);
        refined = result.solution;
        refined_headings = result.headings;
      }
      measure_overrun(search_deadline);
      search_slice_s = std::clamp(search_slice_s * (cheaper ? 2.0 : 0.5), kMinSearchSliceS, kMaxSearchSliceS);
      if (search_done && optimal_when_exhausted) break;
      if (deadline.budget_left_s() <= unclocked_s) break;
    }
    if (plain_mapf && !turning && config.recursive_lacam_rate > 0 &&
        std::uniform_real_distribution<double>(0, 1)(rng) < config.recursive_lacam_rate) {
      const Deadline recursion_deadline = slice(kRefinerSliceS);
      const Solution spliced =
          replan_tail(instance, dist, result.solution, config.forbid_rotations, rng, recursion_deadline);
      if (!spliced.empty() && flowtime(spliced, instance.goals) < result.flowtime) {
        keep_timed(spliced, {}, name + " recursive LaCAM");
        refined = result.solution;
      }
      measure_overrun(recursion_deadline);
      continue;
    }
    const Deadline refiner_deadline = slice(kRefinerSliceS);
    const LnsStats stats = turning ? refiner.refine_with_turns(refined, refined_headings, orders, turning, refiner_deadline)
                                   : refiner.refine(refined, orders, refiner_deadline);
    result.lns_iterations += stats.iterations;
    keep_timed(refined, refined_headings, name + " refiner");
    measure_overrun(refiner_deadline);
  }
}

}  // namespace planner_core
