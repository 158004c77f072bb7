#include "coordinator/mission_journal.hpp"

#include <spdlog/spdlog.h>
#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <cstdio>
#include <limits>
#include <set>
#include <string>
#include <variant>

#include "planner_core/input_file.hpp"

namespace coordinator {

namespace {

constexpr const char* kFormat = "ctsfleet-journal-1";
// SQLite's application id of a ctsfleet journal ("CTSJ"): a database of another program is refused
// before anything is written to it.
constexpr int64_t kApplicationId = 0x43545346;
// The tables of a journal: a file with others (or without `meta`) is no journal.
const std::set<std::string> kJournalTables = {"meta",   "runs",        "claims",          "epochs",      "bindings",
                                              "visits", "tasks_added", "tasks_cancelled", "tasks_pinned"};

// FNV-1a, 64 bits: stable across builds and machines, unlike std::hash.
struct Fingerprint {
  uint64_t hash = 1469598103934665603ull;
  void add(int64_t value) {
    for (int i = 0; i < 8; ++i) {
      hash ^= static_cast<uint64_t>(value >> (8 * i)) & 0xff;
      hash *= 1099511628211ull;
    }
  }
};

}  // namespace

std::string mission_fingerprint(const planner_core::Instance& mission) {
  Fingerprint fingerprint;
  const planner_core::Graph& graph = *mission.graph;
  fingerprint.add(graph.width());
  fingerprint.add(graph.height());
  for (int y = 0; y < graph.height(); ++y) {
    for (int x = 0; x < graph.width(); ++x) fingerprint.add(graph.is_free({x, y}) ? 1 : 0);
  }
  // Cells by their coordinates, not by vertex number: the numbering is the planner's own and may
  // change between versions, while a journal and a standby coordinator outlive a version.
  const auto add_cell = [&](planner_core::Vertex v) {
    const planner_core::Cell cell = graph.cell_of(v);
    fingerprint.add(cell.x);
    fingerprint.add(cell.y);
  };
  for (planner_core::Vertex v : mission.starts) add_cell(v);
  fingerprint.add(-1);
  for (planner_core::Vertex v : mission.goals) add_cell(v);
  fingerprint.add(-2);
  for (const planner_core::Task& task : mission.tasks) {
    add_cell(task.at);
    for (int agent : task.agents) fingerprint.add(agent);
    fingerprint.add(-3);
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(fingerprint.hash));
  return text;
}

// One prepared statement with its parameters bound, stepped to the end or row by row.
class MissionJournal::Statement {
 public:
  using Value = std::variant<int64_t, std::string>;
  Statement(const MissionJournal& journal, const std::string& sql, const std::vector<Value>& values = {})
      : journal_(journal) {
    if (sqlite3_prepare_v2(journal.db_, sql.c_str(), -1, &statement_, nullptr) != SQLITE_OK) journal.fail(sql);
    for (size_t i = 0; i < values.size(); ++i) {
      const int index = static_cast<int>(i) + 1;
      if (const auto* number = std::get_if<int64_t>(&values[i])) {
        sqlite3_bind_int64(statement_, index, *number);
      } else {
        sqlite3_bind_text(statement_, index, std::get<std::string>(values[i]).c_str(), -1, SQLITE_TRANSIENT);
      }
    }
  }
  ~Statement() { sqlite3_finalize(statement_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // The next row, false at the end.
  bool next() {
    const int rc = sqlite3_step(statement_);
    if (rc == SQLITE_ROW) return true;
    if (rc != SQLITE_DONE) journal_.fail(sqlite3_sql(statement_));
    return false;
  }
  void run() {
    while (next()) {
    }
  }
  int64_t number(int column) const { return sqlite3_column_int64(statement_, column); }
  // A column's integer, refused (JournalError naming the field and its range) when it is not an
  // integer or lies outside [low, high]: a journal edited by hand or by another program.
  int64_t number_in(int column, const char* field, int64_t low, int64_t high) const {
    const int64_t value = number(column);
    if (sqlite3_column_type(statement_, column) != SQLITE_INTEGER || value < low || value > high) {
      throw JournalError("--journal " + journal_.path() + ": " + field + " is " + text(column) +
                         ", not an integer in [" + std::to_string(low) + ", " + std::to_string(high) +
                         "]; the journal is left as it is: move it away to start afresh, or give the right file");
    }
    return value;
  }
  int int_in(int column, const char* field, int low = 0) const {
    return static_cast<int>(number_in(column, field, low, std::numeric_limits<int>::max()));
  }
  std::string text(int column) const {
    const unsigned char* value = sqlite3_column_text(statement_, column);
    return value == nullptr ? std::string() : reinterpret_cast<const char*>(value);
  }

 private:
  const MissionJournal& journal_;
  sqlite3_stmt* statement_ = nullptr;
};

void MissionJournal::fail(const std::string& what) const {
  const int code = db_ ? sqlite3_errcode(db_) : SQLITE_CANTOPEN;
  const std::string message = db_ ? sqlite3_errmsg(db_) : "cannot open";
  if (code == SQLITE_BUSY || code == SQLITE_LOCKED) {
    throw JournalError("--journal " + path_ + ": the journal is in use by another coordinator (" + message +
                       "); one coordinator writes a mission's journal: run this one with --standby, or stop the other");
  }
  if (code == SQLITE_NOTADB || code == SQLITE_CORRUPT) {
    throw JournalError("--journal " + path_ + ": not a readable journal (" + message +
                       "); it is left as it is: move it away to start afresh, or give the right file");
  }
  throw JournalError("--journal " + path_ + ": " + message + " (in: " + what + ")");
}

void MissionJournal::execute(const std::string& sql) {
  char* error = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    sqlite3_free(error);
    fail(sql);
  }
}

MissionJournal::MissionJournal(const std::string& path, const std::string& fingerprint, const std::string& description)
    : path_(path) {
  if (std::filesystem::exists(path)) {
    try {
      planner_core::require_regular_file(path, "journal");
    } catch (const planner_core::InputError& e) {
      throw JournalError(std::string("--journal ") + e.what());
    }
  }
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
    const std::string message = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw JournalError("--journal " + path + ": cannot open or create it (" + message + ")");
  }
  try {
    // Exclusive locking: the first write takes the lock and keeps it while this coordinator lives
    // (the operating system drops it if the process dies), so a second coordinator is refused.
    execute("PRAGMA locking_mode=EXCLUSIVE");
    refuse_other_programs_databases();
    execute("PRAGMA journal_mode=WAL");
    execute("PRAGMA synchronous=FULL");
    execute("BEGIN IMMEDIATE");
    execute(
        "CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);"
        "CREATE TABLE IF NOT EXISTS runs(run INTEGER PRIMARY KEY, started_ms INTEGER NOT NULL, ended_ms INTEGER,"
        " outcome TEXT);"
        "CREATE TABLE IF NOT EXISTS claims(run INTEGER NOT NULL, term INTEGER NOT NULL, coordinator TEXT NOT NULL,"
        " claimed_ms INTEGER NOT NULL);"
        "CREATE TABLE IF NOT EXISTS epochs(run INTEGER NOT NULL, epoch INTEGER NOT NULL, term INTEGER NOT NULL,"
        " planned_ms INTEGER NOT NULL);"
        "CREATE TABLE IF NOT EXISTS bindings(run INTEGER NOT NULL, role INTEGER NOT NULL, robot TEXT NOT NULL,"
        " PRIMARY KEY(run, role));"
        "CREATE TABLE IF NOT EXISTS visits(run INTEGER NOT NULL, task INTEGER NOT NULL, role INTEGER NOT NULL,"
        " robot TEXT NOT NULL, epoch INTEGER NOT NULL, at_ms INTEGER NOT NULL, PRIMARY KEY(run, task, role));"
        "CREATE TABLE IF NOT EXISTS tasks_added(run INTEGER NOT NULL, task INTEGER NOT NULL, x INTEGER NOT NULL,"
        " y INTEGER NOT NULL, role INTEGER NOT NULL, request TEXT NOT NULL, at_ms INTEGER NOT NULL,"
        " PRIMARY KEY(run, task));"
        "CREATE TABLE IF NOT EXISTS tasks_cancelled(run INTEGER NOT NULL, task INTEGER NOT NULL,"
        " request TEXT NOT NULL, at_ms INTEGER NOT NULL, PRIMARY KEY(run, task));"
        "CREATE TABLE IF NOT EXISTS tasks_pinned(run INTEGER NOT NULL, task INTEGER NOT NULL,"
        " PRIMARY KEY(run, task));");
    std::string format, recorded;
    {
      Statement meta(*this, "SELECT key, value FROM meta");
      while (meta.next()) {
        if (meta.text(0) == "format") format = meta.text(1);
        if (meta.text(0) == "mission") recorded = meta.text(1);
      }
    }
    if (format.empty() && recorded.empty()) {
      Statement(*this, "INSERT INTO meta VALUES('format', ?1), ('mission', ?2), ('description', ?3)",
                {std::string(kFormat), fingerprint, description})
          .run();
      execute("PRAGMA application_id=" + std::to_string(kApplicationId));
    } else if (format != kFormat) {
      throw JournalError("--journal " + path + ": not a ctsfleet journal (format '" + format + "', expected '" +
                         kFormat + "')");
    } else if (recorded != fingerprint) {
      std::string other;
      Statement described(*this, "SELECT value FROM meta WHERE key = 'description'");
      if (described.next()) other = described.text(0);
      throw JournalError("--journal " + path + ": the journal of another mission (" + recorded + ": " + other +
                         "), not of this one (" + fingerprint + ": " + description +
                         "); give each mission its own journal file");
    }
    read_resumable();
    execute("COMMIT");
    checkpoint();
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

MissionJournal::~MissionJournal() { sqlite3_close(db_); }

void MissionJournal::refuse_other_programs_databases() {
  int64_t application_id = 0;
  {
    Statement id(*this, "PRAGMA application_id");
    if (id.next()) application_id = id.number(0);
  }
  std::vector<std::string> tables;
  {
    Statement listed(*this, "SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name");
    while (listed.next()) tables.push_back(listed.text(0));
  }
  if (application_id == kApplicationId) return;
  // A new file, or a journal of a version before the application id (it has `meta`).
  bool only_ours = true;
  for (const std::string& table : tables) only_ours = only_ours && kJournalTables.count(table) > 0;
  const bool has_meta = std::find(tables.begin(), tables.end(), "meta") != tables.end();
  if (application_id == 0 && (tables.empty() || (only_ours && has_meta))) return;
  std::string listing;
  for (size_t k = 0; k < tables.size() && k < 8; ++k) listing += (k ? ", " : "") + tables[k];
  if (tables.size() > 8) listing += ", ...";
  char id[32];
  std::snprintf(id, sizeof id, "0x%llx", static_cast<unsigned long long>(application_id));
  throw JournalError("--journal " + path_ + ": not a ctsfleet journal but an SQLite database of another program "
                     "(application id " + id + ", tables: " + (listing.empty() ? "none" : listing) +
                     "); it is left as it is: give the journal a file of its own");
}

void MissionJournal::checkpoint() {
  // Every record is copied into the main file at once: the file alone (copied without its -wal,
  // or with a -wal cut short) holds the whole mission.
  if (sqlite3_wal_checkpoint_v2(db_, nullptr, SQLITE_CHECKPOINT_FULL, nullptr, nullptr) != SQLITE_OK) {
    fail("checkpoint");
  }
}

// The journal keeps, per run and table, how many rows it ever wrote (in `meta`): rows are never
// deleted, so a resume that finds fewer lost some (an older copy of the file, a file cut short).
std::string MissionJournal::count_key(const std::string& table, int64_t run) {
  return "rows:" + table + ":" + std::to_string(run);
}

void MissionJournal::count_row_written(const std::string& table) {
  if (sqlite3_changes(db_) == 0) return;  // a repeat, ignored
  Statement(*this,
            "INSERT INTO meta VALUES(?1, '1') ON CONFLICT(key) DO UPDATE SET value = CAST(value AS INTEGER) + 1",
            {count_key(table, run_)})
      .run();
}

void MissionJournal::limit_size_for_test(int64_t pages) { execute("PRAGMA max_page_count=" + std::to_string(pages)); }

void MissionJournal::refuse_writes_for_test() { execute("PRAGMA query_only=1"); }

void MissionJournal::read_resumable() {
  {
    Statement term(*this, "SELECT coalesce(max(term), 0) FROM claims");
    if (term.next()) highest_term_ = static_cast<uint32_t>(term.number_in(0, "claims.term", 0, UINT32_MAX));
  }
  Statement open_run(*this, "SELECT run FROM runs WHERE ended_ms IS NULL ORDER BY run DESC LIMIT 1");
  if (!open_run.next()) return;
  JournalResume resume;
  resume.run = open_run.number(0);
  {
    Statement last(*this, "SELECT coalesce(max(term), 0) FROM claims WHERE run = ?1", {resume.run});
    if (last.next()) resume.last_term = static_cast<uint32_t>(last.number_in(0, "claims.term", 0, UINT32_MAX));
  }
  {
    Statement epoch(*this, "SELECT coalesce(max(epoch), 0) FROM epochs WHERE run = ?1", {resume.run});
    if (epoch.next()) resume.last_epoch = epoch.int_in(0, "epochs.epoch");
  }
  {
    Statement bindings(*this, "SELECT role, robot FROM bindings WHERE run = ?1 AND robot != ''", {resume.run});
    while (bindings.next()) resume.bindings[bindings.int_in(0, "bindings.role")] = bindings.text(1);
  }
  {
    Statement added(*this, "SELECT task, x, y, role FROM tasks_added WHERE run = ?1 ORDER BY task", {resume.run});
    while (added.next()) {
      resume.added_tasks.push_back({added.int_in(0, "tasks_added.task"), added.int_in(1, "tasks_added.x"),
                                    added.int_in(2, "tasks_added.y"), added.int_in(3, "tasks_added.role")});
    }
    Statement cancelled(*this, "SELECT task FROM tasks_cancelled WHERE run = ?1 ORDER BY task", {resume.run});
    while (cancelled.next()) resume.cancelled_tasks.push_back(cancelled.int_in(0, "tasks_cancelled.task"));
    Statement pinned(*this, "SELECT task FROM tasks_pinned WHERE run = ?1 ORDER BY task", {resume.run});
    while (pinned.next()) resume.pinned_tasks.push_back(pinned.int_in(0, "tasks_pinned.task"));
  }
  Statement visits(*this, "SELECT task, role FROM visits WHERE run = ?1 ORDER BY task, role", {resume.run});
  while (visits.next()) {
    resume.visits.push_back({visits.int_in(0, "visits.task"), visits.int_in(1, "visits.role")});
  }
  const std::pair<const char*, size_t> held[] = {{"visits", resume.visits.size()},
                                                  {"tasks_added", resume.added_tasks.size()},
                                                  {"tasks_cancelled", resume.cancelled_tasks.size()}};
  for (const auto& [table, found] : held) {
    Statement written(*this, "SELECT CAST(value AS INTEGER) FROM meta WHERE key = ?1", {count_key(table, resume.run)});
    const int64_t count = written.next() ? written.number_in(0, "meta.rows", 0, INT64_MAX) : 0;
    if (count > static_cast<int64_t>(found)) {
      resume.lost_records += static_cast<int>(count - static_cast<int64_t>(found));
      spdlog::warn("journal {}: run {} wrote {} rows of {} but {} are left: the file lost records (an older copy, "
                   "or a file cut short); resuming from what it holds, so work may be done again",
                   path_, resume.run, count, table, found);
    }
  }
  resumable_ = resume;
}

void MissionJournal::claim(uint32_t term, uint64_t coordinator, int64_t claimed_ms) {
  char id[17];
  std::snprintf(id, sizeof id, "%016llx", static_cast<unsigned long long>(coordinator));
  execute("BEGIN IMMEDIATE");
  try {
    if (resumable_) {
      run_ = resumable_->run;
    } else if (run_ == 0) {
      Statement(*this, "INSERT INTO runs(started_ms) VALUES(?1)", {claimed_ms}).run();
      run_ = sqlite3_last_insert_rowid(db_);
    }
    Statement(*this, "INSERT INTO claims VALUES(?1, ?2, ?3, ?4)",
              {run_, static_cast<int64_t>(term), std::string(id), claimed_ms})
        .run();
    execute("COMMIT");
  } catch (...) {
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
  checkpoint();
  highest_term_ = std::max(highest_term_, term);
}

void MissionJournal::record_epoch(int epoch, uint32_t term) {
  Statement(*this, "INSERT INTO epochs VALUES(?1, ?2, ?3, ?4)",
            {run_, static_cast<int64_t>(epoch), static_cast<int64_t>(term), fleet_transport::wall_clock_ms()})
      .run();
  checkpoint();
}

void MissionJournal::record_binding(int role, const std::string& robot_id) {
  Statement(*this, "INSERT OR REPLACE INTO bindings VALUES(?1, ?2, ?3)", {run_, static_cast<int64_t>(role), robot_id})
      .run();
  checkpoint();
}

void MissionJournal::record_visit(const fleet_transport::TaskVisit& visit, const std::string& robot_id, int epoch) {
  Statement(*this, "INSERT OR IGNORE INTO visits VALUES(?1, ?2, ?3, ?4, ?5, ?6)",
            {run_, static_cast<int64_t>(visit.task), static_cast<int64_t>(visit.role), robot_id,
             static_cast<int64_t>(epoch), fleet_transport::wall_clock_ms()})
      .run();
  count_row_written("visits");
  checkpoint();
}

void MissionJournal::record_task_added(int task, int x, int y, int role, const std::string& request_id) {
  Statement(*this, "INSERT OR IGNORE INTO tasks_added VALUES(?1, ?2, ?3, ?4, ?5, ?6, ?7)",
            {run_, static_cast<int64_t>(task), static_cast<int64_t>(x), static_cast<int64_t>(y),
             static_cast<int64_t>(role), request_id, fleet_transport::wall_clock_ms()})
      .run();
  count_row_written("tasks_added");
  checkpoint();
}

void MissionJournal::record_task_pinned(int task) {
  Statement(*this, "INSERT OR IGNORE INTO tasks_pinned VALUES(?1, ?2)", {run_, static_cast<int64_t>(task)}).run();
  checkpoint();
}

void MissionJournal::record_task_role(int task, int role) {
  Statement(*this, "UPDATE tasks_added SET role = ?1 WHERE run = ?2 AND task = ?3",
            {static_cast<int64_t>(role), run_, static_cast<int64_t>(task)})
      .run();
  checkpoint();
}

void MissionJournal::record_task_cancelled(int task, const std::string& request_id) {
  Statement(*this, "INSERT OR IGNORE INTO tasks_cancelled VALUES(?1, ?2, ?3, ?4)",
            {run_, static_cast<int64_t>(task), request_id, fleet_transport::wall_clock_ms()})
      .run();
  count_row_written("tasks_cancelled");
  checkpoint();
}

void MissionJournal::finish(const std::string& outcome) {
  if (run_ == 0) return;
  Statement(*this, "UPDATE runs SET ended_ms = ?1, outcome = ?2 WHERE run = ?3",
            {fleet_transport::wall_clock_ms(), outcome, run_})
      .run();
  checkpoint();
  resumable_.reset();
}

}  // namespace coordinator
