// ctsfleet-solve: solves one CTS-MAPF instance (or MovingAI .scen) and writes a validated solution.
#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "ctsfleet/program.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/solver.hpp"
#include "solver_options.hpp"
#include "planner_core/svg_writer.hpp"
#include "planner_core/validator.hpp"

namespace {

// The most memory this process has held so far.
double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

std::string join(const std::vector<int>& values) {
  std::string out;
  for (size_t i = 0; i < values.size(); ++i) out += (i ? "," : "") + std::to_string(values[i]);
  return out;
}

// "(x,y),(x,y)," as lacam writes its starts= and goals= lines.
std::string cells_text(const planner_core::Graph& graph, const std::vector<planner_core::Vertex>& vertices) {
  std::string out;
  for (planner_core::Vertex v : vertices) {
    const planner_core::Cell c = graph.cell_of(v);
    out += "(" + std::to_string(c.x) + "," + std::to_string(c.y) + "),";
  }
  return out;
}

// Checking and writing the plan come after the solver returns, inside the user's time limit:
// measured at about 60 ns per agent and step (0.3 s for 10,000 agents over 595 steps on
// warehouse-20-40-10-2-2), and a plan lasts about as many steps as the map is wide and high.
// At most a tenth of the limit is held back for it.
double output_reserve_s(const planner_core::Instance& instance, double limit_s) {
  constexpr double kOutputSecondsPerAgentStep = 60e-9;
  const double steps = instance.graph->width() + instance.graph->height();
  return std::min(0.1 * limit_s, kOutputSecondsPerAgentStep * instance.agent_count() * steps);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace planner_core;
  ctsfleet::Program program("ctsfleet-solve",
                            "plan collision-free paths for agents that must visit their tasks and end on their goals");
  CLI::App& app = program.app();
  std::string instance_path, out_path = "solution.txt", svg_path, map;
  int scen_agents = 0;
  double seconds = 10;
  int64_t iterations = 0;
  bool verbose = false, json = false;
  SolverConfig config;
  std::string actions = "move4";
  app.add_option("-i,--instance", instance_path, "instance: CTS-MAPF .yaml or MovingAI .scen")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("-N,--agents", scen_agents, "number of agents taken from a .scen (first N rows; default all)")
      ->check(ctsfleet::count_in(1, 10'000'000));
  app.add_option("--map", map, ".scen only: the map file, or a folder to look for the map the .scen names")
      ->check(CLI::ExistingPath);
  app.add_option("-t,--time", seconds, "time limit in seconds")
      ->check(ctsfleet::positive_seconds(kMaxTimeLimitS))
      ->capture_default_str();
  app.add_option("-o,--output", out_path, "solution file to write")->check(ctsfleet::writable_file())->capture_default_str();
  app.add_option("--solver", config.solver, "solver variant")
      ->check(CLI::IsMember(solver_names()))
      ->capture_default_str();
  app.add_option("--seed", config.seed, "random seed")->capture_default_str();
  app.add_option("--actions", actions,
                 "how robots move: move4 (a step to any neighbour) or rotate (forward, quarter turn or wait, each "
                 "one step; headings from the instance's 'heading' fields, east when absent; cts-pibt and "
                 "cts-pibt-anytime plan with turns, the others plan four-way moves to which turns are added)")
      ->check(CLI::IsMember({"move4", "rotate"}))
      ->capture_default_str();
  std::string turns = "both";
  app.add_option("--turns", turns,
                 "cts-pibt*, cts-lacam and lacam* with --actions rotate: 'planned' (Extended-PIBT, or LaCAM over "
                 "cell and heading, plans with turns), 'added' (four-way plans, turns added as robots would carry "
                 "them out) or 'both', keeping the cheaper; to measure each")
      ->check(CLI::IsMember({"both", "planned", "added"}))
      ->capture_default_str();
  app.add_option("--svg", svg_path, "also draw the plan as an SVG picture")->check(ctsfleet::writable_file());
  app.add_option("--exact-task-limit", config.task_order.exact_task_limit,
                 "Held-Karp task ordering up to this many tasks per agent")
      ->check(ctsfleet::count_in(0, 16))
      ->capture_default_str();
  app.add_option("--step-limit-factor", config.pibt.step_limit_factor,
                 "Extended-PIBT gives up after this multiple of the longest single-agent tour")
      ->check(ctsfleet::number_in(1, 1000))
      ->capture_default_str();
  app.add_option("--max-sequences", config.max_sequences, "anytime: stop after this many joint sequences (0 = none)")
      ->check(ctsfleet::count_in(0, 1'000'000'000));
  add_iterations_option(app, iterations);
  app.add_flag("--no-fallback{false}", config.complete_fallback,
               "CTS solvers: no complete search when their own method runs out (to study a method alone)");
  add_solver_part_options(app, config);
  app.add_option("--lns-neighbourhood", config.lns.neighbourhood_size, "LNS (cts-pll-v3, lacam-star): agents replanned at once")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_flag("-v,--verbose", verbose, "print each improvement as it is found (on stderr)");
  app.add_flag("--json", json, "print the summary as one JSON object instead of key=value words");
  return program.main(argc, argv, [&] {
    // The time limit and every reported time count from here, before the instance is read.
    SolveOptions options{Deadline::in_seconds(seconds, &ctsfleet::stop_requested()), {}, Clock::now()};
    Instance instance = [&] {
      const ctsfleet::StopsAtOnce reading("ctsfleet-solve", "reading " + instance_path);
      return load_instance(instance_path, scen_agents, map);
    }();
    instance.actions = parse_action_model(actions, "--actions");
    config.plan_with_turns = turns != "added";
    config.add_turns = turns != "planned";
    options.deadline = options.deadline.within(options.deadline.seconds_left() - output_reserve_s(instance, seconds));
    if (iterations > 0) options.deadline = options.deadline.with_work_budget(iterations * kWorkPerIteration);
    if (verbose) {
      options.on_solution = [](const SolveResult& r) {
        const Improvement& last = r.improvements.back();
        std::cerr << "  t=" << last.time_ms << "ms flowtime=" << last.flowtime << " (sequence " << last.sequence_index
                  << ")\n";
      };
    }
    const SolveResult result = make_solver(config)->solve(instance, options);
    // With --iterations the plan is the same on every run unless the clock (or Ctrl-C) ended the
    // solve first: the clock never goes back, so a deadline not reached now was never reached.
    const bool reproducible = iterations > 0 && options.deadline.seconds_left() > 0;

    SolutionFile file;
    const auto put = [&](const std::string& key, const auto& value) {
      std::ostringstream text;
      text << value;
      file.header.emplace_back(key, text.str());
    };
    put("instance", instance_path);
    put("solver", config.solver);
    put("agents", instance.agent_count());
    put("tasks", instance.task_count());
    put("seed", config.seed);
    if (instance.actions == ActionModel::kRotate) put("actions", actions);
    put("solver_version", ctsfleet::version_text());
    if (iterations > 0) put("iterations", iterations);
    put("solved", result.solved ? 1 : 0);
    if (result.solved) {
      const ValidationReport report =
          validate(instance, result.solution, ValidationOptions{config.forbid_rotations}, result.headings);
      if (!report.ok()) {
        std::cerr << "error: the solver's plan failed validation; nothing written\n" << report.summary();
        return ctsfleet::kExitInternalError;
      }
      put("flowtime", report.flowtime);
      put("soc", report.flowtime);  // lacam's name for the same sum
      put("makespan", report.makespan);
      put("sum_of_loss", result.sum_of_loss);
      file.solution = result.solution;
      file.headings = result.headings;
    }
    put("lower_bound", result.lower_bound);
    put("soc_lb", result.lower_bound);
    put("map_file", instance.graph->name + ".map");
    put("starts", cells_text(*instance.graph, instance.starts));
    put("goals", cells_text(*instance.graph, instance.goals));
    put("comp_time", static_cast<int64_t>(result.comp_time_ms));
    put("comp_time_ms", static_cast<int64_t>(result.comp_time_ms));
    put("comp_time_first_ms", static_cast<int64_t>(result.first_solution_ms));
    put("comp_time_preprocessing_ms", static_cast<int64_t>(result.preprocessing_ms));
    put("sequences", result.sequences_tried);
    put("lock_releases", result.lock_releases);
    put("lns_iterations", result.lns_iterations);
    if (!result.solved) put("failure", result.failure_reason);
    for (size_t a = 0; a < result.orders.size(); ++a) put("order_" + std::to_string(a), join(result.orders[a]));
    write_solution(out_path, *instance.graph, file);
    if (!svg_path.empty()) write_svg(svg_path, instance, result.solution);

    const double ratio =
        result.lower_bound > 0 && result.solved ? static_cast<double>(result.flowtime) / result.lower_bound : 0.0;
    const double memory_mb = peak_memory_mb();
    if (json) {
      nlohmann::json improvements = nlohmann::json::array();
      for (const Improvement& improvement : result.improvements) {
        improvements.push_back({{"time_ms", improvement.time_ms}, {"flowtime", improvement.flowtime}});
      }
      const nlohmann::json summary = {
          {"solver", config.solver}, {"seed", config.seed}, {"solver_version", ctsfleet::version_text()},
          {"iterations", iterations}, {"work", options.deadline.work_done()},
          {"reproducible", reproducible}, {"solved", result.solved}, {"agents", instance.agent_count()},
          {"tasks", instance.task_count()}, {"flowtime", result.flowtime}, {"makespan", result.makespan},
          {"lower_bound", result.lower_bound}, {"ratio", ratio}, {"comp_time_ms", result.comp_time_ms},
          {"first_ms", result.first_solution_ms}, {"preprocessing_ms", result.preprocessing_ms},
          {"peak_memory_mb", memory_mb}, {"sequences", result.sequences_tried}, {"releases", result.lock_releases},
          {"lns_iterations", result.lns_iterations}, {"output", out_path},
          {"failure", result.solved ? "" : result.failure_reason}, {"improvements", improvements}};
      std::printf("%s\n", summary.dump().c_str());
    } else {
      std::printf("solver=%s solved=%d agents=%d tasks=%d flowtime=%lld makespan=%d lower_bound=%lld ratio=%.3f "
                  "comp_time_ms=%.0f first_ms=%.1f preprocessing_ms=%.1f peak_memory_mb=%.0f sequences=%d "
                  "releases=%d lns_iterations=%d output=%s\n",
                  config.solver.c_str(), result.solved ? 1 : 0, instance.agent_count(), instance.task_count(),
                  static_cast<long long>(result.flowtime), result.makespan, static_cast<long long>(result.lower_bound),
                  ratio, result.comp_time_ms, result.first_solution_ms, result.preprocessing_ms, memory_mb,
                  result.sequences_tried, result.lock_releases, result.lns_iterations, out_path.c_str());
    }
    if (!result.solved) std::fprintf(stderr, "not solved: %s\n", result.failure_reason.c_str());
    if (!result.solved && reproducible && options.deadline.work_done() >= options.deadline.work_at) {
      std::fprintf(stderr, "the budget of --iterations %lld ran out first (raise it for a plan)\n",
                   static_cast<long long>(iterations));
    }
    if (iterations > 0 && !reproducible) {
      if (ctsfleet::stop_requested().load()) {
        std::fprintf(stderr, "warning: stopped before its %lld iterations: another run may give another plan\n",
                     static_cast<long long>(iterations));
      } else {
        std::fprintf(stderr, "warning: the time limit (-t %g) ended the solve before its %lld iterations: another run "
                             "may give another plan (raise -t)\n", seconds, static_cast<long long>(iterations));
      }
    }
    // Stopped by Ctrl-C or SIGTERM: 130, as every program (the best plan found so far, if any, is
    // written above, validated).
    if (ctsfleet::stop_requested().load()) return ctsfleet::kExitInterrupted;
    return result.solved ? 0 : 1;
  });
}
