// Cross-checks planner_core's validator and lower bound against the independent checker
// ../shared/tools/ctsval.py on a few hundred solutions: the solver's own plans and mutated ones.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <unistd.h>

#include "planner_core/instance_generator.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/validator.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

namespace fs = std::filesystem;
using CellPlan = std::vector<std::vector<Cell>>;

std::string ctsval_path() {
  const std::string shared = std::string(CTSFLEET_SHARED_DIR) + "/tools/ctsval.py";
  return fs::exists(shared) ? shared : testing::data_path("ctsval.py");
}

std::string plan_text(const CellPlan& plan) {
  std::ostringstream out;
  out << "solver=test\nsolution=\n";
  for (size_t t = 0; t < plan.size(); ++t) {
    out << t << ":";
    for (Cell c : plan[t]) out << "(" << c.x << "," << c.y << "),";
    out << "\n";
  }
  return out.str();
}

CellPlan to_cells(const Graph& graph, const Solution& solution) {
  CellPlan plan;
  for (const Config& config : solution) {
    plan.emplace_back();
    for (Vertex v : config) plan.back().push_back(graph.cell_of(v));
  }
  return plan;
}

// Every agent walks a shortest path from start to goal, ignoring tasks and the others.
CellPlan naive_plan(const Instance& instance) {
  DistTable dist(*instance.graph);
  const Graph& graph = *instance.graph;
  Config at = instance.starts;
  Solution solution{at};
  for (bool moving = true; moving;) {
    moving = false;
    for (int a = 0; a < instance.agent_count(); ++a) {
      if (at[a] == instance.goals[a]) continue;
      for (Vertex u : graph.neighbours(at[a])) {
        if (dist.get(instance.goals[a], u) < dist.get(instance.goals[a], at[a])) {
          at[a] = u;
          break;
        }
      }
      moving = true;
    }
    if (moving) solution.push_back(at);
  }
  return to_cells(graph, solution);
}

std::vector<CellPlan> mutations(const CellPlan& plan, const Graph& graph, std::mt19937& rng) {
  std::vector<CellPlan> out;
  const int T = static_cast<int>(plan.size());
  const int n = static_cast<int>(plan[0].size());
  const int mid = T / 2;
  if (n >= 2 && T > 2) {
    CellPlan swapped = plan;  // two agents trade places: jumps, maybe conflicts
    std::swap(swapped[mid][0], swapped[mid][1]);
    out.push_back(swapped);
    CellPlan stacked = plan;  // agent 1 on agent 0's cell
    stacked[mid][1] = stacked[mid][0];
    out.push_back(stacked);
  }
  if (T > 4) {
    out.push_back(CellPlan(plan.begin(), plan.end() - 3));  // cut short
    CellPlan skipped = plan;
    skipped.erase(skipped.begin() + mid);
    out.push_back(skipped);
  }
  CellPlan walled = plan;  // onto a wall or off the map
  Cell wall{-1, 0};
  for (int y = 0; y < graph.height() && wall.x < 0; ++y) {
    for (int x = 0; x < graph.width(); ++x) {
      if (!graph.is_free({x, y})) {
        wall = {x, y};
        break;
      }
    }
  }
  walled[std::uniform_int_distribution<int>(0, T - 1)(rng)][std::uniform_int_distribution<int>(0, n - 1)(rng)] = wall;
  out.push_back(walled);
  return out;
}

TEST(CtsvalCrossCheck, ValidatorAndLowerBoundAgreeOnHundredsOfSolutions) {
  const std::string python = CTSFLEET_PYTHON;
  if (python.empty() || !fs::exists(python)) {
    GTEST_SKIP() << "\n\n*** python3 NOT FOUND: the cross-check against ctsval.py did not run ***\n\n";
  }
  const fs::path dir = fs::temp_directory_path() / ("ctsfleet-crosscheck-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::mt19937 rng(2024);
  const std::vector<std::string> maps = {"maps/random-32-32-20.map", "maps/maze-32-32-2.map", "maps/empty-32-32.map"};
  struct Case {
    std::string instance_file, solution_file;
    const Instance* instance;
  };
  std::vector<Instance> instances;
  instances.reserve(64);
  std::vector<Case> cases;
  for (int i = 0; i < 45; ++i) {
    const std::string map = testing::data_path(maps[i % maps.size()]);
    auto graph = std::make_shared<const Graph>(load_movingai_map(map));
    GeneratorSettings settings;
    settings.agents = i % 9 == 0 ? 2 : 3 + i % 12;  // some agents with more than 12 tasks
    settings.tasks = i % 9 == 0 ? 30 : (i * 7) % 31;
    settings.seed = 1000 + i;
    instances.push_back(generate_instance(graph, settings));
    const Instance& instance = instances.back();
    const std::string instance_file = (dir / ("i" + std::to_string(i) + ".yaml")).string();
    std::ofstream(instance_file) << instance_to_yaml(instance, map);

    SolverConfig config;
    config.solver = "cts-pibt-anytime";
    config.max_sequences = 3;
    const SolveResult result = make_solver(config)->solve(instance, {Deadline::in_seconds(10), {}});
    std::vector<CellPlan> plans{naive_plan(instance)};
    if (result.solved) {
      const CellPlan solved = to_cells(*graph, result.solution);
      plans.push_back(solved);
      for (CellPlan& m : mutations(solved, *graph, rng)) plans.push_back(std::move(m));
    }
    for (size_t k = 0; k < plans.size(); ++k) {
      const std::string solution_file = (dir / ("i" + std::to_string(i) + "-s" + std::to_string(k) + ".txt")).string();
      std::ofstream(solution_file) << plan_text(plans[k]);
      cases.push_back({instance_file, solution_file, &instance});
    }
  }
  ASSERT_GE(cases.size(), 200u);

  const fs::path list = dir / "cases.tsv";
  {
    std::ofstream out(list);
    for (const Case& c : cases) out << c.instance_file << "\t" << c.solution_file << "\n";
  }
  const std::string command = python + " " + testing::data_path("ctsval_batch.py") + " " + ctsval_path() + " < " +
                              list.string() + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  int feasible_seen = 0, infeasible_seen = 0;
  char line[4096];
  for (const Case& c : cases) {
    ASSERT_NE(fgets(line, sizeof line, pipe), nullptr) << "ctsval stopped early (is python3-yaml installed?)";
    int feasible = -1;
    long long flow = -1, lb = -1;
    int span = -1;
    ASSERT_EQ(std::sscanf(line, "%d %lld %d %lld", &feasible, &flow, &span, &lb), 4) << "ctsval said: " << line;

    const Instance& instance = *c.instance;
    const SolutionFile file = read_solution(c.solution_file, *instance.graph);
    const ValidationReport report = validate(instance, file.solution);
    EXPECT_EQ(report.ok(), feasible == 1) << c.solution_file << "\nours:\n" << report.summary();
    if (feasible == 1) {
      ++feasible_seen;
      EXPECT_EQ(report.flowtime, flow) << c.solution_file;
      EXPECT_EQ(report.makespan, span) << c.solution_file;
    } else {
      ++infeasible_seen;
    }
    DistTable dist(*instance.graph);
    const int64_t ours = tour_lower_bound(instance, dist, TaskOrderConfig{});
    int most_tasks = 0;
    for (const auto& tasks : instance.tasks_of_agent) most_tasks = std::max(most_tasks, static_cast<int>(tasks.size()));
    if (most_tasks <= 12) {
      EXPECT_EQ(ours, lb) << c.instance_file;
    } else {
      EXPECT_GE(ours, lb) << c.instance_file;  // exact up to our limit, both MST bounds beyond
    }
  }
  pclose(pipe);
  EXPECT_GT(feasible_seen, 30);
  EXPECT_GT(infeasible_seen, 100);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace planner_core
