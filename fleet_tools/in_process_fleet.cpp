#include "in_process_fleet.hpp"

#include <spdlog/spdlog.h>

#include <map>
#include <memory>
#include <thread>

#include "coordinator/fleet_coordinator.hpp"
#include "robot_agent/robot_agent.hpp"
#include "robot_agent/sim_robot.hpp"

namespace coordinator {

namespace {

using Clock = std::chrono::steady_clock;

// Delivers each message to its readers at once.
class InProcessTransport : public fleet_transport::Transport {
 public:
  InProcessTransport(FleetCoordinator& coordinator, TaskStream& stream) : coordinator_(coordinator), stream_(stream) {}
  void add_agent(robot_agent::RobotAgent& agent, const std::string& robot_id) { agents_[robot_id] = &agent; }

  void announce(const fleet_transport::Announcement& announcement) override { coordinator_.on_announcement(announcement); }
  void say_goodbye(const std::string& robot_id) override {
    coordinator_.on_robot_gone(robot_id, fleet_transport::GoneReason::kGoodbye);
  }
  void publish_state(const fleet_transport::RobotState& state) override { coordinator_.on_state(state); }
  void send_command(const fleet_transport::StepCommand& command) override {
    const auto agent = agents_.find(command.robot_id);
    if (agent != agents_.end()) agent->second->on_command(command);
  }
  void open_commands_for(const std::string&) override {}
  void publish_coordinator_status(const fleet_transport::CoordinatorStatus& status) override {
    for (auto& [id, agent] : agents_) agent->on_coordinator_status(status);
  }
  void publish_fleet_status(const fleet_transport::FleetStatus&) override {}
  void publish_mission_info(const fleet_transport::MissionInfo&) override {}
  void publish_fleet_plan(const fleet_transport::FleetPlan&) override {}
  void publish_fleet_event(const fleet_transport::FleetEvent&) override {}
  void request_task(const fleet_transport::TaskRequest& request) override { coordinator_.on_task_request(request); }
  void reply_task(const fleet_transport::TaskReply& reply) override { stream_.answered(reply); }
  void set_command_strength(int) override {}

 private:
  FleetCoordinator& coordinator_;
  TaskStream& stream_;
  std::map<std::string, robot_agent::RobotAgent*> agents_;
};

}  // namespace

StreamFigures run_in_process_fleet(const FleetConfig& config, const planner_core::Instance& mission, double step_s,
                                   double jitter, double turn_s, TaskStream& stream, const StreamTimeline& timeline,
                                   const std::atomic<bool>& stop) {
  // Its log would drown the benchmark's table: warnings and errors only, as they matter.
  const spdlog::level::level_enum level = spdlog::get_level();
  spdlog::set_level(spdlog::level::warn);
  struct RestoreLevel {
    spdlog::level::level_enum level;
    ~RestoreLevel() { spdlog::set_level(level); }
  } restore{level};
  FleetCoordinator coordinator(config, mission);
  InProcessTransport transport(coordinator, stream);
  std::vector<std::unique_ptr<robot_agent::SimRobot>> robots;
  std::vector<std::unique_ptr<robot_agent::RobotAgent>> agents;
  for (int r = 0; r < mission.agent_count(); ++r) {
    robot_agent::SimSettings sim;
    sim.step_s = step_s;
    sim.jitter = jitter;
    sim.turn_s = turn_s;
    sim.seed = static_cast<uint32_t>(r + 1);
    const planner_core::Cell start = mission.graph->cell_of(mission.starts[r]);
    robots.push_back(std::make_unique<robot_agent::SimRobot>(robot_agent::Cell{start.x, start.y}, sim));
    robot_agent::AgentSettings settings;
    settings.robot_id = "robot" + std::to_string(r);
    agents.push_back(std::make_unique<robot_agent::RobotAgent>(settings, *robots.back()));
    transport.add_agent(*agents.back(), settings.robot_id);
    transport.announce(agents.back()->announcement());
  }
  StreamFigures figures;
  std::optional<Clock::time_point> first_plan, counting_from;
  int done_at_start = 0;
  const auto seconds = [](double s) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); };
  for (;;) {
    const Clock::time_point now = Clock::now();
    if (stop.load()) {
      figures.interrupted = true;
      break;
    }
    if (!coordinator.step(transport)) break;
    for (auto& agent : agents) agent->step(transport, true);
    const MissionSummary& summary = coordinator.summary();
    if (!first_plan && summary.first_command_wall_ms > 0) first_plan = now;
    if (first_plan) {
      for (const fleet_transport::TaskRequest& request : stream.due(summary.tasks_done, now)) {
        coordinator.on_task_request(request);
      }
      if (!counting_from && now >= *first_plan + seconds(timeline.warmup_s)) {
        counting_from = now;
        done_at_start = summary.tasks_done;
      }
      if (counting_from && now >= *counting_from + seconds(timeline.measure_s)) {
        figures.tasks_done = summary.tasks_done - done_at_start;
        figures.seconds = std::chrono::duration<double>(now - *counting_from).count();
        break;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const MissionSummary& summary = coordinator.summary();
  figures.tasks_per_minute = figures.seconds > 0 ? 60 * figures.tasks_done / figures.seconds : 0;
  figures.accepted = stream.accepted();
  figures.refused = stream.refused();
  figures.windows = summary.windows;
  figures.window_ms_max = summary.window_ms_max;
  figures.windows_late = summary.windows_late;
  figures.robot_s_waiting_for_windows = summary.robot_s_waiting_for_windows;
  figures.tasks_reassigned = summary.tasks_reassigned;
  figures.replans = summary.replans;
  return figures;
}

}  // namespace coordinator
