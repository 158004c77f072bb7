// ctsfleet-toio-emulator: emulated toio cubes behind a fake BlueZ on a private D-Bus, so the toio
// backend runs its real D-Bus code path without a radio. Start a private bus first:
//   dbus-daemon --session --print-address --fork   (or let ctsfleet-sim --backend toio-emulated do it)
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "fake_bluez.hpp"
#include "planner_core/input_error.hpp"
#include "robot_agent/dbus_event_pump.hpp"
#include "robot_agent/mat_calibration.hpp"

namespace {
std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

// "NAME@X,Y[,ANGLE]" (mat coordinates) or "NAME@cell:X,Y" (needs a mat file).
toio_emulator::CubeSpec parse_cube(const std::string& text, const robot_agent::MatCalibration* mat) {
  const size_t at = text.find('@');
  if (at == std::string::npos || at == 0) throw std::invalid_argument("--cube must be NAME@X,Y[,ANGLE] or NAME@cell:X,Y, got '" + text + "'");
  toio_emulator::CubeSpec spec;
  spec.name = text.substr(0, at);
  const std::string where = text.substr(at + 1);
  if (where.rfind("cell:", 0) == 0) {
    int x = 0, y = 0;
    if (!mat) throw std::invalid_argument("--cube " + text + ": a cell needs --mat");
    if (std::sscanf(where.c_str() + 5, "%d,%d", &x, &y) != 2) throw std::invalid_argument("--cube " + text + ": cell must be X,Y");
    const Eigen::Vector2d centre = mat->cell_centre({x, y});
    spec.pose = {centre.x(), centre.y(), mat->grid_heading_deg()};
    return spec;
  }
  const int read = std::sscanf(where.c_str(), "%lf,%lf,%lf", &spec.pose.x, &spec.pose.y, &spec.pose.angle_deg);
  if (read < 2) throw std::invalid_argument("--cube " + text + ": position must be X,Y[,ANGLE]");
  return spec;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ctsfleet-toio-emulator: toio cubes behind a fake BlueZ on a private D-Bus"};
  std::string bus, adapter = "hci0", mat_file;
  std::vector<std::string> cube_texts;
  double speed_per_unit = 2.0, tick_ms = 10;
  app.add_option("--bus", bus, "D-Bus address to serve on (default: $DBUS_SYSTEM_BUS_ADDRESS; never the real system bus)");
  app.add_option("--cube", cube_texts, "a cube: NAME@X,Y[,ANGLE] in mat coordinates, or NAME@cell:X,Y with --mat")->required();
  app.add_option("--mat", mat_file, "mat file, to place cubes by cell");
  app.add_option("--adapter", adapter, "adapter name")->capture_default_str();
  app.add_option("--speed-per-unit", speed_per_unit, "mat units per second per unit of max_speed")->capture_default_str();
  app.add_option("--tick-ms", tick_ms, "simulation step in milliseconds")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  if (bus.empty()) {
    if (const char* env = std::getenv("DBUS_SYSTEM_BUS_ADDRESS")) bus = env;
  }
  if (bus.empty()) {
    spdlog::error("no bus: give --bus or set DBUS_SYSTEM_BUS_ADDRESS to a private bus (the emulator never serves on "
                  "the real system bus)");
    return 2;
  }
  std::vector<toio_emulator::CubeSpec> cubes;
  try {
    std::optional<robot_agent::MatCalibration> mat;
    if (!mat_file.empty()) mat = robot_agent::MatCalibration::load(mat_file);
    for (const std::string& text : cube_texts) cubes.push_back(parse_cube(text, mat ? &*mat : nullptr));
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  try {
    auto connection = sdbus::createSessionBusConnectionWithAddress(bus);
    toio_emulator::FakeBluez bluez(*connection, cubes, adapter, speed_per_unit);
    connection->requestName("org.bluez");
    robot_agent::DbusEventPump pump(*connection);
    std::cout << "toio-emulator ready: " << cubes.size() << " cubes on " << bus << std::endl;
    const auto tick = std::chrono::microseconds(static_cast<int64_t>(tick_ms * 1000));
    auto last = std::chrono::steady_clock::now();
    auto next_tick = last + tick;
    while (!g_stop.load()) {
      const auto now = std::chrono::steady_clock::now();
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
}
