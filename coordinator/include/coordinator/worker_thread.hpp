// WorkerThread: one job at a time on a thread of its own, so that the coordinator's loop goes on
// meanwhile (heartbeats, robots' states, commands). The loop hands over a self-contained job,
// polls for the outcome, and checks it against the world as it is when it comes back. `work(job,
// cancel)` runs on the thread; cancel() and the destructor set `cancel`, which the work hands to
// its deadline so that it ends early. The planning worker (whole plans) and the window worker
// (lifelong windows) are each one of these.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>
#include <utility>

namespace coordinator {

template <typename Job, typename Outcome>
class WorkerThread {
 public:
  using Work = std::function<Outcome(Job& job, const std::atomic<bool>& cancel)>;

  explicit WorkerThread(Work work) : work_(std::move(work)), thread_([this] { run(); }) {}
  ~WorkerThread() {  // cuts the job under way short and waits for the thread
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      quit_ = true;
    }
    cancel_.store(true);
    wake_.notify_all();
    thread_.join();
  }
  WorkerThread(const WorkerThread&) = delete;
  WorkerThread& operator=(const WorkerThread&) = delete;

  // Starts `job`; only while idle().
  void start(Job job) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (busy_ || outcome_) throw std::logic_error("WorkerThread::start while a job is under way or uncollected");
      cancel_.store(false);
      job_ = std::move(job);
      busy_ = true;
    }
    wake_.notify_all();
  }
  // The outcome once the job has ended (then idle again), else nothing.
  std::optional<Outcome> poll() {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::optional<Outcome> outcome;
    outcome.swap(outcome_);
    return outcome;
  }
  // As poll(), waiting up to `timeout` for the job to end.
  std::optional<Outcome> wait_for(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait_for(lock, timeout, [&] { return outcome_.has_value(); });
    std::optional<Outcome> outcome;
    outcome.swap(outcome_);
    return outcome;
  }
  void cancel() { cancel_.store(true); }
  // No job under way and no outcome uncollected.
  bool idle() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return !busy_ && !outcome_;
  }

 private:
  void run() {
    for (;;) {
      std::optional<Job> job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return quit_ || job_.has_value(); });
        if (quit_) return;
        job.swap(job_);
      }
      Outcome outcome = work_(*job, cancel_);
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        outcome_ = std::move(outcome);
        busy_ = false;
      }
      done_.notify_all();
    }
  }

  Work work_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;  // an outcome was set
  std::optional<Job> job_;
  std::optional<Outcome> outcome_;
  bool busy_ = false;
  bool quit_ = false;
  std::atomic<bool> cancel_{false};
  std::thread thread_;  // last: starts once the members above exist
};

}  // namespace coordinator
