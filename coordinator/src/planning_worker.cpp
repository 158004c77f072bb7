#include "coordinator/planning_worker.hpp"

namespace coordinator {

PlanningWorker::PlanningWorker() : thread_([this] { run(); }) {}

PlanningWorker::~PlanningWorker() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  cancel_.store(true);
  wake_.notify_all();
  thread_.join();
}

void PlanningWorker::start(PlanningRequest request) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (busy_ || outcome_) throw std::logic_error("PlanningWorker::start while a plan is under way or uncollected");
    cancel_.store(false);
    request_ = std::move(request);
    busy_ = true;
  }
  wake_.notify_all();
}

std::optional<PlanningOutcome> PlanningWorker::poll() {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::optional<PlanningOutcome> outcome;
  outcome.swap(outcome_);
  return outcome;
}

std::optional<PlanningOutcome> PlanningWorker::wait_for(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait_for(lock, timeout, [&] { return outcome_.has_value(); });
  std::optional<PlanningOutcome> outcome;
  outcome.swap(outcome_);
  return outcome;
}

bool PlanningWorker::idle() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return !busy_ && !outcome_;
}

planner_core::SolveResult PlanningWorker::first_window(const PlanningRequest& request,
                                                     const planner_core::Deadline& deadline) {
  const planner_core::Instance& instance = request.built.instance;
  std::vector<WindowAgent> agents(instance.agent_count());
  for (int a = 0; a < instance.agent_count(); ++a) agents[a].park = instance.goals[a];
  for (const planner_core::Task& task : instance.tasks) {
    for (int a : task.agents) agents[a].errands.push_back(task.at);
  }
  WindowPlanner windows(instance.graph, request.solver.seed, instance.actions,
                        window_settings(request.lifelong_planner, *instance.graph, instance.agent_count(), instance.actions));
  planner_core::Headings headings;
  if (instance.actions == planner_core::ActionModel::kRotate) {
    for (int a = 0; a < instance.agent_count(); ++a) headings.push_back(instance.start_heading(a));
  }
  PlanWindow window = windows.plan({instance.starts, headings}, agents, request.window_steps, deadline);
  planner_core::SolveResult result;
  result.solution = std::move(window.steps);
  result.headings = std::move(window.headings);
  result.solved = true;
  return result;
}

void PlanningWorker::run() {
  for (;;) {
    PlanningRequest request;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || request_.has_value(); });
      if (quit_) return;
      request = std::move(*request_);
      request_.reset();
    }
    PlanningOutcome outcome;
    const auto started = std::chrono::steady_clock::now();
    try {
      const auto deadline = planner_core::Deadline::for_limits(request.time_limit_s, request.iterations, &cancel_);
      if (request.lifelong_window) {
        outcome.result = first_window(request, deadline);
      } else {
        outcome.result = planner_core::make_solver(request.solver)->solve(request.built.instance, {deadline, {}});
      }
      if (outcome.result.solved) {
        planner_core::ValidationOptions options;
        options.forbid_rotations = request.solver.forbid_rotations || request.lifelong_window;
        options.first_stretch = request.lifelong_window;
        outcome.report =
            planner_core::validate(request.built.instance, outcome.result.solution, options, outcome.result.headings);
      }
    } catch (const std::exception& e) {  // a solver bug must not end the mission
      outcome.error = std::string("the solver threw: ") + e.what();
    }
    outcome.planning_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
    outcome.cancelled = cancel_.load();
    outcome.built = std::move(request.built);
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      outcome_ = std::move(outcome);
      busy_ = false;
    }
    done_.notify_all();
  }
}

}  // namespace coordinator
