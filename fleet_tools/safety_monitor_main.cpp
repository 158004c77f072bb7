// ctsfleet-monitor: an independent observer. Records every robot state it hears and checks, from
// the robots' own arrival timestamps, that no two robots ever held the same cell at the same time
// (which also rules out swaps), and that no robot id is claimed by two live processes (told apart by
// their incarnation), and that no two coordinators stay active together (a coordinator that failed
// to stand down). Runs until SIGINT/SIGTERM or --duration; exit 0 when safe, 1 on a collision, a
// duplicate id or two active coordinators, 4 when it heard no robot at all (a check that saw
// nothing has not passed).
#include <spdlog/spdlog.h>

#include <atomic>
#include <map>
#include <set>
#include <mutex>
#include <thread>

#include "coordinator/active_coordinator_watch.hpp"
#include "observer_options.hpp"
#include "ctsfleet/data_dir.hpp"
#include "ctsfleet/program.hpp"
#include "fleet_transport/transport.hpp"

namespace {

constexpr int kExitHeardNothing = ctsfleet::kExitHeardNothing;

struct Visit {
  int x, y;
  int64_t from_ms;  // arrival
  int64_t to_ms;    // arrival at the next cell (open-ended: INT64_MAX)
};
}  // namespace

int main(int argc, char** argv) {
  ctsfleet::Program program("ctsfleet-monitor", "check that robots never share a cell, from their reported states");
  CLI::App& app = program.app();
  ctsfleet::ObserverOptions dds("monitor");
  dds.add_to(app);
  double duration = 0;
  double coordinator_overlap_s = 5;
  app.add_option("--duration", duration, "stop after this many seconds (0 = until a signal)")
      ->check(ctsfleet::number_in(0, 1e6))
      ->capture_default_str();
  app.add_option("--coordinator-overlap", coordinator_overlap_s,
                 "seconds two coordinators may both be active (one listening, then standing down) before it is an alarm")
      ->check(ctsfleet::number_in(0, 3600))
      ->capture_default_str();
  return program.main(argc, argv, [&] {
    const std::atomic<bool>& g_stop = ctsfleet::stop_requested();
    const fleet_transport::TransportConfig config = dds.transport_config();

    std::mutex mutex;
    // Paths per robot process: "id#incarnation", so a restart starts a new path and a second process
    // under one id is told apart from the first.
    std::map<std::string, std::vector<Visit>> visits;
    struct Incarnation {
      std::chrono::steady_clock::time_point first_heard, last_heard;
    };
    std::map<std::string, std::map<uint64_t, Incarnation>> incarnations;  // robot id -> its processes
    std::set<std::pair<std::string, std::pair<uint64_t, uint64_t>>> duplicates;
    int64_t gaps = 0, states = 0;
    coordinator::ActiveCoordinatorWatch coordinators(
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(coordinator_overlap_s)));
    fleet_transport::Handlers handlers;
    bool closed = false;
    handlers.on_coordinator_status = [&](const fleet_transport::CoordinatorStatus& status) {
      const std::lock_guard<std::mutex> lock(mutex);
      if (closed) return;
      if (const auto alarm = coordinators.on_status(status, std::chrono::steady_clock::now())) spdlog::error("{}", *alarm);
    };
    // Each robot process stamps arrivals on its own host's clock. Per process, the smallest
    // (this monitor's receive time - the stamp) is that clock's offset from ours plus the shortest
    // delivery delay: stamps + offset put every robot on this monitor's clock, so hosts whose
    // clocks disagree by seconds are judged alike.
    std::map<std::string, int64_t> clock_offset_ms;  // "id#incarnation" -> offset
    // A restarted robot: (old process, new process); the old one's last stay ends where the new
    // one's first begins.
    std::vector<std::pair<std::string, std::string>> handovers;
    handlers.on_state = [&](const fleet_transport::RobotState& s) {
      const int64_t received_ms = fleet_transport::wall_clock_ms();
      const std::lock_guard<std::mutex> lock(mutex);
      if (closed) return;
      ++states;
      const std::string key = s.robot_id + "#" + std::to_string(s.incarnation);
      if (const auto [offset, first] = clock_offset_ms.try_emplace(key, received_ms - s.stamp_ms); !first) {
        offset->second = std::min(offset->second, received_ms - s.stamp_ms);
      }
      const auto now = std::chrono::steady_clock::now();
      auto& of_robot = incarnations[s.robot_id];
      const bool new_process = of_robot.find(s.incarnation) == of_robot.end();
      Incarnation& self = of_robot[s.incarnation];
      if (new_process) {
        self.first_heard = now;
        spdlog::info("first state of {} (process {:016x})", s.robot_id, s.incarnation);
      }
      self.last_heard = now;
      for (const auto& [other, seen] : of_robot) {
        if (other == s.incarnation) continue;
        // A restart hands over (the old process falls silent before the new one speaks, give or take
        // states in flight); two processes both heard after the other began are a duplicate id.
        constexpr auto kGrace = std::chrono::milliseconds(300);
        const auto overlap = std::min(seen.last_heard, self.last_heard) - std::max(seen.first_heard, self.first_heard);
        if (overlap > kGrace &&
            duplicates.insert({s.robot_id, {std::min(other, s.incarnation), std::max(other, s.incarnation)}}).second) {
          spdlog::error("duplicate robot id {}: two processes (incarnations {:016x} and {:016x}) publish states", s.robot_id,
                        other, s.incarnation);
        }
        if (new_process) {  // the other's last cell is left when this one starts (a restart)
          auto& other_path = visits[s.robot_id + "#" + std::to_string(other)];
          if (!other_path.empty() && other_path.back().to_ms == INT64_MAX) {
            Visit& last = other_path.back();
            // Heard first on that cell or the next one: left by the time of this state. Heard
            // first further away (its first states were not heard): when it left is unknown,
            // so that stay is not judged, as for a lost state.
            if (std::abs(last.x - s.cell_x) + std::abs(last.y - s.cell_y) <= 1) {
              // Closed when judged, once both processes' clocks are known well (the new one's
              // first state may have waited for discovery: its offset is not yet its own).
              handovers.emplace_back(s.robot_id + "#" + std::to_string(other), key);
            } else {
              ++gaps;
              last.to_ms = last.from_ms;
            }
          }
        }
      }
      std::vector<Visit>& path = visits[key];
      if (!path.empty() && path.back().x == s.cell_x && path.back().y == s.cell_y) return;
      if (!path.empty()) {
        Visit& last = path.back();
        if (s.stamp_ms < last.from_ms) return;  // an older state arriving late
        if (std::abs(last.x - s.cell_x) + std::abs(last.y - s.cell_y) == 1) {
          last.to_ms = s.stamp_ms;
        } else {
          ++gaps;  // a lost state: we do not know when the robot left `last`; do not judge it
          last.to_ms = last.from_ms;
        }
      }
      path.push_back({s.cell_x, s.cell_y, s.stamp_ms, INT64_MAX});
    };
    handlers.on_refused = [](const std::string& what) { spdlog::warn("refused: {}", what); };
    auto transport = fleet_transport::make_transport(config, handlers);
    const auto start = std::chrono::steady_clock::now();
    while (!g_stop.load() &&
           (duration <= 0 || std::chrono::steady_clock::now() - start < std::chrono::duration<double>(duration))) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    {
      const std::lock_guard<std::mutex> lock(mutex);
      closed = true;  // what arrives from now on is not judged; the transport goes last (see below)
    }

    // Every pair of visits of one cell by different robots must not overlap in time, on this
    // monitor's clock.
    for (auto& [id, path] : visits) {
      const int64_t offset = clock_offset_ms[id];
      for (Visit& visit : path) {
        visit.from_ms += offset;
        if (visit.to_ms != INT64_MAX) visit.to_ms += offset;
      }
    }
    for (const auto& [old_process, new_process] : handovers) {
      std::vector<Visit>& old_path = visits[old_process];
      const std::vector<Visit>& new_path = visits[new_process];
      if (old_path.empty() || new_path.empty() || old_path.back().to_ms != INT64_MAX) continue;
      old_path.back().to_ms = std::max(old_path.back().from_ms, new_path.front().from_ms);
    }
    std::map<std::pair<int, int>, std::vector<std::pair<const Visit*, const std::string*>>> by_cell;
    int64_t cell_visits = 0;
    for (const auto& [id, path] : visits) {
      for (const Visit& visit : path) {
        by_cell[{visit.x, visit.y}].emplace_back(&visit, &id);
        ++cell_visits;
      }
    }
    int overlaps = 0;
    for (auto& [cell, list] : by_cell) {
      std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.first->from_ms < b.first->from_ms; });
      for (size_t i = 0; i + 1 < list.size(); ++i) {
        for (size_t j = i + 1; j < list.size() && list[j].first->from_ms < list[i].first->to_ms; ++j) {
          if (*list[i].second == *list[j].second) continue;  // one process's own consecutive visits
          ++overlaps;
          spdlog::error("collision: {} and {} both on ({},{}) around t={} ms", *list[i].second, *list[j].second,
                        cell.first, cell.second, list[j].first->from_ms);
        }
      }
    }
    std::printf("monitor: robots %zu, processes %zu, states %lld, cell visits %lld, overlaps %d, gaps %lld, "
                "duplicate ids %zu, coordinators active together %zu\n",
                incarnations.size(), visits.size(), static_cast<long long>(states), static_cast<long long>(cell_visits),
                overlaps, static_cast<long long>(gaps), duplicates.size(), coordinators.alarms());
    // For each id claimed twice, how far each of its processes went: a refused one stays on 1 cell.
    for (const auto& [robot_id, pair] : duplicates) {
      for (const uint64_t incarnation : {pair.first, pair.second}) {
        const auto path = visits.find(robot_id + "#" + std::to_string(incarnation));
        std::printf("monitor: duplicate %s: process %016llx on %zu cells\n", robot_id.c_str(),
                    static_cast<unsigned long long>(incarnation), path == visits.end() ? size_t{0} : path->second.size());
      }
    }
    std::fflush(stdout);
    int verdict = overlaps == 0 && duplicates.empty() && coordinators.alarms() == 0 ? 0 : 1;
    if (incarnations.empty()) {
      std::fprintf(stderr, "ctsfleet-monitor: heard no robot on %s domain %d with DDS config %s: nothing was checked\n",
                   dds.vendor.c_str(), config.domain_id, config.loopback_config_dir.c_str());
      verdict = kExitHeardNothing;
    }
    fleet_transport::exit_if_shutdown_hangs(1.5, verdict);
    transport.reset();
    return verdict;
  });
}
