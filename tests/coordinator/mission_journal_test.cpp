// MissionJournal on real SQLite files in a temporary folder: what a restarted coordinator finds,
// and the files it must refuse.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <sqlite3.h>

#include "coordinator/mission_journal.hpp"

namespace coordinator {
namespace {

namespace fs = std::filesystem;

struct JournalTest : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("ctsfleet-journal-" + std::to_string(::getpid()) + "-" +
                                              ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::string path = (dir / "mission.journal").string();
  void SetUp() override { fs::create_directories(dir); }
  void TearDown() override { fs::remove_all(dir); }
};

// The message of the JournalError `open` throws ("" when it throws none).
template <typename Open>
std::string error_of(Open open) {
  try {
    open();
  } catch (const JournalError& e) {
    return e.what();
  }
  return "";
}

TEST_F(JournalTest, AnUnfinishedRunIsFoundAgainWithItsVisitsBindingsAndEpoch) {
  {
    MissionJournal journal(path, "aaaa", "test mission");
    EXPECT_FALSE(journal.resumable().has_value());
    EXPECT_EQ(journal.highest_term(), 0u);
    journal.claim(1, 0x11, 1000);
    journal.record_binding(0, "robot0");
    journal.record_binding(1, "robot1");
    journal.record_epoch(1, 1);
    journal.record_visit({3, 0}, "robot0", 1);
    journal.record_binding(1, "");  // robot1 lost
    journal.record_epoch(2, 1);
    journal.record_visit({5, 1}, "robot2", 2);
    journal.record_visit({5, 1}, "robot2", 2);  // recorded once
  }  // the process "dies" here: nothing closes the run
  MissionJournal journal(path, "aaaa", "test mission");
  ASSERT_TRUE(journal.resumable().has_value());
  const JournalResume& resume = *journal.resumable();
  EXPECT_EQ(resume.run, 1);
  EXPECT_EQ(resume.last_term, 1u);
  EXPECT_EQ(resume.last_epoch, 2);
  EXPECT_EQ(resume.bindings, (std::map<int, std::string>{{0, "robot0"}}));
  EXPECT_EQ(resume.visits, (std::vector<fleet_transport::TaskVisit>{{3, 0}, {5, 1}}));
  EXPECT_EQ(journal.highest_term(), 1u);
}

TEST_F(JournalTest, AFinishedRunIsNotResumedButTermsKeepGrowing) {
  {
    MissionJournal journal(path, "aaaa", "test mission");
    journal.claim(1, 0x11, 1000);
    journal.claim(2, 0x22, 2000);  // a takeover within the run
    journal.finish("completed");
  }
  MissionJournal journal(path, "aaaa", "test mission");
  EXPECT_FALSE(journal.resumable().has_value());
  EXPECT_EQ(journal.highest_term(), 2u);
}

TEST_F(JournalTest, AJournalOfAnotherMissionIsRefused) {
  { MissionJournal journal(path, "aaaa", "the first mission"); }
  const std::string error = error_of([&] { MissionJournal journal(path, "bbbb", "the second mission"); });
  EXPECT_NE(error.find("--journal " + path + ": the journal of another mission (aaaa: the first mission)"),
            std::string::npos)
      << error;
}

TEST_F(JournalTest, AJournalInUseByALiveCoordinatorIsRefused) {
  MissionJournal holder(path, "aaaa", "test mission");
  holder.claim(1, 0x11, 1000);
  const std::string error = error_of([&] { MissionJournal second(path, "aaaa", "test mission"); });
  EXPECT_NE(error.find("in use by another coordinator"), std::string::npos) << error;
  holder.record_visit({0, 0}, "robot0", 1);  // the holder is unharmed
}

TEST_F(JournalTest, AFileThatIsNoJournalIsRefusedAndLeftAlone) {
  {
    std::ofstream out(path);
    out << "robots: [1, 2, 3]\n";  // a YAML file given by mistake
  }
  const std::string error = error_of([&] { MissionJournal journal(path, "aaaa", "test mission"); });
  EXPECT_NE(error.find("not a readable journal"), std::string::npos) << error;
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "robots: [1, 2, 3]\n");
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs `sql` on a database of its own (another program's, or a journal behind the coordinator's back).
void run_sql(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  const int code = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error);
  const std::string message = error ? error : "";
  sqlite3_free(error);
  sqlite3_close(db);
  ASSERT_EQ(code, SQLITE_OK) << message;
}

TEST_F(JournalTest, AnSQLiteDatabaseOfAnotherProgramIsRefusedAndLeftAlone) {
  run_sql(path, "CREATE TABLE users(name TEXT, email TEXT); INSERT INTO users VALUES('ada', 'ada@example.org');");
  const std::string before = bytes_of(path);
  const std::string error = error_of([&] { MissionJournal journal(path, "aaaa", "test mission"); });
  EXPECT_NE(error.find("--journal " + path + ": not a ctsfleet journal but an SQLite database of another program"),
            std::string::npos) << error;
  EXPECT_NE(error.find("tables: users"), std::string::npos) << error;
  EXPECT_EQ(bytes_of(path), before) << "the other program's file was changed";
  EXPECT_FALSE(fs::exists(path + "-wal"));
  // Another program's database that happens to have a `meta` table is no journal either.
  const std::string other = (dir / "other.db").string();
  run_sql(other, "PRAGMA application_id=1234; CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);");
  EXPECT_NE(error_of([&] { MissionJournal journal(other, "aaaa", "test mission"); }).find("application id 0x4d2"),
            std::string::npos);
}

// Numbers edited into a journal past their type are refused naming the field, never wrapped.
TEST_F(JournalTest, NumbersPastTheirTypeAreRefusedNamingTheField) {
  const auto journal_with = [&](const std::string& sql) {
    fs::remove(path);
    {
      MissionJournal journal(path, "aaaa", "test mission");
      journal.claim(1, 0x11, 1000);
      journal.record_epoch(1, 1);
      journal.record_visit({3, 0}, "robot0", 1);
    }
    run_sql(path, sql);
    return error_of([&] { MissionJournal journal(path, "aaaa", "test mission"); });
  };
  const std::string role = journal_with("UPDATE visits SET role = 1099511627776");  // 2^40
  EXPECT_NE(role.find("visits.role is 1099511627776, not an integer in [0, 2147483647]"), std::string::npos) << role;
  const std::string epoch = journal_with("INSERT INTO epochs SELECT run, 9223372036854775807, 1, 1 FROM runs");
  EXPECT_NE(epoch.find("epochs.epoch is 9223372036854775807"), std::string::npos) << epoch;
  const std::string term = journal_with("UPDATE claims SET term = 4294967296");
  EXPECT_NE(term.find("claims.term is 4294967296"), std::string::npos) << term;
  const std::string negative = journal_with("UPDATE visits SET task = -1");
  EXPECT_NE(negative.find("visits.task is -1"), std::string::npos) << negative;
  const std::string text = journal_with("UPDATE visits SET task = 'three'");
  EXPECT_NE(text.find("visits.task is three"), std::string::npos) << text;
}

// A journal that lost rows it once held (an older copy put back, a file cut short) resumes from
// what it holds, and says how much is missing; one that lost nothing says nothing.
TEST_F(JournalTest, AResumeThatFindsLessThanTheFileOnceHeldIsCounted) {
  {
    MissionJournal journal(path, "aaaa", "test mission");
    journal.claim(1, 0x11, 1000);
    journal.record_visit({3, 0}, "robot0", 1);
    journal.record_visit({3, 0}, "robot0", 1);  // a repeat: one row, counted once
    journal.record_visit({4, 1}, "robot1", 1);
    journal.record_visit({5, 1}, "robot1", 1);
    journal.record_task_added(20, 1, 1, 0, "a");
  }
  {
    MissionJournal journal(path, "aaaa", "test mission");
    ASSERT_TRUE(journal.resumable().has_value());
    EXPECT_EQ(journal.resumable()->lost_records, 0);
    EXPECT_EQ(journal.resumable()->visits.size(), 3u);
  }
  run_sql(path, "DELETE FROM visits WHERE task = 5; DELETE FROM tasks_added;");
  MissionJournal journal(path, "aaaa", "test mission");
  ASSERT_TRUE(journal.resumable().has_value());
  EXPECT_EQ(journal.resumable()->visits.size(), 2u);
  EXPECT_EQ(journal.resumable()->lost_records, 2);
}

// The main file alone is the whole journal after every record: a copy made without its -wal (a
// backup tool, a careless cp) resumes the mission where it was.
TEST_F(JournalTest, TheMainFileAloneHoldsEveryRecord) {
  const std::string copy = (dir / "copy.journal").string();
  {
    MissionJournal journal(path, "aaaa", "test mission");
    journal.claim(1, 0x11, 1000);
    journal.record_binding(0, "robot0");
    journal.record_epoch(3, 1);
    journal.record_visit({5, 0}, "robot0", 3);
    fs::copy_file(path, copy);  // while the coordinator runs, without the -wal beside it
  }
  MissionJournal resumed(copy, "aaaa", "test mission");
  ASSERT_TRUE(resumed.resumable().has_value());
  EXPECT_EQ(resumed.resumable()->last_epoch, 3);
  ASSERT_EQ(resumed.resumable()->visits.size(), 1u);
  EXPECT_EQ(resumed.resumable()->visits[0], (fleet_transport::TaskVisit{5, 0}));
  EXPECT_EQ(resumed.resumable()->bindings.at(0), "robot0");
}

// A disk that fills: the write fails with a JournalError naming the file, and the journal stays
// usable for reading what it holds (the coordinator goes on from memory: fleet_coordinator_test).
TEST_F(JournalTest, AFullDiskIsAnErrorNamingTheFile) {
  MissionJournal journal(path, "aaaa", "test mission");
  journal.claim(1, 0x11, 1000);
  journal.limit_size_for_test(1);
  std::string error;
  for (int visit = 0; visit < 1000 && error.empty(); ++visit) {
    error = error_of([&] { journal.record_visit({visit, 0}, "robot0-with-a-long-name-to-fill-pages", 1); });
  }
  EXPECT_NE(error.find("--journal " + path), std::string::npos) << error;
  EXPECT_NE(error.find("full"), std::string::npos) << error;
}

TEST_F(JournalTest, AFolderThatCannotHoldTheFileIsNamed) {
  const std::string missing = (dir / "no-such-folder" / "mission.journal").string();
  const std::string error = error_of([&] { MissionJournal journal(missing, "aaaa", "test mission"); });
  EXPECT_NE(error.find("--journal " + missing), std::string::npos) << error;
}

TEST_F(JournalTest, TasksAddedAndCancelledAtRuntimeAreFoundAgain) {
  {
    MissionJournal journal(path, "aaaa", "test mission");
    journal.claim(1, 0x11, 1000);
    journal.record_task_added(16, 4, 2, 3, "request-a");
    journal.record_task_added(17, 1, 1, 0, "request-b");
    journal.record_task_cancelled(17, "request-c");
    journal.record_task_cancelled(17, "request-c");  // a repeat changes nothing
  }
  MissionJournal again(path, "aaaa", "test mission");
  ASSERT_TRUE(again.resumable().has_value());
  const auto& added = again.resumable()->added_tasks;
  ASSERT_EQ(added.size(), 2u);
  EXPECT_EQ(added[0].task, 16);
  EXPECT_EQ(added[0].x, 4);
  EXPECT_EQ(added[0].y, 2);
  EXPECT_EQ(added[0].role, 3);
  EXPECT_EQ(added[1].task, 17);
  EXPECT_EQ(again.resumable()->cancelled_tasks, std::vector<int>{17});
}

TEST(MissionFingerprint, SameMissionSameFingerprintAnyChangeAnother) {
  auto graph = std::make_shared<const planner_core::Graph>(3, 2, std::vector<std::string>{"...", ".@."});
  planner_core::Instance mission;
  mission.graph = graph;
  mission.starts = {graph->vertex_at({0, 0})};
  mission.goals = {graph->vertex_at({2, 1})};
  mission.tasks = {{graph->vertex_at({1, 0}), {0}}};
  mission.index_tasks();
  const std::string fingerprint = mission_fingerprint(mission);
  EXPECT_EQ(fingerprint.size(), 16u);
  EXPECT_EQ(mission_fingerprint(mission), fingerprint);
  planner_core::Instance moved = mission;
  moved.tasks[0].at = graph->vertex_at({2, 0});
  EXPECT_NE(mission_fingerprint(moved), fingerprint);
  planner_core::Instance other_goal = mission;
  other_goal.goals = {graph->vertex_at({0, 1})};
  EXPECT_NE(mission_fingerprint(other_goal), fingerprint);
}

}  // namespace
}  // namespace coordinator
