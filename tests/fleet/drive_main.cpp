// ctsfleet-test-drive: drives one robot agent over DDS without a coordinator (tests only). Sends
// step commands along --path and waits for each arrival, or waits for the robot to report a status.
// Prints what it sees; exits 0 on success, 3 when the robot faults or a deadline passes.
#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <thread>
#include <unistd.h>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <optional>
#include <sstream>

#include "fleet_transport/transport.hpp"

namespace {

using fleet_transport::RobotState;
using fleet_transport::RobotStatus;

struct Latest {
  std::mutex mutex;
  std::condition_variable changed;
  std::optional<RobotState> state;
};

// Waits up to `timeout_s` for a state satisfying `done`; returns it, or nullopt.
template <typename Condition>
std::optional<RobotState> wait_for(Latest& latest, double timeout_s, Condition done) {
  std::unique_lock<std::mutex> lock(latest.mutex);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  if (!latest.changed.wait_until(lock, deadline, [&] { return latest.state && done(*latest.state); })) return std::nullopt;
  return latest.state;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ctsfleet-test-drive: move one robot along a path, or wait for its status (tests only)"};
  std::string vendor = "cyclone", dds_dir, robot, path_text, status_text;
  int domain = 0, epoch = 1;
  double timeout_s = 60;
  bool even_in_fault = false;
  app.add_option("--dds", vendor);
  app.add_option("--domain", domain);
  app.add_option("--dds-config-dir", dds_dir);
  std::string discovery_server;
  app.add_option("--discovery-server", discovery_server, fleet_transport::kDiscoveryServerHelp);
  app.add_option("--robot", robot, "robot id")->required();
  app.add_option("--path", path_text, "cells to visit, one step each: \"x,y x,y ...\"");
  app.add_option("--epoch", epoch, "plan epoch of the commands")->capture_default_str();
  app.add_option("--wait-status", status_text, "instead: wait until the robot reports this status")
      ->check(CLI::IsMember({"idle", "moving", "arrived", "fault", "ready"}));
  app.add_option("--timeout", timeout_s, "seconds to wait for each step or status")->capture_default_str();
  app.add_flag("--even-in-fault", even_in_fault, "send the path without waiting for the robot to be ready");
  std::string security_dir, identity;
  app.add_option("--security", security_dir, "fleet directory made by ctsfleet-ca (DDS Security)");
  app.add_option("--identity", identity, "the enrolled name to act as (with --security)");
  CLI11_PARSE(app, argc, argv);

  Latest latest;
  fleet_transport::TransportConfig config;
  config.vendor = fleet_transport::parse_vendor(vendor);
  config.domain_id = domain;
  config.loopback_config_dir = dds_dir;
  config.discovery_servers = discovery_server;
  try {
    config.security = fleet_transport::load_fleet_security(security_dir, identity);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ctsfleet-test-drive: error: %s\n", e.what());
    return 2;
  }
  fleet_transport::Handlers handlers;
  handlers.on_state = [&](const RobotState& state) {
    if (state.robot_id != robot) return;
    const std::lock_guard<std::mutex> lock(latest.mutex);
    latest.state = state;
    latest.changed.notify_all();
  };
  std::unique_ptr<fleet_transport::Transport> transport;
  try {
    transport = fleet_transport::make_transport(config, handlers);
    transport->open_commands_for(robot);
  } catch (const std::exception& e) {  // e.g. access control refuses a command writer to this robot
    std::fprintf(stderr, "ctsfleet-test-drive: refused: %s\n", e.what());
    return 4;
  }
  // Agents obey an active coordinator that announced the epoch: this tool is one, of term 0, so
  // any real coordinator outranks it. Its status goes out every 0.25 s while it runs.
  fleet_transport::CoordinatorStatus status;
  status.coordinator = 0x7e57d12e0000ull ^ static_cast<uint64_t>(fleet_transport::wall_clock_ms());
  status.term = 0;
  status.claimed_ms = fleet_transport::wall_clock_ms();
  status.mission_id = "test-drive";
  status.plan_epoch = epoch;
  std::atomic<bool> done{false};
  std::thread heartbeat([&] {
    while (!done.load()) {
      try {
        transport->publish_coordinator_status(status);
      } catch (const std::exception& e) {  // an identity whose status writer access control refuses
        std::fprintf(stderr, "ctsfleet-test-drive: refused: %s\n", e.what());
        std::fflush(stderr);
        _exit(4);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
    }
  });
  // On the way out: no more heartbeat, and a last status "ended" so the robot follows the next
  // coordinator (or test tool) at once.
  struct End {
    std::atomic<bool>& done;
    std::thread& thread;
    fleet_transport::Transport& transport;
    fleet_transport::CoordinatorStatus& status;
    ~End() {
      done = true;
      thread.join();
      status.role = fleet_transport::CoordinatorRole::kEnded;
      transport.publish_coordinator_status(status);
    }
  } end{done, heartbeat, *transport, status};

  if (!status_text.empty()) {
    // "ready" = any status but fault (idle or arrived).
    const auto seen = wait_for(latest, timeout_s, [&](const RobotState& s) {
      if (status_text == "ready") return s.status == RobotStatus::kIdle || s.status == RobotStatus::kArrived;
      return status_text == fleet_transport::to_string(s.status);
    });
    if (!seen) {
      std::printf("timeout: %s never reported %s\n", robot.c_str(), status_text.c_str());
      return 3;
    }
    std::printf("status %s at %d,%d\n", fleet_transport::to_string(seen->status), seen->cell_x, seen->cell_y);
    return 0;
  }

  const auto ready = wait_for(latest, timeout_s, [&](const RobotState& s) {
    return even_in_fault || s.status != RobotStatus::kFault;
  });
  if (!ready) {
    std::printf("timeout: %s never became ready\n", robot.c_str());
    return 3;
  }
  std::istringstream cells(path_text);
  std::string cell;
  for (int index = 0; cells >> cell; ++index) {
    int x = 0, y = 0;
    if (std::sscanf(cell.c_str(), "%d,%d", &x, &y) != 2) {
      std::fprintf(stderr, "--path: '%s' is not x,y\n", cell.c_str());
      return 2;
    }
    const int64_t deadline_ms = fleet_transport::wall_clock_ms() + static_cast<int64_t>(timeout_s * 1000);
    const auto start = std::chrono::steady_clock::now();
    std::optional<RobotState> seen;
    // Resend until the agent acknowledges (the first command may go out before discovery ends).
    while (!seen && std::chrono::steady_clock::now() - start < std::chrono::duration<double>(timeout_s)) {
      // For the process whose states it hears (one robot id, one body).
      transport->send_command({robot, epoch, index, x, y, static_cast<double>(x), static_cast<double>(y), deadline_ms,
                               status.coordinator, fleet_transport::wall_clock_ms(), ready->incarnation});
      seen = wait_for(latest, 1.0, [&](const RobotState& s) {
        return s.status == RobotStatus::kFault ||
               (s.plan_epoch == epoch && s.action_index == index && s.status == RobotStatus::kArrived &&
                s.cell_x == x && s.cell_y == y);
      });
    }
    if (!seen) {
      std::printf("timeout: no arrival at %d,%d\n", x, y);
      return 3;
    }
    if (seen->status == RobotStatus::kFault) {
      std::printf("fault at %d,%d on the way to %d,%d\n", seen->cell_x, seen->cell_y, x, y);
      return 3;
    }
    std::printf("arrived %d at %d,%d\n", index, x, y);
  }
  return 0;
}
