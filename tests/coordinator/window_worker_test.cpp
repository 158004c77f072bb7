// WorkerThread and WindowWorker: a job runs on the worker's thread, one at a time, and is cut short
// by cancel(); a lifelong window planned there is the window the planner makes on the caller's; a
// worker destroyed mid-window cuts it short.
#include <gtest/gtest.h>

#include "coordinator/window_worker.hpp"

#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>
#include <utility>

namespace coordinator {
namespace {

using planner_core::Graph;

// Polls until the outcome comes back (a loaded machine may take its time: 60 s at most).
std::optional<WindowOutcome> outcome_of(WindowWorker& worker) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    if (std::optional<WindowOutcome> outcome = worker.poll()) return outcome;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return std::nullopt;
}

TEST(WorkerThread, RunsOneJobAtATimeOffTheCallersThreadAndCancelCutsItShort) {
  // A job that counts until cancelled (or 60 s pass), returning its count and its thread.
  WorkerThread<int, std::pair<int, std::thread::id>> worker([](int& start, const std::atomic<bool>& cancel) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    int count = start;
    while (!cancel.load() && std::chrono::steady_clock::now() < until) {
      ++count;
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    return std::make_pair(count, std::this_thread::get_id());
  });
  worker.start(5);
  EXPECT_FALSE(worker.idle());
  EXPECT_THROW(worker.start(6), std::logic_error);
  EXPECT_FALSE(worker.wait_for(std::chrono::milliseconds(20)).has_value());  // still counting
  const auto cancelled_at = std::chrono::steady_clock::now();
  worker.cancel();
  const std::optional<std::pair<int, std::thread::id>> outcome = worker.wait_for(std::chrono::seconds(30));
  ASSERT_TRUE(outcome.has_value());
  EXPECT_LT(std::chrono::steady_clock::now() - cancelled_at, std::chrono::seconds(30));
  EXPECT_GT(outcome->first, 5);
  EXPECT_NE(outcome->second, std::this_thread::get_id());
  EXPECT_TRUE(worker.idle());
  worker.start(0);  // the next job starts uncancelled
  EXPECT_FALSE(worker.wait_for(std::chrono::milliseconds(20)).has_value());
}

TEST(WindowWorker, PlansTheSameWindowAsThePlannerOnTheCallersThreadOneAtATime) {
  auto graph = std::make_shared<const Graph>(8, 2, std::vector<std::string>{"........", "........"});
  const auto v = [&](int x, int y) { return graph->vertex_at({x, y}); };
  const planner_core::Poses from{{v(0, 0), v(7, 1)}, {}};
  const std::vector<WindowAgent> agents = {{{v(7, 0)}, v(0, 1)}, {{v(0, 1)}, v(7, 0)}};
  WindowPlanner here(graph, 3);
  const PlanWindow expected = here.plan(from, agents, 6, planner_core::Deadline::in_seconds(5));

  WindowWorker worker(std::make_unique<WindowPlanner>(graph, 3));
  EXPECT_TRUE(worker.idle());
  worker.start({4, 17, from, agents, 6, 5.0});
  EXPECT_THROW(worker.start({4, 17, from, agents, 6, 5.0}), std::logic_error);  // one at a time
  const std::optional<WindowOutcome> outcome = outcome_of(worker);
  ASSERT_TRUE(outcome.has_value());
  EXPECT_TRUE(outcome->error.empty());
  EXPECT_EQ(outcome->job.epoch, 4);
  EXPECT_EQ(outcome->job.plan_steps, 17);
  EXPECT_EQ(outcome->window.steps, expected.steps);
  EXPECT_EQ(outcome->window.reached, expected.reached);
  EXPECT_TRUE(worker.idle());
  EXPECT_FALSE(worker.poll().has_value());  // collected once
}

TEST(WindowWorker, AWindowThatCannotBePlannedComesBackAsAnError) {
  auto graph = std::make_shared<const Graph>(4, 1, std::vector<std::string>{"...."});
  WindowWorker worker(std::make_unique<WindowPlanner>(graph, 1));
  worker.start({1, 0, {{0, 3}, {}}, {{{}, 0}}, 5, 1.0});  // two agents, one WindowAgent
  const std::optional<WindowOutcome> outcome = outcome_of(worker);
  ASSERT_TRUE(outcome.has_value());
  EXPECT_NE(outcome->error.find("one WindowAgent per agent"), std::string::npos) << outcome->error;
  EXPECT_TRUE(worker.idle());
}

TEST(WindowWorker, AWorkerDestroyedMidWindowCutsItShort) {
  // 400 agents on a 40 x 40 map heading across it, a window of 100,000 steps with a minute's
  // budget: the destructor must not wait for it.
  std::vector<std::string> rows(40, std::string(40, '.'));
  auto graph = std::make_shared<const Graph>(40, 40, rows);
  planner_core::Poses from;
  std::vector<WindowAgent> agents;
  for (int k = 0; k < 400; ++k) {
    from.cells.push_back(graph->vertex_at({k % 40, k / 40}));
    agents.push_back({{graph->vertex_at({39 - k % 40, 39 - k / 40})}, graph->vertex_at({k % 40, k / 40})});
  }
  const auto started = std::chrono::steady_clock::now();
  {
    WindowWorker worker(std::make_unique<WindowPlanner>(graph, 1));
    worker.start({1, 0, from, agents, 100000, 60.0});
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(30));
}

}  // namespace
}  // namespace coordinator
