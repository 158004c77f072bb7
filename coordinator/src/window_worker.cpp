#include "coordinator/window_worker.hpp"

#include <chrono>
#include <stdexcept>

namespace coordinator {

WindowWorker::WindowWorker(std::unique_ptr<WindowPlanner> planner)
    : planner_(std::move(planner)), thread_([this] { run(); }) {}

WindowWorker::~WindowWorker() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  cancel_.store(true);
  wake_.notify_all();
  thread_.join();
}

void WindowWorker::start(WindowJob job) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (busy_ || outcome_) throw std::logic_error("WindowWorker::start while a window is under way or uncollected");
    job_ = std::move(job);
    busy_ = true;
  }
  wake_.notify_all();
}

std::optional<WindowOutcome> WindowWorker::poll() {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::optional<WindowOutcome> outcome;
  outcome.swap(outcome_);
  return outcome;
}

bool WindowWorker::idle() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return !busy_ && !outcome_;
}

void WindowWorker::run() {
  for (;;) {
    WindowJob job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || job_.has_value(); });
      if (quit_) return;
      job = std::move(*job_);
      job_.reset();
    }
    WindowOutcome outcome;
    const auto started = std::chrono::steady_clock::now();
    try {
      outcome.window =
          planner_->plan(job.from, job.agents, job.steps, planner_core::Deadline::in_seconds(job.budget_s, &cancel_));
    } catch (const std::exception& e) {
      outcome.error = e.what();
    }
    outcome.planning_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
    outcome.job = std::move(job);
    const std::lock_guard<std::mutex> lock(mutex_);
    outcome_ = std::move(outcome);
    busy_ = false;
  }
}

}  // namespace coordinator
