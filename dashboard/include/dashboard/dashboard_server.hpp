// DashboardServer: the web side of ctsfleet-dashboard. Serves the page (plain HTML/JS/CSS built
// into the program), the live picture as server-sent events (/api/stream: "mission" and "plan"
// when they change, "frame" at up to 20 Hz when something changed and at least once a second),
// snapshots (/api/frame, /api/mission, /api/plan), task requests (POST /api/tasks, answered by the
// active coordinator) and the replay speed (POST /api/replay). The fleet's messages come in
// through the on_* calls (from DDS handlers or a replay), each recorded when a recorder is set.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "dashboard/fleet_view.hpp"
#include "dashboard/history.hpp"

namespace dashboard {

class GuardedHttpServer;

class DashboardServer {
 public:
  // Sends a task request to the fleet (unset: a replay, where tasks cannot be added).
  using RequestTask = std::function<void(const fleet_transport::TaskRequest&)>;

  DashboardServer(double lost_after_s, RequestTask request_task, HistoryRecorder* recorder);
  ~DashboardServer();

  // Thread-safe inputs: the message and the wall-clock ms at which it was heard.
  void apply(const HistoryEntry& entry);
  void on_task_reply(const fleet_transport::TaskReply& reply);
  // The clock frames are drawn at: live, the wall clock; in a replay, the replayed time.
  void set_clock(std::function<int64_t()> now_ms) { now_ms_ = std::move(now_ms); }
  // A replay's speed control (unset: live).
  void set_replay_control(std::function<void(double speed)> set_speed) { set_speed_ = std::move(set_speed); }
  // Serve the page's files from this folder instead of the built-in copies ("" = built in).
  void set_web_dir(std::string dir) { web_dir_ = std::move(dir); }
  // Wakes the streams (e.g. the replay clock moved although no message came).
  void touch();

  // Binds; throws planner_core::InputError when the address or port cannot be had.
  void bind(const std::string& host, int port);
  int port() const { return port_; }
  // Serves until stop(); call from one thread.
  void serve();
  void stop();

 private:
  void add_routes();
  Json frame() const;  // the view's frame, saying whether it is a replay (call with mutex_ held)
  fleet_transport::TaskReply request(fleet_transport::TaskRequest request);

  std::unique_ptr<GuardedHttpServer> http_;
  RequestTask request_task_;
  HistoryRecorder* recorder_;
  std::function<int64_t()> now_ms_;
  std::function<void(double)> set_speed_;
  int port_ = 0;
  std::string web_dir_;

  std::mutex mutex_;
  std::condition_variable changed_;
  FleetView view_;
  uint64_t changes_ = 0;  // grows with every input
  bool stopping_ = false;
  std::map<std::string, std::optional<fleet_transport::TaskReply>> pending_;  // request id -> answer
  std::condition_variable answered_;
  uint64_t requests_made_ = 0;
};

}  // namespace dashboard
