// WindowWorker: a lifelong window planned on the worker's thread is the window the planner makes
// on the caller's; one at a time; a worker destroyed mid-window cuts it short.
#include <gtest/gtest.h>

#include "coordinator/window_worker.hpp"

#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>

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
