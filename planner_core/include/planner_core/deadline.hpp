// Deadline: when a search must stop. A wall-clock limit, an atomic interrupt flag that another
// thread may raise, and a work limit counted on the solve's WorkMeter.
//
// Work is what makes a solver reproducible: a limit inside a solver ("the complete search gets as
// much as this sequence took", "a local LaCAM gets a fifth of a second") is given in work units,
// so it falls at the same point of the search on every run and every machine. Only the user's
// time limit (and the interrupt) is read off the clock. With a work budget (`--iterations`) the
// shares after the first plan are counted in work too, so the final plan is reproducible as well.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>

namespace planner_core {

using Clock = std::chrono::steady_clock;

// One unit of work: one agent's state expanded once (a SIPP or A* node, one agent's move in an
// Extended-PIBT step or in a LaCAM configuration). Counted by one solve, on one thread.
class WorkMeter {
 public:
  void spend(int64_t units) { done_.store(done_.load(std::memory_order_relaxed) + units, std::memory_order_relaxed); }
  int64_t done() const { return done_.load(std::memory_order_relaxed); }

 private:
  std::atomic<int64_t> done_{0};  // atomic only so that helper threads may look (DistTable::prepare)
};

// Work units this machine does in about a second (measured on the benchmark suites, docs/results/HISTORY.md
// section 21): converts the solvers' time shares into work and back. A slower machine
// takes longer for the same work; the plan stays the same.
constexpr int64_t kWorkPerSecond = 3'000'000;
constexpr int64_t kNoWorkLimit = std::numeric_limits<int64_t>::max();
// `--iterations`: one iteration is this much work, about a millisecond of search here.
constexpr int64_t kWorkPerIteration = kWorkPerSecond / 1000;
constexpr int64_t kMaxIterations = 1'000'000'000'000;  // 10^12 x kWorkPerIteration fits in int64_t

struct Deadline {
  Clock::time_point at = Clock::time_point::max();
  const std::atomic<bool>* interrupt = nullptr;
  std::shared_ptr<WorkMeter> meter;  // shared by every slice of one solve; none: no work counted
  int64_t work_at = kNoWorkLimit;    // expired once the meter has counted this much
  // A work budget (`--iterations`): the solver's time shares are counted in work (slice(),
  // budget_left_s()) and the clock ends the solve only at `at`, as a safety stop.
  bool shares_in_work = false;
  // The solver's nominal budget in seconds: the user's time limit as given (not as read off the
  // clock later), or the work budget at kWorkPerSecond. Solvers size their shares from it.
  double budget_s = 1e18;

  // `seconds` from now, counting the work done before it on a meter of its own.
  static Deadline in_seconds(double seconds, const std::atomic<bool>* interrupt = nullptr) {
    // Beyond this the clock's range would overflow: no limit (programs refuse such limits first).
    constexpr double kNoLimitBeyondS = 1e9;
    Deadline deadline{Clock::time_point::max(), interrupt, std::make_shared<WorkMeter>()};
    deadline.budget_s = seconds;
    if (seconds < kNoLimitBeyondS) {
      deadline.at = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
    }
    return deadline;
  }
  // A user's limits: `seconds`, and with `iterations` > 0 a work budget of that many iterations
  // (kWorkPerIteration each), the clock then only a safety stop.
  static Deadline for_limits(double seconds, int64_t iterations, const std::atomic<bool>* interrupt = nullptr);
  // The same deadline that also ends after `units` of work from now, with the solver's shares
  // counted in work from then on (`--iterations`).
  Deadline with_work_budget(int64_t units) const {
    Deadline budgeted = within_work(units);
    budgeted.shares_in_work = true;
    budgeted.budget_s = static_cast<double>(units) / kWorkPerSecond;
    return budgeted;
  }
  // The earlier of this deadline and `seconds` from now (always the clock: for programs).
  Deadline within(double seconds) const {
    Deadline slice = *this;
    const Deadline clock = in_seconds(seconds);
    slice.at = std::min(at, clock.at);
    return slice;
  }
  // The earlier of this deadline and `units` of work from now: the same point of the search on
  // every run.
  Deadline within_work(int64_t units) const {
    Deadline slice = *this;
    if (!slice.meter) slice.meter = std::make_shared<WorkMeter>();
    const int64_t now = slice.meter->done();
    const int64_t limit = units >= kNoWorkLimit - now ? kNoWorkLimit : now + std::max<int64_t>(0, units);
    slice.work_at = std::min(work_at, limit);
    return slice;
  }
  // A solver's share of its budget: `seconds` of the clock, or as much work with a work budget.
  Deadline slice(double seconds) const {
    return shares_in_work ? within_work(work_of(seconds)) : within(seconds);
  }
  // What is left of the budget in seconds: of the clock, or of the work budget at kWorkPerSecond.
  // 0 once expired.
  double budget_left_s() const {
    if (!shares_in_work) return seconds_left();
    if (expired()) return 0;
    return static_cast<double>(work_at - meter->done()) / kWorkPerSecond;
  }
  // Seconds until `at` (0 once it has passed or the interrupt is raised).
  double seconds_left() const {
    if (interrupt && interrupt->load(std::memory_order_relaxed)) return 0;
    if (at == Clock::time_point::max()) return 1e18;
    return std::max(0.0, std::chrono::duration<double>(at - Clock::now()).count());
  }
  void spend(int64_t units) const {
    if (meter) meter->spend(units);
  }
  int64_t work_done() const { return meter ? meter->done() : 0; }
  bool expired() const {
    return (interrupt && interrupt->load(std::memory_order_relaxed)) || (meter && meter->done() >= work_at) ||
           Clock::now() >= at;
  }
  static int64_t work_of(double seconds) {
    if (!(seconds > 0)) return 0;
    if (seconds >= static_cast<double>(kNoWorkLimit / kWorkPerSecond)) return kNoWorkLimit;
    return static_cast<int64_t>(seconds * kWorkPerSecond);
  }
};

inline Deadline Deadline::for_limits(double seconds, int64_t iterations, const std::atomic<bool>* interrupt) {
  const Deadline clock = in_seconds(seconds, interrupt);
  return iterations > 0 ? clock.with_work_budget(iterations * kWorkPerIteration) : clock;
}

// A time limit a program accepts from its user: a finite number of seconds in (0, 1e6].
constexpr double kMaxTimeLimitS = 1e6;

inline double elapsed_ms(Clock::time_point since) {
  return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

}  // namespace planner_core
