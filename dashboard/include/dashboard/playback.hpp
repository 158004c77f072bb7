// What a replay plays: the fleet's messages in time order, made as they are needed, so that a long
// history or a plan of thousands of agents never sits in memory as one message per robot per step.
//
//   RecordedPlayback: a history file's entries (--replay FILE).
//   PlanPlayback:     a ctsfleet-solve solution of an instance (--plan FILE --instance FILE), its
//                     robots agent0..agentN-1 stepping through it, one step every step_ms. The plan
//                     is shown in windows of kPlanWindow steps, each a new plan epoch, the way a
//                     coordinator replans: the page draws every robot's next steps, never all of them.
#pragma once

#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "dashboard/history.hpp"
#include "planner_core/instance.hpp"
#include "planner_core/solution.hpp"

namespace dashboard {

class Playback {
 public:
  virtual ~Playback() = default;
  // The times of its first and last messages.
  virtual int64_t start_ms() const = 0;
  virtual int64_t end_ms() const = 0;
  // Hands over, in time order, every message stamped up to `until_ms` not handed over before.
  virtual void play_until(int64_t until_ms, const std::function<void(const HistoryEntry&)>& apply) = 0;
};

class RecordedPlayback : public Playback {
 public:
  explicit RecordedPlayback(std::vector<HistoryEntry> entries) : entries_(std::move(entries)) {}
  int64_t start_ms() const override { return entries_.empty() ? 0 : entries_.front().t_ms; }
  int64_t end_ms() const override { return entries_.empty() ? 0 : entries_.back().t_ms; }
  void play_until(int64_t until_ms, const std::function<void(const HistoryEntry&)>& apply) override;

 private:
  std::vector<HistoryEntry> entries_;
  size_t next_ = 0;
};

class PlanPlayback : public Playback {
 public:
  static constexpr int kPlanWindow = 32;  // steps of each robot's path the page is sent at a time

  // Checks the solution with planner_core's validator (as ctsfleet-solve does before it writes
  // one); throws planner_core::InputError naming `plan_source` and the first fault when it fails.
  PlanPlayback(const planner_core::Instance& instance, planner_core::Solution solution, int64_t step_ms,
               const std::string& plan_source);
  int64_t start_ms() const override { return 0; }
  int64_t end_ms() const override { return static_cast<int64_t>(solution_.size() - 1) * step_ms_; }
  void play_until(int64_t until_ms, const std::function<void(const HistoryEntry&)>& apply) override;
  const planner_core::Solution& solution() const { return solution_; }

 private:
  void play_start(const std::function<void(const HistoryEntry&)>& apply);
  void play_step(size_t t, const std::function<void(const HistoryEntry&)>& apply);
  int epoch_of(size_t t) const { return static_cast<int>(t / kPlanWindow) + 1; }

  planner_core::Instance instance_;
  planner_core::Solution solution_;
  int64_t step_ms_;
  int64_t flowtime_ = 0;
  int makespan_ = 0;
  size_t next_step_ = 0;
  bool started_ = false;
  std::set<std::pair<int, int>> visits_done_;  // (task, agent)
  std::vector<fleet_transport::TaskVisit> visit_list_;
  int tasks_done_ = 0;
};

// Every message of a playback, in order (for tests and pictures of short ones).
std::vector<HistoryEntry> all_entries(Playback& playback);

}  // namespace dashboard
