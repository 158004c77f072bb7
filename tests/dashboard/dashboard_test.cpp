// The dashboard's parts without DDS or a browser: the JSON of every wire message, FleetView (what
// the page is told about robots, tasks and coordinators), history files and plans as histories.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "dashboard/fleet_view.hpp"
#include "dashboard/history.hpp"
#include "dashboard/message_json.hpp"
#include "dashboard/playback.hpp"
#include "planner_core/input_error.hpp"

namespace dashboard {
namespace {

namespace fs = std::filesystem;
using fleet_transport::RobotStatus;

// Written as JSON and read back, a message says the same.
template <typename Message>
void expect_round_trip(const Message& message) {
  const Json written = message;
  const Message read = written.get<Message>();
  EXPECT_EQ(Json(read), written) << written.dump();
}

TEST(MessageJson, EveryMessageRoundTripsWithItsFieldNames) {
  fleet_transport::RobotState state;
  state.robot_id = "robot7";
  state.cell_x = 3;
  state.pose_x = 3.25;
  state.status = RobotStatus::kMoving;
  state.seq_number = 18446744073709551615ull;  // uint64 survives
  state.stamp_ms = 1796196321817;
  state.heading = 2;
  expect_round_trip(state);
  EXPECT_EQ(Json(state).at("status"), "moving");
  EXPECT_EQ(Json(state).at("robot_id"), "robot7");
  expect_round_trip(fleet_transport::Announcement{"r", "toio", "", "1.0", true, 42});
  expect_round_trip(fleet_transport::StepCommand{"r", 2, 3, 4, 5, 4.0, 5.0, 99, 7, 98});
  expect_round_trip(fleet_transport::CoordinatorStatus{0xABCDEF0123456789ull, 3, 5, fleet_transport::CoordinatorRole::kStandby,
                                                       "m", 4});
  EXPECT_EQ(Json(fleet_transport::CoordinatorStatus{}).at("role"), "active");
  fleet_transport::FleetStatus status;
  status.assignments = {{"a", 0, 1, 2}};
  status.done_visits = {{3, 0}};
  status.round_trip_p99_ms = 4.5;
  expect_round_trip(status);
  expect_round_trip(fleet_transport::MissionInfo{1, "m", 2, 1, "..", {{0, 0}}, {{1, 0, {0}, true}}, true});
  expect_round_trip(fleet_transport::FleetPlan{1, 2, 3, 4.5, 6, {{"a", 0, {{0, 0}, {1, 0}}}}});
  expect_round_trip(fleet_transport::FleetEvent{1, 2, "lost", "a", "said goodbye", 0});
  expect_round_trip(fleet_transport::TaskRequest{"id", fleet_transport::TaskAction::kCancel, 1, 2, "", 5});
  EXPECT_EQ(Json(fleet_transport::TaskRequest{}).at("action"), "add");
  expect_round_trip(fleet_transport::TaskReply{"id", 1, true, "ok", 3, "a", "task 0 ...\n"});
  // A recording made before headings existed loads, heading unknown.
  Json before_headings = state;
  before_headings.erase("heading");
  EXPECT_EQ(before_headings.get<fleet_transport::RobotState>().heading, -1);
  Json command = fleet_transport::StepCommand{"r", 2, 3, 4, 5, 4.0, 5.0, 99, 7, 98};
  command.erase("target_heading");
  EXPECT_EQ(command.get<fleet_transport::StepCommand>().target_heading, -1);
  // A message missing a field is refused, naming it.
  Json broken = state;
  broken.erase("cell_y");
  try {
    (void)broken.get<fleet_transport::RobotState>();
    FAIL() << "accepted a state without cell_y";
  } catch (const nlohmann::json::exception& e) {
    EXPECT_NE(std::string(e.what()).find("cell_y"), std::string::npos) << e.what();
  }
}

// A 4x1 corridor with one coordinator, two robots and three tasks.
struct ViewTest : ::testing::Test {
  FleetView view{2.0};
  static constexpr uint64_t kCoordinator = 0x10;

  void SetUp() override {
    view.on_coordinator_status({kCoordinator, 1, 100, fleet_transport::CoordinatorRole::kActive, "m", 1}, 1000);
    // Tasks: 0 at (2,0) for role 0; 1 at (3,0) for role 0; 2 at (1,0) for role 1 (no robot has role 1).
    view.on_mission({kCoordinator, "m", 4, 1, "....", {{3, 0}, {0, 0}}, {{2, 0, {0}, false}, {3, 0, {0}, false},
                                                                         {1, 0, {1}, false}}, false},
                    1000);
    view.on_plan({kCoordinator, 1, 1000, 5, 3, {{"a", 0, {{0, 0}, {1, 0}, {2, 0}, {3, 0}}}}}, 1000);
    fleet_transport::FleetStatus status;
    status.coordinator = kCoordinator;
    status.assignments = {{"a", 0, 0, 2}, {"b", -1, 0, 0}};
    view.on_fleet_status(status, 1000);
  }
  fleet_transport::RobotState state(const std::string& id, int x, int action, RobotStatus status, uint64_t seq) {
    fleet_transport::RobotState s;
    s.robot_id = id;
    s.cell_x = x;
    s.plan_epoch = 1;
    s.action_index = action;
    s.status = status;
    s.seq_number = seq;
    s.coordinator = kCoordinator;
    s.incarnation = 5;
    return s;
  }
};

TEST_F(ViewTest, RobotsAreMovingWaitingParkedLostOrLeft) {
  view.on_state(state("a", 0, -1, RobotStatus::kIdle, 1), 1000);
  EXPECT_EQ(view.robot_status("a", 1000), "waiting");  // in the plan, not started
  EXPECT_EQ(view.path_from("a"), 1);
  view.on_state(state("a", 0, 0, RobotStatus::kMoving, 2), 1100);
  EXPECT_EQ(view.robot_status("a", 1100), "moving");
  EXPECT_EQ(view.path_from("a"), 1);  // on its way to path[1]
  view.on_state(state("a", 1, 0, RobotStatus::kArrived, 3), 1200);
  EXPECT_EQ(view.robot_status("a", 1200), "waiting");
  EXPECT_EQ(view.path_from("a"), 2);
  view.on_state(state("a", 0, 0, RobotStatus::kMoving, 2), 1250);  // late, out of order: ignored
  EXPECT_EQ(view.path_from("a"), 2);
  view.on_state(state("a", 3, 2, RobotStatus::kArrived, 4), 1300);
  EXPECT_EQ(view.robot_status("a", 1300), "parked");
  EXPECT_EQ(view.robot_status("a", 3301), "lost");  // nothing heard for 2 s
  view.on_state(state("a", 3, 2, RobotStatus::kFault, 5), 3400);
  EXPECT_EQ(view.robot_status("a", 3400), "fault");
  view.on_state(state("a", 3, 2, RobotStatus::kArrived, 6), 3500);
  view.on_event({kCoordinator, 3500, "off_plan", "a", "moved by hand", 0}, 3500);
  EXPECT_EQ(view.robot_status("a", 3500), "off_plan");
  view.on_event({kCoordinator, 3600, "join", "a", "back", 0}, 3600);
  EXPECT_EQ(view.robot_status("a", 3600), "parked");
  view.on_robot_gone("a", fleet_transport::GoneReason::kLivelinessLost, 3700);
  EXPECT_EQ(view.robot_status("a", 3700), "lost");
  view.on_announcement({"a", "sim", "", "1", true, 5}, 3800);
  EXPECT_EQ(view.robot_status("a", 3800), "left");
  EXPECT_EQ(view.robot_status("nobody", 3800), "unknown");
}

TEST_F(ViewTest, NextTasksFollowThePlanAndTaskStatesFollowTheVisits) {
  view.on_state(state("a", 0, -1, RobotStatus::kIdle, 1), 1000);
  view.on_state(state("b", 1, -1, RobotStatus::kIdle, 1), 1000);
  EXPECT_EQ(view.next_tasks("a"), (std::vector<int>{0, 1}));  // (2,0) comes before (3,0) on its path
  EXPECT_TRUE(view.next_tasks("b").empty());                  // no role
  Json frame = view.frame_json(1000);
  EXPECT_EQ(frame["tasks"], Json({"pending", "pending", "unassigned"}));
  fleet_transport::FleetStatus status;
  status.coordinator = kCoordinator;
  status.assignments = {{"a", 0, 1, 2}};
  status.done_visits = {{0, 0}};
  view.on_fleet_status(status, 1100);
  EXPECT_EQ(view.next_tasks("a"), (std::vector<int>{1}));
  frame = view.frame_json(1100);
  EXPECT_EQ(frame["tasks"][0], "done");
  EXPECT_EQ(frame["robots"][0]["id"], "a");
  EXPECT_EQ(frame["robots"][0]["next_tasks"], Json({1}));
  EXPECT_EQ(frame["coordinator"]["role"], "active");
  EXPECT_EQ(frame["coordinator"]["id"], "0000000000000010");  // a string: JavaScript numbers lose 64-bit ids
}

TEST_F(ViewTest, TheHighestRankedActiveCoordinatorIsFollowed) {
  const int mission_version = view.mission_version();
  // A standby is heard: nothing changes. It takes over with a higher term: it is followed.
  view.on_coordinator_status({0x20, 1, 50, fleet_transport::CoordinatorRole::kStandby, "m", 1}, 1500);
  EXPECT_EQ(view.mission_version(), mission_version);
  view.on_mission({0x20, "m", 4, 1, "....", {{3, 0}, {0, 0}}, {}, false}, 1600);
  EXPECT_EQ(view.mission_json()["tasks"].size(), 3u);  // still the active one's
  view.on_coordinator_status({0x20, 2, 2000, fleet_transport::CoordinatorRole::kActive, "m", 2}, 2000);
  EXPECT_GT(view.mission_version(), mission_version);
  EXPECT_EQ(view.mission_json()["tasks"].size(), 0u);
  EXPECT_EQ(view.frame_json(2000)["coordinator"]["term"], 2);
}

// The schedule of a lifelong fleet: a task its robot's plan reaches is in the plan, with the steps to
// it; one it does not reach yet waits in the pool; a role without a robot leaves its task unassigned.
TEST_F(ViewTest, ALifelongFleetsTasksAreInAPlanWithTheirStepsInThePoolOrUnassigned) {
  // Lifelong, and task 3 at (0,0) for role 0 was added: robot a, already at (1,0) on its path
  // (0,0)..(3,0), has left that cell behind.
  view.on_mission({kCoordinator, "m", 4, 1, "....", {{3, 0}, {0, 0}},
                   {{2, 0, {0}, false}, {3, 0, {0}, false}, {1, 0, {1}, false}, {0, 0, {0}, false}}, true},
                  1000);
  view.on_state(state("a", 1, 0, RobotStatus::kArrived, 1), 1000);  // at (1,0): (0,0) is behind it
  const std::vector<FleetView::Due> due = view.schedule("a");
  ASSERT_EQ(due.size(), 3u);
  EXPECT_EQ(due[0].task, 0);  // (2,0): one step on from the cell it stands on
  EXPECT_EQ(due[0].steps, 1);
  EXPECT_EQ(due[1].task, 1);  // (3,0): two
  EXPECT_EQ(due[1].steps, 2);
  EXPECT_EQ(due[2].task, 3);  // (0,0): behind it, not in its plan
  EXPECT_EQ(due[2].steps, FleetView::kNotPlanned);
  Json frame = view.frame_json(1000);
  EXPECT_EQ(frame["tasks"], Json({"pending", "pending", "unassigned", "pool"}));
  EXPECT_EQ(frame["schedule"]["in_plans"], 2);
  EXPECT_EQ(frame["schedule"]["pool"], 1);
  EXPECT_EQ(frame["schedule"]["unassigned"], 1);
  EXPECT_EQ(frame["robots"][0]["planned_tasks"], 2);
  EXPECT_EQ(frame["robots"][0]["task_steps"], 1);
  // The same tasks in a one-shot mission: the next plan takes every task, none waits in a pool.
  view.on_mission({kCoordinator, "m", 4, 1, "....", {{3, 0}, {0, 0}},
                   {{2, 0, {0}, false}, {3, 0, {0}, false}, {1, 0, {1}, false}, {0, 0, {0}, false}}, false},
                  1100);
  frame = view.frame_json(1100);
  EXPECT_EQ(frame["tasks"][3], "pending");
  EXPECT_EQ(frame["schedule"]["pool"], 0);
}

// A robot is delayed when its move has lasted more than kLateFactor times the fleet's typical move
// (the median of the moves the dashboard saw, from first state moving to first state arrived);
// never before enough moves were seen, never once it has arrived, and not a robot waiting its turn.
TEST_F(ViewTest, ARobotMovingForLongerThanTwiceTheTypicalMoveIsDelayed) {
  int64_t t = 1000;
  uint64_t seq = 0;
  auto move = [&](const std::string& id, int action, int64_t lasting_ms) {
    view.on_state(state(id, 0, action, RobotStatus::kMoving, ++seq), t);
    view.on_state(state(id, 0, action, RobotStatus::kMoving, ++seq), t + lasting_ms / 2);  // a state mid-move
    t += lasting_ms;
    view.on_state(state(id, 0, action, RobotStatus::kArrived, ++seq), t);
  };
  // Too few moves seen: a long move is not called delayed.
  view.on_state(state("a", 0, 0, RobotStatus::kMoving, ++seq), t);
  EXPECT_EQ(view.robot_status("a", t + 1500), "moving");
  EXPECT_EQ(view.typical_move_ms(), -1);
  view.on_state(state("a", 0, 0, RobotStatus::kArrived, ++seq), t + 200);
  t += 200;
  for (int k = 1; static_cast<size_t>(k) <= FleetView::kMovesForTypical; ++k) move("a", k, k % 2 ? 190 : 210);
  EXPECT_EQ(view.typical_move_ms(), 200);
  const int next = static_cast<int>(FleetView::kMovesForTypical) + 1;
  view.on_state(state("a", 0, next, RobotStatus::kMoving, ++seq), t);
  EXPECT_EQ(view.robot_status("a", t + 350), "moving");
  EXPECT_EQ(view.robot_status("a", t + 450), "delayed");
  Json frame = view.frame_json(t + 450);
  EXPECT_EQ(frame["schedule"]["delayed"], Json({"a"}));
  EXPECT_EQ(frame["schedule"]["typical_move_ms"], 200);
  EXPECT_EQ(frame["schedule"]["late_after_ms"], 400.0);
  EXPECT_EQ(frame["robots"][0]["moving_ms"], 450);
  // A state of the same move mid-way does not restart its clock; arriving ends it.
  view.on_state(state("a", 0, next, RobotStatus::kMoving, ++seq), t + 460);
  EXPECT_EQ(view.robot_status("a", t + 470), "delayed");
  view.on_state(state("a", 1, next, RobotStatus::kArrived, ++seq), t + 500);
  EXPECT_EQ(view.robot_status("a", t + 1500), "parked");  // action 21 is past its 3-action plan
  EXPECT_EQ(view.frame_json(t + 500)["schedule"]["delayed"], Json::array());
  // A restarted process (a new incarnation) with the same command starts a move of its own.
  fleet_transport::RobotState restarted = state("a", 1, next, RobotStatus::kMoving, 1);
  restarted.incarnation = 6;
  view.on_state(restarted, t + 1000);
  EXPECT_EQ(view.robot_status("a", t + 1100), "moving");
}

struct HistoryTest : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("ctsfleet-history-" + std::to_string(::getpid()) + "-" +
                                              ::testing::UnitTest::GetInstance()->current_test_info()->name());
  void SetUp() override { fs::create_directories(dir); }
  void TearDown() override { fs::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir / name).string();
    std::ofstream(path) << text;
    return path;
  }
  static std::string error_of(const std::string& path) {
    try {
      load_history(path);
    } catch (const planner_core::InputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(HistoryTest, WhatIsRecordedReplaysInTimeOrder) {
  const std::string path = (dir / "h.jsonl").string();
  {
    HistoryRecorder recorder(path);
    fleet_transport::RobotState s;
    s.robot_id = "a";
    s.seq_number = 2;
    s.cell_x = 2;
    recorder.write({200, "state", s});
    s.seq_number = 1;
    s.cell_x = 1;
    recorder.write({100, "state", s});
    recorder.write({150, "gone", {{"robot_id", "b"}, {"reason", "goodbye"}}});
  }
  const std::vector<HistoryEntry> entries = load_history(path);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[0].t_ms, 100);
  EXPECT_EQ(entries[2].t_ms, 200);
  FleetView view;
  for (const HistoryEntry& entry : entries) apply(view, entry);
  EXPECT_EQ(view.frame_json(200)["robots"][0]["x"], 2);
  EXPECT_EQ(view.robot_status("b", 200), "left");
}

TEST_F(HistoryTest, BadFilesAreRefusedNamingTheLine) {
  const std::string header = "{\"format\": \"ctsfleet-history-1\"}\n";
  EXPECT_NE(error_of(write("empty", "")).find("empty"), std::string::npos);
  EXPECT_NE(error_of(write("other", "{\"format\": \"x\"}\n")).find("other:1: not a ctsfleet history"), std::string::npos);
  // Found by fuzz.file_readers: a format that is no string threw nlohmann's type error (exit 1).
  EXPECT_NE(error_of(write("number", "{\"format\": 33}\n")).find("number:1: not a ctsfleet history"), std::string::npos);
  EXPECT_NE(error_of(write("json", header + "{\"t\": 1, \n")).find("json:2: not JSON"), std::string::npos);
  EXPECT_NE(error_of(write("key", header + "{\"t\": 1, \"type\": \"state\"}\n")).find("key:2:"), std::string::npos);
  EXPECT_NE(error_of(write("type", header + "{\"t\": 1, \"type\": \"teleport\", \"msg\": {}}\n"))
                .find("type:2: unknown message type 'teleport'"),
            std::string::npos);
  const std::string field = error_of(write("field", header + "{\"t\": 1, \"type\": \"state\", \"msg\": {\"robot_id\": 3}}\n"));
  EXPECT_NE(field.find("field:2: a 'state' message"), std::string::npos) << field;
  EXPECT_NE(error_of((dir / "missing").string()).find("cannot open"), std::string::npos);
}

TEST_F(HistoryTest, NumbersPastTheirTypeAndUnknownWordsAreRefusedNamingTheField) {
  const std::string header = "{\"format\": \"ctsfleet-history-1\"}\n";
  const auto state_with = [&](const std::string& name, const std::string& field, const std::string& value) {
    Json state = fleet_transport::RobotState{"r1", 1, 2, 1, 2, 0, 1, 0, fleet_transport::RobotStatus::kIdle, 50, 1, 1, 1, 1};
    std::string line = Json{{"t", 1}, {"type", "state"}, {"msg", state}}.dump();
    const std::string key = "\"" + field + "\":";
    const size_t at = line.find(key) + key.size();
    line.replace(at, line.find_first_of(",}", at) - at, value);
    return error_of(write(name, header + line + "\n"));
  };
  EXPECT_EQ(state_with("fine", "cell_x", "7"), "");
  const std::string wide = state_with("wide", "cell_x", "4294967320");  // 2^32 + 24: read as 24 before
  EXPECT_NE(wide.find("wide:2: field cell_x is 4294967320, which its type cannot hold"),
            std::string::npos) << wide;
  EXPECT_NE(state_with("low", "plan_epoch", "-2147483649").find("field plan_epoch is -2147483649"), std::string::npos);
  EXPECT_NE(state_with("fraction", "action_index", "1.5").find("field action_index is 1.5"), std::string::npos);
  // Found by fuzz.file_readers: a float past int64 where an integer goes was cast (undefined
  // behaviour) before it was checked.
  const std::string huge = state_with("huge", "stamp_ms", "1e140");
  EXPECT_NE(huge.find("field stamp_ms is 1e+140, not an integer"), std::string::npos) << huge;
  EXPECT_NE(state_with("negative", "seq_number", "-1.5").find("field seq_number is -1.5"), std::string::npos);
  EXPECT_NE(state_with("word", "status", "\"flying\"").find("field status is \"flying\""), std::string::npos);
  const std::string cut = state_with("long", "cell_y", std::string(500, '9'));
  EXPECT_LT(cut.size(), 400u) << cut;  // the 500 digits are echoed cut
  // The time of a line too.
  const std::string time = error_of(write("time", header + "{\"t\": 1.5, \"type\": \"state\", \"msg\": {}}\n"));
  EXPECT_NE(time.find("time:2: field t is 1.5"), std::string::npos) << time;
  // Nested: a plan's cell.
  Json plan = fleet_transport::FleetPlan{1, 1, 0, 0, 0, {{"r1", 0, {{1, 2}, {1, 3}}}}};
  plan["robots"][0]["path"][1]["y"] = 4294967296ULL;
  const std::string nested = error_of(write("nested", header + Json{{"t", 1}, {"type", "plan"}, {"msg", plan}}.dump() + "\n"));
  EXPECT_NE(nested.find("field robots[0].path[1].y is 4294967296"), std::string::npos) << nested;
}

// Two agents on a 3x2 map, each with one task on its way, and the plan that does it in 2 steps.
struct TinyPlan : ::testing::Test {
  planner_core::Instance instance;
  planner_core::Solution solution;
  planner_core::Vertex v(int x, int y) const { return instance.graph->vertex_at({x, y}); }
  void SetUp() override {
    instance.graph = std::make_shared<const planner_core::Graph>(3, 2, std::vector<std::string>{"...", "..."});
    instance.starts = {v(0, 0), v(0, 1)};
    instance.goals = {v(2, 0), v(2, 1)};
    instance.tasks = {{v(1, 0), {0}}, {v(1, 1), {1}}};
    instance.index_tasks();
    instance.source = "tiny";
    solution = {{v(0, 0), v(0, 1)}, {v(1, 0), v(1, 1)}, {v(2, 0), v(2, 1)}};
  }
};

TEST_F(TinyPlan, APlanPlaysToTheEndWithEveryTaskDone) {
  PlanPlayback playback(instance, solution, 100, "tiny.txt");
  EXPECT_EQ(playback.end_ms(), 200);
  const std::vector<HistoryEntry> entries = all_entries(playback);
  FleetView view;
  for (const HistoryEntry& entry : entries) apply(view, entry);
  const Json frame = view.frame_json(entries.back().t_ms);
  EXPECT_EQ(frame["tasks"], Json({"done", "done"}));
  EXPECT_EQ(frame["robots"][0]["status"], "parked");
  EXPECT_EQ(frame["robots"][0]["x"], 2);
  EXPECT_NE(frame["events"][0]["text"].get<std::string>().find("valid, flowtime 4"), std::string::npos);
}

TEST_F(TinyPlan, APlanThatDoesNotSolveItsInstanceIsRefusedNamingTheFault) {
  const auto refusal = [&](planner_core::Solution plan) {
    try {
      PlanPlayback playback(instance, std::move(plan), 100, "bad.txt");
    } catch (const planner_core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // Two agents on one cell.
  EXPECT_NE(refusal({{v(0, 0), v(0, 1)}, {v(1, 0), v(1, 0)}, {v(2, 0), v(2, 1)}}).find("bad.txt: not a valid plan of tiny"),
            std::string::npos);
  // Ends short of the goals; jumps two cells and so skips its task.
  EXPECT_NE(refusal({{v(0, 0), v(0, 1)}, {v(1, 0), v(1, 1)}}).find("bad.txt"), std::string::npos);
  EXPECT_NE(refusal({{v(0, 0), v(0, 1)}, {v(2, 0), v(1, 1)}, {v(2, 0), v(2, 1)}}).find("bad.txt"), std::string::npos);
  // A plan that waits a step more is still valid.
  EXPECT_EQ(refusal({{v(0, 0), v(0, 1)}, {v(0, 0), v(1, 1)}, {v(1, 0), v(2, 1)}, {v(2, 0), v(2, 1)}}), "accepted");
  EXPECT_NE(refusal({}).find("bad.txt: no timesteps"), std::string::npos);
}

TEST(PlanPlaybackTest, ALongPlanIsSentInWindowsAndTheRobotsStayOnThem) {
  // One agent walking 100 cells east: the page gets the plan 32 steps at a time, and at every step
  // the robot's place in the window is where it stands.
  planner_core::Instance line;
  line.graph = std::make_shared<const planner_core::Graph>(101, 1, std::vector<std::string>{std::string(101, '.')});
  line.starts = {line.graph->vertex_at({0, 0})};
  line.goals = {line.graph->vertex_at({100, 0})};
  line.index_tasks();
  line.source = "line";
  planner_core::Solution walk;
  for (int x = 0; x <= 100; ++x) walk.push_back({line.graph->vertex_at({x, 0})});
  PlanPlayback playback(line, walk, 10, "walk.txt");
  FleetView view;
  int plans = 0;
  for (int64_t t = 0; t <= playback.end_ms(); t += 10) {
    playback.play_until(t, [&](const HistoryEntry& entry) {
      plans += entry.type == "plan";
      apply(view, entry);
    });
    const Json robot = view.frame_json(t)["robots"][0];
    const Json path = view.plan_json()["robots"]["agent0"]["path"];
    ASSERT_LE(path.size(), static_cast<size_t>(PlanPlayback::kPlanWindow + 1));
    const int from = robot["path_from"].get<int>();
    ASSERT_GE(from, 1);
    if (t < playback.end_ms()) {
      ASSERT_LT(from, static_cast<int>(path.size())) << "at " << t;
      EXPECT_EQ(path[from - 1], Json::array({robot["x"], 0})) << "at " << t;  // it stands on (or leaves) path[from-1]
    }
  }
  EXPECT_EQ(plans, 4);  // steps 0, 32, 64, 96
  EXPECT_EQ(view.frame_json(playback.end_ms())["robots"][0]["status"], "parked");
}

TEST_F(TinyPlan, ARunBecomesAPlanForTheSvgPicture) {
  PlanPlayback playback(instance, solution, 100, "run.txt");
  const HistoryPicture picture = history_picture(all_entries(playback), "run");
  EXPECT_EQ(picture.robots, (std::vector<std::string>{"agent0", "agent1"}));
  EXPECT_EQ(picture.instance.starts, instance.starts);
  EXPECT_EQ(picture.instance.goals, instance.goals);
  ASSERT_EQ(picture.instance.tasks.size(), 2u);
  EXPECT_EQ(picture.instance.tasks[1].agents, std::vector<int>{1});
  EXPECT_EQ(picture.solution.size(), 5u);  // the start, then one step per robot's move
  EXPECT_EQ(picture.solution.back(), instance.goals);
  // Nothing to draw: said, naming the file.
  std::vector<HistoryEntry> no_mission = {{0, "state", fleet_transport::RobotState{}}};
  try {
    history_picture(no_mission, "empty.jsonl");
    FAIL() << "drew a history without a mission";
  } catch (const planner_core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("empty.jsonl: no mission"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dashboard
