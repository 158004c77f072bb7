// ctsfleet-dashboard: the fleet in a browser. An observer on the DDS domain (it hears the topics
// robots and coordinators publish; nothing else ties it to them) serving a live page: the map,
// every robot where it reports itself, its plan and next tasks, the tasks' states, the events and
// the fleet's figures; a click on a free cell asks the coordinator for a task there. It can record
// what it hears (--record FILE), replay such a file at any speed (--replay FILE), and show a plan
// written by ctsfleet-solve moving (--plan SOLUTION --instance INSTANCE).
#include <spdlog/spdlog.h>

#include <arpa/inet.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "dashboard/dashboard_server.hpp"
#include "dashboard/history.hpp"
#include "dashboard/message_json.hpp"
#include "dashboard/playback.hpp"
#include "observer_options.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/svg_writer.hpp"

namespace {

using dashboard::HistoryEntry;
using dashboard::Json;

bool is_loopback(const std::string& host) {
  in_addr address{};
  return host == "localhost" || (inet_pton(AF_INET, host.c_str(), &address) == 1 && (ntohl(address.s_addr) >> 24) == 127);
}

// Plays a playback into the server on a clock that runs `speed` times as fast as the wall clock.
class Replay {
 public:
  Replay(std::unique_ptr<dashboard::Playback> playback, double speed) : playback_(std::move(playback)), speed_(speed) {
    anchor_replayed_ms_ = playback_->start_ms();
    anchor_real_ = std::chrono::steady_clock::now();
  }
  int64_t now_ms() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return replayed_at(std::chrono::steady_clock::now());
  }
  void set_speed(double speed) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    anchor_replayed_ms_ = replayed_at(now);
    anchor_real_ = now;
    speed_ = speed;
  }
  void run(dashboard::DashboardServer& server, const std::atomic<bool>& stop) {
    while (!stop) {
      playback_->play_until(now_ms(), [&server](const HistoryEntry& entry) { server.apply(entry); });
      server.touch();  // the clock moved: robots may turn lost
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }

 private:
  int64_t replayed_at(std::chrono::steady_clock::time_point now) const {
    const double real_ms = std::chrono::duration<double, std::milli>(now - anchor_real_).count();
    return std::min(playback_->end_ms(), anchor_replayed_ms_ + static_cast<int64_t>(real_ms * speed_));
  }
  std::unique_ptr<dashboard::Playback> playback_;
  std::mutex mutex_;
  double speed_;
  int64_t anchor_replayed_ms_ = 0;
  std::chrono::steady_clock::time_point anchor_real_;
};

}  // namespace

int main(int argc, char** argv) {
  ctsfleet::Program program("ctsfleet-dashboard", "a live web page of the fleet; record, replay, or show a plan");
  CLI::App& app = program.app();
  ctsfleet::ObserverOptions dds("dashboard");
  dds.add_to(app);
  std::string host = "127.0.0.1", record, replay, plan, instance;
  int port = 8080;
  double speed = 1, lost_after_s = 2, duration_s = 0;
  int step_ms = 300;
  app.add_option("--port", port, "HTTP port (0: any free one, printed)")->check(CLI::Range(0, 65535))->capture_default_str();
  app.add_option("--listen", host, "address to serve on (127.0.0.1: this host only; 0.0.0.0: every interface)")
      ->capture_default_str();
  app.add_option("--record", record, "write every message heard to this history file (JSON Lines)")
      ->check(ctsfleet::writable_file());
  auto* replay_option =
      app.add_option("--replay", replay, "replay a history file instead of listening to DDS")->check(CLI::ExistingFile);
  auto* plan_option = app.add_option("--plan", plan, "show this ctsfleet-solve solution moving (with --instance)")
                          ->check(CLI::ExistingFile);
  auto* instance_option = app.add_option("--instance", instance, "the instance the --plan solves")->check(CLI::ExistingFile);
  plan_option->needs(instance_option);
  instance_option->needs(plan_option);
  replay_option->excludes(plan_option);
  app.add_option("--speed", speed, "replay speed (1 = as recorded; the page can change it)")
      ->check(ctsfleet::number_in(0.01, 1000))
      ->capture_default_str();
  app.add_option("--step-ms", step_ms, "--plan: milliseconds per timestep")->check(CLI::Range(10, 60000))->capture_default_str();
  app.add_option("--lost-after", lost_after_s, "show a robot lost after this many seconds without a word from it")
      ->check(ctsfleet::positive_seconds(3600))
      ->capture_default_str();
  std::string svg;
  app.add_option("--svg", svg, "with --replay or --plan: draw the run (map, tasks, each robot's trail) as an SVG "
                               "picture, and exit")
      ->check(ctsfleet::writable_file());
  std::string web_dir;
  app.add_option("--web-dir", web_dir, "serve the page's files from this folder (working on the page; default: built in)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--duration", duration_s, "stop after this many seconds (0: until Ctrl-C)")
      ->check(ctsfleet::number_in(0, 1e7))
      ->capture_default_str();
  return program.main(argc, argv, [&] {
    const std::atomic<bool>& stop = ctsfleet::stop_requested();
    const bool live = replay.empty() && plan.empty();
    std::unique_ptr<dashboard::Playback> playback;
    std::optional<ctsfleet::StopsAtOnce> reading;  // until the input is read and checked
    if (!live) reading.emplace("ctsfleet-dashboard", "reading " + (replay.empty() ? plan : replay));
    if (!live && !record.empty()) throw planner_core::InputError("--record: only a live dashboard records");
    if (!svg.empty() && live) throw planner_core::InputError("--svg: draws a --replay or a --plan");
    if (!replay.empty()) {
      std::vector<HistoryEntry> entries = dashboard::load_history(replay);
      if (!svg.empty()) {
        const dashboard::HistoryPicture picture = dashboard::history_picture(entries, replay);
        planner_core::write_svg(svg, picture.instance, picture.solution);
        std::cout << "picture of " << picture.robots.size() << " robots over " << picture.solution.size() - 1
                  << " moves: " << svg << std::endl;
        return 0;
      }
      playback = std::make_unique<dashboard::RecordedPlayback>(std::move(entries));
    }
    if (!plan.empty()) {
      const planner_core::Instance loaded = planner_core::load_instance(instance);
      planner_core::SolutionFile solution = planner_core::read_solution(plan, *loaded.graph);
      for (const planner_core::Config& config : solution.solution) {
        if (static_cast<int>(config.size()) != loaded.agent_count()) {
          throw planner_core::InputError(plan + ": " + std::to_string(config.size()) + " agents per timestep, but " +
                                         instance + " has " + std::to_string(loaded.agent_count()));
        }
      }
      const size_t steps = solution.solution.size();
      auto shown = std::make_unique<dashboard::PlanPlayback>(loaded, std::move(solution.solution), step_ms, plan);
      if (!svg.empty()) {
        planner_core::write_svg(svg, loaded, shown->solution());
        std::cout << "picture of " << loaded.agent_count() << " robots over " << steps - 1 << " moves: " << svg
                  << std::endl;
        return 0;
      }
      playback = std::move(shown);
    }
    reading.reset();
    const fleet_transport::TransportConfig config = dds.transport_config();
    std::unique_ptr<dashboard::HistoryRecorder> recorder;
    if (!record.empty()) recorder = std::make_unique<dashboard::HistoryRecorder>(record);

    std::unique_ptr<fleet_transport::Transport> transport;
    dashboard::DashboardServer server(
        lost_after_s,
        live ? dashboard::DashboardServer::RequestTask([&](const fleet_transport::TaskRequest& r) {
          if (!transport) return;
          try {
            transport->request_task(r);
          } catch (const std::exception& e) {
            spdlog::error("cannot send the task request ({}); with DDS Security this dashboard's --identity must be "
                          "enrolled as an operator (ctsfleet-ca add-operator DIR NAME)", e.what());
          }
        })
             : nullptr,
        recorder.get());
    server.set_web_dir(web_dir);
    server.bind(host, port);
    if (!is_loopback(host) && !config.security.enabled()) {
      spdlog::warn("serving on {} without DDS Security: anyone who can reach this port sees the fleet and can give "
                   "it tasks", host);
    }
    std::unique_ptr<Replay> replayer;
    std::thread replay_thread;
    if (live) {
      fleet_transport::Handlers handlers;
      const auto heard = [&server](const char* type, Json message) {
        server.apply({fleet_transport::wall_clock_ms(), type, std::move(message)});
      };
      handlers.on_announcement = [heard](const fleet_transport::Announcement& m) { heard("announcement", m); };
      handlers.on_robot_gone = [heard](const std::string& id, fleet_transport::GoneReason reason) {
        heard("gone", {{"robot_id", id},
                       {"reason", reason == fleet_transport::GoneReason::kGoodbye ? "goodbye" : "liveliness lost"}});
      };
      handlers.on_state = [heard](const fleet_transport::RobotState& m) { heard("state", m); };
      handlers.on_coordinator_status = [heard](const fleet_transport::CoordinatorStatus& m) { heard("coordinator", m); };
      handlers.on_fleet_status = [heard](const fleet_transport::FleetStatus& m) { heard("status", m); };
      handlers.on_mission_info = [heard](const fleet_transport::MissionInfo& m) { heard("mission", m); };
      handlers.on_fleet_plan = [heard](const fleet_transport::FleetPlan& m) { heard("plan", m); };
      handlers.on_fleet_event = [heard](const fleet_transport::FleetEvent& m) { heard("event", m); };
      handlers.on_task_reply = [&server](const fleet_transport::TaskReply& r) { server.on_task_reply(r); };
      handlers.on_refused = [](const std::string& what) { spdlog::warn("refused: {}", what); };
      transport = fleet_transport::make_transport(config, handlers);
    } else {
      replayer = std::make_unique<Replay>(std::move(playback), speed);
      server.set_clock([&replayer] { return replayer->now_ms(); });
      server.set_replay_control([&replayer](double s) { replayer->set_speed(s); });
      replay_thread = std::thread([&] { replayer->run(server, stop); });
    }
    std::thread http_thread([&server] { server.serve(); });
    std::cout << "dashboard: http://" << (host == "0.0.0.0" ? "127.0.0.1" : host) << ":" << server.port() << "/"
              << std::endl;
    const auto started = std::chrono::steady_clock::now();
    while (!stop && (duration_s <= 0 || std::chrono::steady_clock::now() - started <
                                            std::chrono::duration<double>(duration_s))) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    // Stopped by Ctrl-C or SIGTERM: 130, as every program; at the end of --duration: 0.
    const int exit_code = stop.load() ? ctsfleet::kExitInterrupted : 0;
    ctsfleet::stop_requested() = true;
    server.stop();
    http_thread.join();
    if (replay_thread.joinable()) replay_thread.join();
    fleet_transport::exit_if_shutdown_hangs(5, exit_code);
    transport.reset();
    return exit_code;
  });
}
