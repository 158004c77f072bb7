// ctsfleet-toio-emulator: emulated toio cubes behind a fake BlueZ on a private D-Bus, so the toio
// backend runs its real D-Bus code path without a radio. Start a private bus first:
//   dbus-daemon --session --print-address --fork   (or let ctsfleet-sim --backend toio-emulated do it)
#include <spdlog/spdlog.h>

#include <atomic>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <optional>

#include <set>

#include "ctsfleet/program.hpp"
#include "fake_bluez.hpp"
#include "planner_core/delay_draws.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/lorr_problem.hpp"
#include "robot_agent/dbus_event_pump.hpp"
#include "robot_agent/mat_calibration.hpp"

namespace {
using planner_core::InputError;

// "NAME@X,Y[,ANGLE]" (mat coordinates) or "NAME@cell:X,Y" (needs a mat file).
toio_emulator::CubeSpec parse_cube(const std::string& text, const robot_agent::MatCalibration* mat) {
  const size_t at = text.find('@');
  if (at == std::string::npos || at == 0) throw InputError("--cube must be NAME@X,Y[,ANGLE] or NAME@cell:X,Y, got '" + text + "'");
  toio_emulator::CubeSpec spec;
  spec.name = text.substr(0, at);
  const std::string where = text.substr(at + 1);
  if (where.rfind("cell:", 0) == 0) {
    int x = 0, y = 0;
    if (!mat) throw InputError("--cube " + text + ": a cell needs --mat");
    if (std::sscanf(where.c_str() + 5, "%d,%d", &x, &y) != 2) throw InputError("--cube " + text + ": cell must be X,Y");
    if (x < 0 || y < 0 || x >= mat->grid_width() || y >= mat->grid_height()) {
      throw InputError("--cube " + text + ": cell " + std::to_string(x) + "," + std::to_string(y) + " is outside the " +
                       std::to_string(mat->grid_width()) + "x" + std::to_string(mat->grid_height()) + " grid of the mat");
    }
    const Eigen::Vector2d centre = mat->cell_centre({x, y});
    spec.pose = {centre.x(), centre.y(), mat->grid_heading_deg()};
    return spec;
  }
  const int read = std::sscanf(where.c_str(), "%lf,%lf,%lf", &spec.pose.x, &spec.pose.y, &spec.pose.angle_deg);
  if (read < 2 || !std::isfinite(spec.pose.x) || !std::isfinite(spec.pose.y) || !std::isfinite(spec.pose.angle_deg) ||
      std::abs(spec.pose.x) > 1e5 || std::abs(spec.pose.y) > 1e5) {
    throw InputError("--cube " + text + ": position must be finite X,Y[,ANGLE] mat coordinates");
  }
  return spec;
}
}  // namespace

int main(int argc, char** argv) {
  ctsfleet::Program program("ctsfleet-toio-emulator", "toio cubes behind a fake BlueZ on a private D-Bus");
  CLI::App& app = program.app();
  std::string bus, adapter = "hci0", mat_file;
  std::vector<std::string> cube_texts;
  double speed_per_unit = 2.0, tick_ms = 10;
  app.add_option("--bus", bus, "D-Bus address to serve on (default: $DBUS_SYSTEM_BUS_ADDRESS; never the real system bus)");
  app.add_option("--cube", cube_texts, "a cube: NAME@X,Y[,ANGLE] in mat coordinates, or NAME@cell:X,Y with --mat")->required();
  app.add_option("--mat", mat_file, "mat file, to place cubes by cell")->check(CLI::ExistingFile);
  app.add_option("--adapter", adapter, "adapter name")->capture_default_str();
  app.add_option("--speed-per-unit", speed_per_unit, "mat units per second per unit of max_speed")
      ->check(ctsfleet::number_in(0.01, 100))
      ->capture_default_str();
  app.add_option("--tick-ms", tick_ms, "simulation step in milliseconds")->check(ctsfleet::number_in(0.1, 1000))->capture_default_str();
  std::string delay_config;
  double delay_tick_s = 0.1;
  unsigned seed = 0;
  app.add_option("--delay-config", delay_config,
                 "cubes delayed (they stand still, their moves wait) as the League of Robot Runners' 2026 rules "
                 "draw delays: a JSON file holding a delayConfig (itself, or a problem with one); seed: its seed "
                 "plus --seed")
      ->check(CLI::ExistingFile);
  app.add_option("--delay-tick", delay_tick_s, "with --delay-config: seconds per tick of the delay model")
      ->check(ctsfleet::number_in(0.001, 3600))
      ->capture_default_str();
  app.add_option("--seed", seed, "with --delay-config: added to the delayConfig's seed")->capture_default_str();
  return program.main(argc, argv, [&] {
    const std::atomic<bool>& g_stop = ctsfleet::stop_requested();
    if (bus.empty()) {
      if (const char* env = std::getenv("DBUS_SYSTEM_BUS_ADDRESS")) bus = env;
    }
    if (bus.empty()) {
      throw InputError("--bus: no bus given and DBUS_SYSTEM_BUS_ADDRESS unset; give a private bus (the emulator never "
                       "serves on the real system bus)");
    }
    std::vector<toio_emulator::CubeSpec> cubes;
    std::optional<robot_agent::MatCalibration> mat;
    if (!mat_file.empty()) mat = robot_agent::MatCalibration::load(mat_file);
    std::set<std::string> names;
    for (const std::string& text : cube_texts) {
      cubes.push_back(parse_cube(text, mat ? &*mat : nullptr));
      if (!names.insert(cubes.back().name).second) throw InputError("--cube " + text + ": a second cube named " + cubes.back().name);
    }
    std::optional<planner_core::DelayDraws> delays;
    if (!delay_config.empty()) {
      planner_core::LeagueDelays config = planner_core::load_delay_config(delay_config);
      config.seed += seed;
      delays.emplace(config, static_cast<int>(cubes.size()));
    }
    try {
      auto connection = sdbus::createSessionBusConnectionWithAddress(bus);
      toio_emulator::FakeBluez bluez(*connection, cubes, adapter, speed_per_unit);
      connection->requestName("org.bluez");
      robot_agent::DbusEventPump pump(*connection);
      std::cout << "toio-emulator ready: " << cubes.size() << " cubes on " << bus;
      if (delays) std::cout << ", delays from " << delay_config << " every " << delay_tick_s << " s";
      std::cout << std::endl;
      const auto tick = std::chrono::microseconds(static_cast<int64_t>(tick_ms * 1000));
      auto last = std::chrono::steady_clock::now();
      auto next_tick = last + tick;
      const auto delay_tick = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(delay_tick_s));
      auto next_delay_tick = last;
      while (!g_stop.load()) {
        const auto now = std::chrono::steady_clock::now();
        for (; delays && now >= next_delay_tick; next_delay_tick += delay_tick) {
          for (int cube : delays->tick()) {
            spdlog::info("cube {} delayed for {} ticks", cubes[cube].name, delays->ticks_left(cube));
          }
          for (size_t cube = 0; cube < cubes.size(); ++cube) bluez.set_paused(cube, delays->delayed(static_cast<int>(cube)));
        }
        if (now >= next_tick) {
          bluez.tick(std::chrono::duration<double>(now - last).count());
          last = now;
          next_tick = now + tick;
        }
        pump.run_once(std::chrono::ceil<std::chrono::milliseconds>(next_tick - std::chrono::steady_clock::now()));
      }
      connection->releaseName("org.bluez");
      return 0;
    } catch (const sdbus::Error& e) {
      spdlog::error("D-Bus: {}: {}", e.getName(), e.getMessage());
      return 1;
    }
  });
}
