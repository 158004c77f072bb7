// TaskStream: the work a warehouse gives a lifelong fleet, for the fleet benchmark. Keeps
// `waiting` tasks the fleet has not done yet (accepted and not done, or asked and not answered),
// each at a random free cell of the map (or the next cell of a list, in its order and over again,
// as the league reveals a problem's tasks), for whichever robot suits it best. A request not answered
// within a second is asked again (the same id: the coordinator answers a repeat without adding
// twice). A task refused because its cell has a task waiting already (the coordinator's
// "duplicate") is asked again a quarter of a second later, under a new id, until it is taken: it
// still waits, so the list's tasks are all given, in their order. Not thread-safe: the caller holds a lock when replies arrive on another thread.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "fleet_transport/messages.hpp"
#include "planner_core/graph.hpp"

namespace coordinator {

class TaskStream {
 public:
  using Clock = std::chrono::steady_clock;

  // `mission_tasks`: the tasks the fleet's mission came with, counted as given.
  TaskStream(const planner_core::Graph& graph, int waiting, int mission_tasks, uint32_t seed, std::string id_prefix);
  // Tasks at `cells_in_order`, the first first; after the last, the first again.
  TaskStream(std::vector<planner_core::Cell> cells_in_order, int waiting, int mission_tasks, std::string id_prefix);

  // The requests to send now, given how many tasks the fleet has done (its status's tasks_done,
  // which may lag): new ones up to `waiting` not done, and unanswered ones again.
  std::vector<fleet_transport::TaskRequest> due(int tasks_done, Clock::time_point now);
  void answered(const fleet_transport::TaskReply& reply);

  int accepted() const { return accepted_; }
  int refused() const { return refused_; }
  int deferred() const { return deferred_; }  // refusals of a cell with a task waiting, asked again
  const std::string& last_refusal() const { return last_refusal_; }
  // In order (the list's constructor): the fleet's id of each task accepted -> its number in the
  // list's order (the first cell 0, the next 1, ... counting on over again after the last).
  const std::map<int, int64_t>& list_number_of_task() const { return list_number_of_task_; }

 private:
  struct Asked {
    fleet_transport::TaskRequest request;
    Clock::time_point last_sent;
    Clock::duration again_after = std::chrono::seconds(1);
    int64_t list_number = -1;  // in order: the cell's number in the list's order
  };
  std::vector<planner_core::Cell> cells_;
  bool in_order_ = false;
  int waiting_;
  int mission_tasks_;
  std::mt19937 rng_;
  std::string id_prefix_;
  int64_t next_id_ = 0;
  uint64_t next_in_order_ = 0;  // the list's next cell
  std::map<std::string, Asked> unanswered_;
  int accepted_ = 0;
  int refused_ = 0;
  int deferred_ = 0;
  std::string last_refusal_;
  std::map<int, int64_t> list_number_of_task_;
};

}  // namespace coordinator
