// MissionJournal: the mission's record in an SQLite file (WAL, every write committed before the
// coordinator acts on it), so a coordinator that restarts resumes the mission instead of starting
// it over: which coordinator terms claimed it, the plan epochs, which robot holds each role, and
// every task visit at the moment it was confirmed. One file per mission: a journal of another
// mission, a file that is no journal, and a journal held by a live coordinator are refused with an
// error naming the file. The open journal stays locked (SQLite exclusive locking mode) until the
// coordinator ends, so a second coordinator cannot write the same mission.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fleet_transport/messages.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/instance.hpp"

struct sqlite3;

namespace coordinator {

// The mission's fingerprint: a hash of its map, starts, goals and tasks (16 hex digits). Two
// configurations with the same fingerprint describe the same mission.
std::string mission_fingerprint(const planner_core::Instance& mission);

class JournalError : public planner_core::InputError {
 public:
  using InputError::InputError;
};

// What an unfinished run of the mission left behind.
struct JournalResume {
  int64_t run = 0;
  uint32_t last_term = 0;
  int last_epoch = 0;
  std::map<int, std::string> bindings;             // role -> robot id
  std::vector<fleet_transport::TaskVisit> visits;  // done
  // Tasks added at runtime, in the order they were added (task ids from the mission's count on).
  struct AddedTask {
    int task = 0;
    int x = 0, y = 0;
    int role = 0;
  };
  std::vector<AddedTask> added_tasks;
  std::vector<int> cancelled_tasks;
  std::vector<int> pinned_tasks;  // added for a robot the operator named (never rebalanced)
  // Rows the run once wrote that the file no longer holds (warned about at open).
  int lost_records = 0;
};

class MissionJournal {
 public:
  // Opens (or creates) `path` for the mission with `fingerprint`. Throws JournalError.
  MissionJournal(const std::string& path, const std::string& fingerprint, const std::string& description);
  ~MissionJournal();
  MissionJournal(const MissionJournal&) = delete;
  MissionJournal& operator=(const MissionJournal&) = delete;

  const std::string& path() const { return path_; }
  // The unfinished run found at open, if any; start() continues it.
  const std::optional<JournalResume>& resumable() const { return resumable_; }
  // The highest term any coordinator of this journal claimed (0 for a new journal).
  uint32_t highest_term() const { return highest_term_; }

  // A coordinator takes the mission: continues the unfinished run, or starts a new one.
  void claim(uint32_t term, uint64_t coordinator, int64_t claimed_ms);
  void record_epoch(int epoch, uint32_t term);
  void record_binding(int role, const std::string& robot_id);  // "" = the role lost its robot
  void record_visit(const fleet_transport::TaskVisit& visit, const std::string& robot_id, int epoch);
  // An operator's task, added to the run (task = its id) or cancelled.
  void record_task_added(int task, int x, int y, int role, const std::string& request_id);
  void record_task_cancelled(int task, const std::string& request_id);
  // An added task stays with the robot the operator named; or goes to another role (lifelong
  // mode's pool: a task the plan had not reached yet).
  void record_task_pinned(int task);
  void record_task_role(int task, int role);
  // The run ended: "completed", "timeout", "interrupted", "stood down"...
  void finish(const std::string& outcome);
  // Tests: the file may grow to `pages` pages at most, as on a disk that fills.
  void limit_size_for_test(int64_t pages);
  // Tests: every write from now on fails (a file system gone read-only).
  void refuse_writes_for_test();

 private:
  class Statement;
  static std::string count_key(const std::string& table, int64_t run);
  void count_row_written(const std::string& table);  // after an INSERT OR IGNORE into `table`
  void execute(const std::string& sql);
  void read_resumable();
  // Throws JournalError, writing nothing, for an SQLite database that is not a ctsfleet journal.
  void refuse_other_programs_databases();
  void checkpoint();
  [[noreturn]] void fail(const std::string& what) const;

  std::string path_;
  sqlite3* db_ = nullptr;
  int64_t run_ = 0;
  std::optional<JournalResume> resumable_;
  uint32_t highest_term_ = 0;
};

}  // namespace coordinator
