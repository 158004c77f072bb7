// ctsfleet-task: gives a running fleet work. `add --at X,Y [--robot ID | --any]` asks the active
// coordinator to add a task (it checks the cell, picks the robot whose tour grows least when --any,
// journals it and replans), `cancel TASK` withdraws one, `list` prints every task with its state.
// The request is sent again every second until the coordinator answers; exit 0 when accepted, 1
// when refused (the reason on stderr), 4 when no coordinator answered within --timeout.
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <iostream>
#include <mutex>
#include <optional>
#include <random>
#include <thread>

#include "observer_options.hpp"
#include "planner_core/input_error.hpp"

namespace {

constexpr int kExitRefused = ctsfleet::kExitFailed;
constexpr int kExitNoAnswer = ctsfleet::kExitHeardNothing;

std::string new_request_id() {
  char host[64] = {0};
  gethostname(host, sizeof host - 1);
  std::random_device device;
  return std::string(host).substr(0, 32) + "-" + std::to_string(getpid()) + "-" + std::to_string(device() % 1000000);
}

}  // namespace

int main(int argc, char** argv) {
  ctsfleet::Program program("ctsfleet-task", "add, cancel or list the tasks of a running fleet");
  CLI::App& app = program.app();
  ctsfleet::ObserverOptions dds("operator");
  dds.add_to(app);
  double timeout_s = 10;
  app.add_option("--timeout", timeout_s, "seconds to wait for the coordinator's answer")
      ->check(ctsfleet::positive_seconds(3600))
      ->capture_default_str();
  app.require_subcommand(1);
  app.fallthrough();  // `ctsfleet-task list --domain 3` as well as `ctsfleet-task --domain 3 list`
  fleet_transport::TaskRequest request;
  request.request_id = new_request_id();
  std::string at;
  CLI::App* add = app.add_subcommand("add", "add a task at a cell, for one robot or for the robot it suits best");
  add->add_option("--at", at, "the task's cell, X,Y")->required();
  auto* robot = add->add_option("--robot", request.robot_id, "the robot that must visit it");
  bool any_robot = false;
  auto* any = add->add_flag("--any", any_robot, "any robot: the one whose tour grows least");
  robot->excludes(any);
  CLI::App* cancel = app.add_subcommand("cancel", "withdraw a task not done yet");
  cancel->add_option("task", request.task, "the task's id (see list)")->required()->check(ctsfleet::count_in(0, 1 << 30));
  app.add_subcommand("list", "print every task: where, for which robot, pending, done or cancelled");
  return program.main(argc, argv, [&] {
    if (add->parsed()) {
      request.action = fleet_transport::TaskAction::kAdd;
      const size_t comma = at.find(',');
      try {
        size_t used_x = 0, used_y = 0;
        if (comma == std::string::npos) throw std::invalid_argument("no comma");
        request.x = std::stoi(at.substr(0, comma), &used_x);
        request.y = std::stoi(at.substr(comma + 1), &used_y);
        if (used_x != comma || used_y != at.size() - comma - 1) throw std::invalid_argument("trailing text");
      } catch (const std::exception&) {
        throw planner_core::InputError("--at '" + at + "': expected X,Y (two integers, e.g. --at 4,7)");
      }
      if (request.robot_id.empty() && !any_robot) {
        throw planner_core::InputError("add: say which robot with --robot ID, or --any for the one it suits best");
      }
      if (!request.robot_id.empty() && !fleet_transport::is_valid_robot_id(request.robot_id)) {
        throw planner_core::InputError("--robot: '" + fleet_transport::printable(request.robot_id, 40) +
                                       "' is not a robot id (" + fleet_transport::kRobotIdRule + ")");
      }
    } else if (cancel->parsed()) {
      request.action = fleet_transport::TaskAction::kCancel;
    } else {
      request.action = fleet_transport::TaskAction::kList;
    }
    const fleet_transport::TransportConfig config = dds.transport_config();

    std::mutex mutex;
    std::condition_variable answered;
    std::optional<fleet_transport::TaskReply> reply;
    fleet_transport::Handlers handlers;
    handlers.on_task_reply = [&](const fleet_transport::TaskReply& r) {
      if (r.request_id != request.request_id) return;  // another operator's
      const std::lock_guard<std::mutex> lock(mutex);
      if (!reply) reply = r;
      answered.notify_all();
    };
    auto transport = fleet_transport::make_transport(config, handlers);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                                 std::chrono::duration<double>(timeout_s));
    std::unique_lock<std::mutex> lock(mutex);
    while (!reply && std::chrono::steady_clock::now() < deadline && !ctsfleet::stop_requested()) {
      lock.unlock();
      try {
        transport->request_task(request);  // again until answered: the first may precede discovery
      } catch (const std::runtime_error& e) {
        throw std::runtime_error(std::string(e.what()) + "; with DDS Security, --identity must be enrolled as an "
                                 "operator (ctsfleet-ca add-operator DIR NAME)");
      }
      lock.lock();
      answered.wait_until(lock, std::min<std::chrono::steady_clock::time_point>(
                                            deadline, std::chrono::steady_clock::now() + std::chrono::seconds(1)),
                          [&] { return reply.has_value(); });
    }
    if (!reply) {
      std::cerr << "ctsfleet-task: no coordinator answered within " << timeout_s << " s on " << dds.vendor
                << " domain " << dds.domain << " (is an active coordinator running there?)\n";
      fleet_transport::exit_if_shutdown_hangs(5, kExitNoAnswer);
      return ctsfleet::stop_requested() ? ctsfleet::kExitInterrupted : kExitNoAnswer;
    }
    const fleet_transport::TaskReply answer = *reply;
    lock.unlock();
    fleet_transport::exit_if_shutdown_hangs(5, answer.accepted ? 0 : kExitRefused);
    if (!answer.accepted) {
      std::cerr << "ctsfleet-task: refused: " << answer.reason << "\n";
      return kExitRefused;
    }
    if (request.action == fleet_transport::TaskAction::kList) {
      std::cout << answer.listing;
    } else {
      std::cout << answer.reason << "\n";
    }
    return 0;
  });
}
