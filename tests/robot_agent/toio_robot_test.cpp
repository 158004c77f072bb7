// ToioRobot through its real BlueZ D-Bus code path, against the cube emulator on a private bus:
// connect, move, and every fault (lifted, between cells, link lost, cube absent, no bus).
#include "robot_agent/toio_robot.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "emulated_bluez.hpp"

namespace robot_agent {
namespace {

using testing::EmulatedBluez;
using testing::eventually;

const std::string kRing = CTSFLEET_CONFIG_DIR "/mats/toio-collection-ring.yaml";

ToioSettings settings_for(const std::string& cube) {
  ToioSettings settings;
  settings.cube = cube;
  settings.discovery_timeout_s = 5;
  settings.reconnect_backoff_min_s = 0.2;
  settings.reconnect_backoff_max_s = 1;
  return settings;
}

bool ready(ToioRobot& robot) { return !robot.poll().fault; }

void move_and_arrive(ToioRobot& robot, EmulatedBluez& bluez, const std::string& cube, Cell target) {
  ASSERT_TRUE(robot.start_move(target, -1));
  EXPECT_TRUE(robot.poll().moving);
  ASSERT_TRUE(eventually([&] { return !robot.poll().moving; })) << "no arrival at " << target.x << "," << target.y;
  const BackendReport report = robot.poll();
  EXPECT_FALSE(report.fault) << robot.fault_reason();
  EXPECT_EQ(report.cell, target);
  EXPECT_GT(report.arrived_ms, 0);
  // Arrival is declared within the spec's reach (15 units); the cube settles on the centre.
  const Eigen::Vector2d centre = robot.calibration().cell_centre(target);
  EXPECT_LE((Eigen::Vector2d(bluez.pose(cube).x, bluez.pose(cube).y) - centre).norm(), 15.5);
  EXPECT_TRUE(eventually([&] {
    const testing::EmulatedCubePose pose = bluez.pose(cube);
    return (Eigen::Vector2d(pose.x, pose.y) - centre).norm() < 2.0;
  }));
}

// The cube's angle on the mat, as a grid heading's distance from `heading` in degrees.
double degrees_off(ToioRobot& robot, EmulatedBluez& bluez, const std::string& cube, int heading) {
  return std::abs(std::remainder(bluez.pose(cube).angle - robot.calibration().heading_on_mat_deg(heading), 360.0));
}

TEST(ToioRobot, TurnsInPlaceToAHeadingAndReportsTheHeadingItFaces) {
  EmulatedBluez bluez({"toio-a@cell:2,2"});
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason() << "\n" << bluez.log();
  const int start = robot.poll().heading;
  ASSERT_GE(start, 0);
  EXPECT_TRUE(robot.start_move({2, 2}, start));  // already facing it: a wait, nothing to drive
  EXPECT_FALSE(robot.poll().moving);
  for (const int heading : {(start + 1) % 4, (start + 3) % 4, (start + 2) % 4}) {
    SCOPED_TRACE("turning to heading " + std::to_string(heading));
    ASSERT_TRUE(robot.start_move({2, 2}, heading));
    EXPECT_TRUE(robot.poll().moving);
    ASSERT_TRUE(eventually([&] { return !robot.poll().moving; })) << bluez.log();
    const BackendReport report = robot.poll();
    EXPECT_FALSE(report.fault) << robot.fault_reason();
    EXPECT_EQ(report.cell, (Cell{2, 2}));
    // Done within the 10 degrees that count as facing (a Position ID may say so before the 83
    // response); the cube then settles on the heading.
    EXPECT_LE(degrees_off(robot, bluez, "toio-a", heading), 10.5);
    EXPECT_TRUE(eventually([&] { return degrees_off(robot, bluez, "toio-a", heading) < 1.0; }));
    EXPECT_TRUE(eventually([&] { return robot.poll().heading == heading; }));
  }
  // A move with a heading ends facing it (the way it went).
  const Cell ahead = robot.poll().heading == 0 ? Cell{3, 2} : robot.poll().heading == 1 ? Cell{2, 3}
                     : robot.poll().heading == 2 ? Cell{1, 2} : Cell{2, 1};
  const int facing = robot.poll().heading;
  move_and_arrive(robot, bluez, "toio-a", ahead);
  EXPECT_TRUE(eventually([&] { return robot.poll().heading == facing; }));
}

TEST(ToioRobot, ConnectsThenMovesACubeThreeCells) {
  EmulatedBluez bluez({"toio-a@cell:1,1", "toio-b@cell:5,5"});
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason() << "\n" << bluez.log();
  EXPECT_TRUE(robot.connected());
  EXPECT_EQ(robot.poll().cell, (Cell{1, 1}));
  EXPECT_EQ(robot.poll().battery_percent, 90);
  EXPECT_GE(bluez.pose("toio-a").light_writes, 1);  // identified itself with its light
  EXPECT_FALSE(bluez.pose("toio-b").connected);      // the other cube is left alone
  move_and_arrive(robot, bluez, "toio-a", {2, 1});
  move_and_arrive(robot, bluez, "toio-a", {2, 2});
  move_and_arrive(robot, bluez, "toio-a", {1, 2});
  // The reported pose follows the cube's Position IDs (cell units).
  EXPECT_TRUE(eventually([&] {
    const BackendReport report = robot.poll();
    return std::abs(report.pose_x - 1) < 0.05 && std::abs(report.pose_y - 2) < 0.05;
  }));
  EXPECT_TRUE(robot.start_move({1, 2}, -1));  // a wait: nothing to drive
  EXPECT_FALSE(robot.poll().moving);
  EXPECT_FALSE(robot.start_move({-1, 2}, -1));  // off the grid
}

TEST(ToioRobot, FindsACubeByAddress) {
  EmulatedBluez bluez({"toio-a@cell:1,1", "toio-b@cell:5,5"});
  ToioRobot robot(settings_for("e0:7c:00:00:00:01"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  EXPECT_EQ(robot.poll().cell, (Cell{5, 5}));
}

TEST(ToioRobot, LiftedCubeIsAFaultUntilPutBackOnACell) {
  EmulatedBluez bluez({"toio-a@cell:1,1"});
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  bluez.lift("toio-a");
  ASSERT_TRUE(eventually([&] { return robot.poll().fault; }));
  EXPECT_NE(robot.fault_reason().find("ID missed"), std::string::npos) << robot.fault_reason();
  EXPECT_FALSE(robot.start_move({2, 1}, -1));
  const Eigen::Vector2d cell = robot.calibration().cell_centre({4, 3});
  bluez.place("toio-a", cell.x(), cell.y());
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  EXPECT_EQ(robot.poll().cell, (Cell{4, 3}));
}

TEST(ToioRobot, CubeLiftedMidMoveFailsTheMoveAndIsHeldAsAFault) {
  EmulatedBluez bluez({"toio-a@cell:1,1"}, {"--speed-per-unit", "0.25"});  // slow: lifted surely mid-move
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  ASSERT_TRUE(robot.start_move({2, 1}, -1));
  bluez.lift("toio-a");
  ASSERT_TRUE(eventually([&] { return robot.poll().fault && !robot.poll().moving; }));
  EXPECT_NE(robot.fault_reason().find("ID missed"), std::string::npos) << robot.fault_reason();
  bluez.place("toio-a", 125, 125);  // back on cell (1,1)
  const auto placed = std::chrono::steady_clock::now();
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  // The failed move stays visible as a fault for at least fault_hold_s (1 s by default).
  EXPECT_GE(std::chrono::steady_clock::now() - placed, std::chrono::milliseconds(500));
  EXPECT_EQ(robot.poll().cell, (Cell{1, 1}));
}

TEST(ToioRobot, BlockedCubeTimesOutAsAFaultThenRejoinsFromWhereItStands) {
  EmulatedBluez bluez({"toio-a@cell:1,1"});
  ToioSettings settings = settings_for("toio-a");
  settings.move_timeout_s = 1;
  ToioRobot robot(settings, MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  bluez.block("toio-a", true);
  ASSERT_TRUE(robot.start_move({2, 1}, -1));
  ASSERT_TRUE(eventually([&] { return robot.poll().fault; }));
  EXPECT_NE(robot.fault_reason().find("move to (2,1) failed: timeout"), std::string::npos) << robot.fault_reason();
  EXPECT_FALSE(robot.poll().moving);
  bluez.block("toio-a", false);
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  EXPECT_EQ(robot.poll().cell, (Cell{1, 1}));  // it never left
}

TEST(ToioRobot, MovePreemptedByAnotherProgramIsAFault) {
  EmulatedBluez bluez({"toio-a@cell:1,1"}, {"--speed-per-unit", "0.25"});  // slow: preempted surely mid-move
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  ASSERT_TRUE(robot.start_move({1, 2}, -1));
  ASSERT_TRUE(eventually([&] { return bluez.pose("toio-a").y > 130; }));
  bluez.write_motor_of_first_cube({0x01, 0x01, 0x01, 0x00, 0x02, 0x01, 0x00});  // stop, from elsewhere
  ASSERT_TRUE(eventually([&] { return robot.poll().fault; }));
  EXPECT_NE(robot.fault_reason().find("preempted by another write"), std::string::npos) << robot.fault_reason();
}

TEST(ToioRobot, CubeBetweenCellsIsAFaultNotRoundedToACell) {
  EmulatedBluez bluez({"toio-a@cell:1,1"});
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  bluez.place("toio-a", 150, 125);  // halfway between cells (1,1) and (2,1)
  ASSERT_TRUE(eventually([&] { return robot.poll().fault; }));
  EXPECT_NE(robot.fault_reason().find("between cells"), std::string::npos) << robot.fault_reason();
  EXPECT_FALSE(robot.start_move({2, 1}, -1));
}

TEST(ToioRobot, LostLinkIsAFaultThenTheRobotReconnects) {
  EmulatedBluez bluez({"toio-a@cell:1,1"});
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  bluez.drop_connection("toio-a", 2.0);  // unreachable for 2 s: the first reconnects fail
  ASSERT_TRUE(eventually([&] { return robot.poll().fault; }));
  EXPECT_NE(robot.fault_reason().find("link"), std::string::npos) << robot.fault_reason();
  ASSERT_TRUE(eventually([&] { return !robot.connected(); }));
  ASSERT_TRUE(eventually([&] { return robot.connected() && ready(robot); })) << robot.fault_reason() << bluez.log();
  move_and_arrive(robot, bluez, "toio-a", {1, 2});
}

TEST(ToioRobot, LinkLostMidMoveThenTheCubeIsDrivenOntoTheNearerOfItsTwoCells) {
  // A slow cube (20 units/s) so that even a loaded machine cuts the link while it is between cells.
  EmulatedBluez bluez({"toio-a@cell:1,1"}, {"--speed-per-unit", "0.25"});
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  ASSERT_TRUE(robot.start_move({2, 1}, -1));
  // Cut the link once the cube is between cells (more than the tolerance, 18, from both centres
  // at x 125 and 175); it stops there, as a real cube stops its motors when the link drops.
  ASSERT_TRUE(eventually([&] { return bluez.pose("toio-a").x > 145; }));
  bluez.drop_connection("toio-a", 0.5);
  ASSERT_TRUE(eventually([&] { return robot.poll().fault && !robot.connected(); }));
  const double stopped_x = bluez.pose("toio-a").x;
  ASSERT_GT(stopped_x, 143) << "the cube must stop between the cells for this test";
  ASSERT_LT(stopped_x, 157) << "the cube must stop between the cells for this test";
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason() << bluez.log();
  const Cell nearer = stopped_x < 150 ? Cell{1, 1} : Cell{2, 1};
  EXPECT_EQ(robot.poll().cell, nearer);
  EXPECT_TRUE(eventually([&] {
    return std::abs(bluez.pose("toio-a").x - robot.calibration().cell_centre(nearer).x()) < 2;
  }));
}

TEST(ToioRobot, AbsentCubeIsAFaultAndTheBackendStillStopsPromptly) {
  EmulatedBluez bluez({"toio-a@cell:1,1"});
  ToioSettings settings = settings_for("toio-zzz");
  settings.discovery_timeout_s = 0.5;
  auto robot = std::make_unique<ToioRobot>(settings, MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return robot->fault_reason().find("not found") != std::string::npos; }))
      << robot->fault_reason();
  EXPECT_TRUE(robot->poll().fault);
  EXPECT_FALSE(robot->start_move({1, 2}, -1));
  const auto stopping = std::chrono::steady_clock::now();
  robot.reset();
  EXPECT_LT(std::chrono::steady_clock::now() - stopping, std::chrono::seconds(5));
}

TEST(ToioRobot, NoBusIsAFaultThatNamesTheBus) {
  setenv("DBUS_SYSTEM_BUS_ADDRESS", "unix:path=/nonexistent/ctsfleet-bus", 1);
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return robot.fault_reason().find("D-Bus") != std::string::npos; }))
      << robot.fault_reason();
  EXPECT_TRUE(robot.poll().fault);
}

// A delayConfig file (ctsfleet-toio-emulator --delay-config) in the temporary folder.
std::string delay_config_file(const std::string& name, double p, int ticks) {
  const auto path = std::filesystem::temp_directory_path() / (name + "-" + std::to_string(getpid()) + ".json");
  std::ofstream(path) << "{\"seed\": 0, \"minDelay\": " << ticks << ", \"maxDelay\": " << ticks
                      << ", \"eventModel\": \"bernoulli\", \"pDelay\": " << p
                      << ", \"durationModel\": \"uniform\", \"gaussMeanRatio\": 0.5, \"gaussStdRatio\": 0.2}";
  return path.string();
}

// pDelay 1: the cube is delayed at its first tick and at once again after each delay; it reports
// where it stands, but a move never starts.
TEST(ToioRobot, CubeDelayedForEverStandsStill) {
  const std::string config = delay_config_file("delayed-for-ever", 1.0, 1000);
  EmulatedBluez bluez({"toio-a@cell:1,1"}, {"--delay-config", config, "--delay-tick", "0.05"});
  std::filesystem::remove(config);
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  EXPECT_NE(bluez.log().find("cube toio-a delayed for 1000 ticks"), std::string::npos) << bluez.log();
  ASSERT_TRUE(robot.start_move({2, 1}, -1));
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(1500);
  while (std::chrono::steady_clock::now() < until) {
    EXPECT_NEAR(bluez.pose("toio-a").x, 125, 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(robot.poll().moving);
}

// Delays of 5 ticks, drawn often: each stops the cube where it is, then its move goes on.
TEST(ToioRobot, DelayedCubeGoesOnWhereItStoppedAndArrives) {
  const std::string config = delay_config_file("delayed-often", 0.3, 5);
  EmulatedBluez bluez({"toio-a@cell:1,1"}, {"--delay-config", config, "--delay-tick", "0.1"});
  std::filesystem::remove(config);
  ToioRobot robot(settings_for("toio-a"), MatCalibration::load(kRing));
  ASSERT_TRUE(eventually([&] { return ready(robot); })) << robot.fault_reason();
  move_and_arrive(robot, bluez, "toio-a", {3, 1});
  EXPECT_NE(bluez.log().find("cube toio-a delayed for 5 ticks"), std::string::npos) << bluez.log();
}

// A delayConfig with a negative delay: exit 2 and a line naming the file and the key, before any bus.
TEST(ToioEmulator, BadDelayConfigIsRefusedNamingTheKey) {
  const std::string config = delay_config_file("negative-delay", 0.1, -3);
  const std::string out = config + ".out";
  const std::string command = std::string(CTSFLEET_BIN_DIR) + "/ctsfleet-toio-emulator --bus unix:path=/nonexistent " +
                              "--cube toio-a@100,100 --delay-config " + config + " > " + out + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream file(out);
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::filesystem::remove(config);
  std::filesystem::remove(out);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2) << text;
  EXPECT_NE(text.find(config), std::string::npos) << text;
  EXPECT_NE(text.find("minDelay"), std::string::npos) << text;
}

}  // namespace
}  // namespace robot_agent
