// A lifelong run written as the league's output file: read back and replayed on its own, it is the
// run that was measured (every move legal, no two robots on a cell, every finished task where its
// robot stands); late and invalid steps are written as the league writes them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "planner_core/input_error.hpp"
#include "planner_core/lifelong.hpp"
#include "planner_core/lifelong_auto_rules.hpp"
#include "planner_core/pibt_lifelong.hpp"
#include "planner_core/lorr_output.hpp"
#include "planner_core/lorr_problem.hpp"

namespace planner_core {
namespace {

namespace fs = std::filesystem;

const std::string kRandom = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2023/random.domain/";

struct WrittenRun {
  fs::path path = fs::temp_directory_path() / ("ctsfleet-lorr-output-" + std::to_string(::getpid()) + ".json");
  ~WrittenRun() { fs::remove(path); }
  nlohmann::json read() const {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
  }
};

std::vector<std::string> split_actions(const std::string& path) {
  std::vector<std::string> actions;
  std::string action;
  for (char c : path) {
    if (c == ',') {
      actions.push_back(action);
      action.clear();
    } else {
      action += c;
    }
  }
  if (!path.empty()) actions.push_back(action);
  return actions;
}

TEST(LorrOutput, TheWrittenRunReplaysToTheRunMeasured) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_100.json");
  PibtLifelong planner(*problem.graph, 5);
  LifelongLog log;
  LifelongSettings settings;
  settings.steps = 150;
  settings.step_time_s = 5;
  settings.log = &log;
  const LifelongResult result = run_lifelong(problem, planner, settings);
  WrittenRun run;
  write_lorr_output(run.path.string(), problem, result, log);
  const nlohmann::json out = run.read();

  EXPECT_EQ(out["actionModel"], "MAPF");
  EXPECT_EQ(out["AllValid"], "Yes");
  ASSERT_EQ(out["teamSize"], 100);
  EXPECT_EQ(out["numTaskFinished"], result.tasks_finished);
  EXPECT_EQ(out["plannerTimes"].size(), 150u);
  EXPECT_EQ(out["plannerPaths"], out["actualPaths"]);  // nothing late, nothing invalid
  const Graph& graph = *problem.graph;
  // Replay on the map's rows and columns, from the written starts.
  std::vector<std::pair<int, int>> at;
  for (const auto& start : out["start"]) at.emplace_back(start[0].get<int>(), start[1].get<int>());
  std::vector<std::vector<std::string>> actions;
  for (const auto& path : out["actualPaths"]) actions.push_back(split_actions(path.get<std::string>()));
  std::map<int64_t, std::pair<int, int>> task_cell;
  for (const auto& task : out["tasks"]) task_cell[task[0].get<int64_t>()] = {task[1].get<int>(), task[2].get<int>()};
  // (step, agent) -> task finished then
  std::map<std::pair<int, int>, int64_t> finished_at;
  int64_t finished = 0;
  for (int a = 0; a < 100; ++a) {
    for (const auto& event : out["events"][a]) {
      if (event[2] == "finished") {
        finished_at[{event[1].get<int>(), a}] = event[0].get<int64_t>();
        ++finished;
      }
    }
  }
  EXPECT_EQ(finished, result.tasks_finished);
  EXPECT_GT(finished, 50);
  int64_t checked = 0;
  for (int step = 0; step < 150; ++step) {
    std::vector<std::pair<int, int>> next = at;
    for (int a = 0; a < 100; ++a) {
      ASSERT_EQ(actions[a].size(), 150u);
      const std::string& act = actions[a][step];
      if (act == "U") --next[a].first;
      else if (act == "D") ++next[a].first;
      else if (act == "L") --next[a].second;
      else if (act == "R") ++next[a].second;
      else ASSERT_EQ(act, "W") << "agent " << a << " step " << step;
      const Cell cell{next[a].second, next[a].first};
      ASSERT_TRUE(graph.inside(cell) && graph.is_free(cell)) << "agent " << a << " off the map at step " << step;
    }
    std::set<std::pair<int, int>> taken;
    for (int a = 0; a < 100; ++a) ASSERT_TRUE(taken.insert(next[a]).second) << "two agents on a cell at " << step;
    for (int a = 0; a < 100; ++a) {
      for (int b = a + 1; b < 100; ++b) {
        ASSERT_FALSE(next[a] == at[b] && next[b] == at[a] && at[a] != at[b]) << a << " and " << b << " swap";
      }
    }
    at = next;
    for (int a = 0; a < 100; ++a) {
      const auto done = finished_at.find({step + 1, a});
      if (done == finished_at.end()) continue;
      EXPECT_EQ(task_cell.at(done->second), at[a]) << "task " << done->second << " finished away from its cell";
      ++checked;
    }
  }
  EXPECT_EQ(checked, finished);
}

// Late steps are the planner's "T", everyone's actual "W"; an invalid step is an error naming its
// agents.
class SlowThenJumpingPlanner : public LifelongPlanner {
 public:
  Poses next_step(const Poses& now, const Config&, const Deadline& deadline) override {
    if (calls_++ == 0) {
      // Past the budget whatever the machine's load; the next step answers at once, well within
      // its budget even on a loaded machine.
      while (!deadline.expired()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      return now;
    }
    Poses next = now;
    next.cells[0] = now.cells[1];
    return next;
  }

 private:
  int calls_ = 0;
};

TEST(LorrOutput, LateAndInvalidStepsAreWrittenAsTheLeagueDoes) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_20.json");
  SlowThenJumpingPlanner planner;
  LifelongLog log;
  LifelongSettings settings;
  settings.steps = 2;
  settings.step_time_s = 0.5;
  settings.log = &log;
  const LifelongResult result = run_lifelong(problem, planner, settings);
  WrittenRun run;
  write_lorr_output(run.path.string(), problem, result, log);
  const nlohmann::json out = run.read();
  EXPECT_EQ(out["AllValid"], "No");
  EXPECT_EQ(out["plannerPaths"][0], "T,T");  // late, then a jump: no action
  EXPECT_EQ(out["plannerPaths"][5], "T,W");
  EXPECT_EQ(out["actualPaths"][0], "W,W");
  ASSERT_EQ(out["errors"].size(), 1u);
  EXPECT_EQ(out["errors"][0][0], 0);
  EXPECT_EQ(out["errors"][0][1], -1);
  EXPECT_EQ(out["errors"][0][2], 1);
  EXPECT_NE(out["errors"][0][3].get<std::string>().find("jumps"), std::string::npos);
}

TEST(LorrOutput, AnUnwritablePathIsNamed) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_20.json");
  LifelongLog log;
  try {
    write_lorr_output("/nonexistent-folder/run.json", problem, LifelongResult{}, log);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/run.json"), std::string::npos);
  }
}

}  // namespace
}  // namespace planner_core
