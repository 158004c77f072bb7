// ctsfleet-toio-calibrate: where the grid lies on a toio mat.
//   fit      fits the grid-to-mat transform by least squares from a cube placed on three or more
//            known cells (or from measured points given on the command line), writes a mat file
//            and reports the residual;
//   corners  drives a cube to the four corner cells of the grid and reports how far from each
//            cell centre it stops (exit 1 when one is beyond the mat file's tolerance);
//   identify blinks and beeps a cube so a person can tell which one it is;
//   scan     lists the toio cubes in range (name, address, signal strength).
#include <spdlog/spdlog.h>

#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <regex>
#include <iostream>
#include <sstream>
#include <thread>

#include "ctsfleet/program.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/yaml_context.hpp"
#include "robot_agent/bluez_client.hpp"
#include "robot_agent/mat_calibration.hpp"
#include "robot_agent/toio_robot.hpp"

namespace {

using namespace robot_agent;
using Clock = std::chrono::steady_clock;

template <typename Condition>
bool wait_until(Condition done, double timeout_s) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done()) {
    if (Clock::now() > deadline || ctsfleet::stop_requested().load()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

Cell parse_cell(const std::string& text) {
  Cell cell;
  if (std::sscanf(text.c_str(), "%d,%d", &cell.x, &cell.y) != 2) throw planner_core::InputError("'" + text + "' is not x,y");
  return cell;
}

// "X,Y=MX,MY": a cell and the mat coordinates measured on it. Cells are small non-negative
// integers, mat coordinates finite numbers within the toio mats' range (0-65535).
CalibrationPoint parse_point(const std::string& text) {
  static const std::regex kPoint(R"(^(\d{1,4}),(\d{1,4})=([-+0-9.eE]{1,32}),([-+0-9.eE]{1,32})$)");
  std::smatch parts;
  if (!std::regex_match(text, parts, kPoint)) {
    throw planner_core::InputError("--point '" + planner_core::cut(text) +
                                   "' must be X,Y=MAT_X,MAT_Y (a cell of at most 4 digits each, then two numbers)");
  }
  const auto coordinate = [&](int part, const char* name) {
    const std::string value = parts[part].str();
    char* end = nullptr;
    const double number = std::strtod(value.c_str(), &end);
    if (end != value.c_str() + value.size() || !std::isfinite(number) || number < 0 || number > 65535) {
      throw planner_core::InputError("--point '" + text + "': " + name + " is " + value +
                                     ", not a number in [0, 65535] (mat coordinates)");
    }
    return number;
  };
  CalibrationPoint point;
  point.cell = {std::stoi(parts[1].str()), std::stoi(parts[2].str())};
  point.mat = {coordinate(3, "MAT_X"), coordinate(4, "MAT_Y")};
  return point;
}

ToioSettings cube_settings(const std::string& cube, const std::string& adapter) {
  ToioSettings settings;
  settings.cube = cube;
  settings.adapter = adapter;
  return settings;
}

// The cube's mat position once it has stood still for 300 ms.
std::optional<Eigen::Vector2d> steady_position(const ToioRobot& robot, double timeout_s) {
  std::optional<Eigen::Vector2d> last;
  auto since = Clock::now();
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (Clock::now() < deadline) {
    const auto p = robot.mat_position();
    const std::optional<Eigen::Vector2d> now = p ? std::optional<Eigen::Vector2d>(Eigen::Vector2d(p->x, p->y)) : std::nullopt;
    if (now != last) {
      last = now;
      since = Clock::now();
    } else if (last && Clock::now() - since >= std::chrono::milliseconds(300)) {
      return last;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return std::nullopt;
}

int fit(const std::string& mat_file, const std::string& out_file, const std::vector<std::string>& point_texts,
        const std::string& cube, const std::string& adapter, const std::string& cells_text) {
  const MatCalibration base = MatCalibration::load(mat_file);
  std::vector<CalibrationPoint> points;
  for (const std::string& text : point_texts) points.push_back(parse_point(text));
  if (!cube.empty()) {
    ToioRobot robot(cube_settings(cube, adapter), base);
    std::printf("connecting to %s...\n", cube.c_str());
    std::fflush(stdout);
    if (!wait_until([&] { return robot.connected(); }, 60)) {
      std::printf("could not connect to %s: %s\n", cube.c_str(), robot.fault_reason().c_str());
      return 1;
    }
    std::istringstream cells(cells_text);
    for (std::string text; cells >> text;) {
      const Cell cell = parse_cell(text);
      std::printf("place %s on cell (%d,%d), then press Enter\n", cube.c_str(), cell.x, cell.y);
      std::fflush(stdout);
      std::string line;
      if (!std::getline(std::cin, line)) {
        std::printf("input ended before every cell was measured\n");
        return 1;
      }
      const auto position = steady_position(robot, 10);
      if (!position) {
        std::printf("no steady position from %s on cell (%d,%d): is it on the mat?\n", cube.c_str(), cell.x, cell.y);
        return 1;
      }
      std::printf("cell (%d,%d) at mat (%.0f, %.0f)\n", cell.x, cell.y, position->x(), position->y());
      points.push_back({cell, *position});
    }
  }
  const CalibrationFit result = fit_grid_to_mat(points);
  MatCalibration fitted(base.mat(), base.grid_width(), base.grid_height(), result.linear, result.offset,
                        base.tolerance());
  fitted.set_fit_residual(result.rms_residual);
  for (const CalibrationPoint& point : points) {
    const double error = (fitted.cell_centre(point.cell) - point.mat).norm();
    std::printf("  cell (%d,%d): measured (%.1f, %.1f), fitted centre off by %.2f units\n", point.cell.x, point.cell.y,
                point.mat.x(), point.mat.y(), error);
  }
  std::printf("fit: pitch %.2f x %.2f units, grid x axis at %.1f degrees, residual rms %.2f max %.2f units\n",
              fitted.linear().col(0).norm(), fitted.linear().col(1).norm(), fitted.grid_heading_deg(),
              result.rms_residual, result.max_residual);
  const std::vector<std::string> problems = fitted.problems();
  for (const std::string& problem : problems) std::printf("problem: %s\n", problem.c_str());
  if (!problems.empty()) return 1;
  if (result.max_residual > base.tolerance() / 2) {
    std::printf("problem: a measured point is %.1f units off the fit (more than half the tolerance %.1f): "
                "check the cells you named\n", result.max_residual, base.tolerance());
    return 1;
  }
  fitted.save(out_file, "written by ctsfleet-toio-calibrate fit from " + std::to_string(points.size()) + " cells");
  std::printf("wrote %s\n", out_file.c_str());
  return 0;
}

int corners(const std::string& mat_file, const std::string& cube, const std::string& adapter) {
  const MatCalibration mat = MatCalibration::load(mat_file);
  ToioRobot robot(cube_settings(cube, adapter), mat);
  if (!wait_until([&] { return !robot.poll().fault; }, 60)) {
    std::printf("%s is not ready: %s\n", cube.c_str(), robot.fault_reason().c_str());
    return 1;
  }
  const int w = mat.grid_width() - 1, h = mat.grid_height() - 1;
  bool all_good = true;
  for (Cell corner : {Cell{0, 0}, Cell{w, 0}, Cell{w, h}, Cell{0, h}}) {
    if (!robot.start_move(corner, -1)) {
      std::printf("%s refused the move to (%d,%d): %s\n", cube.c_str(), corner.x, corner.y, robot.fault_reason().c_str());
      return 1;
    }
    if (!wait_until([&] { return !robot.poll().moving; }, 30) || robot.poll().fault) {
      std::printf("corner (%d,%d) not reached: %s\n", corner.x, corner.y, robot.fault_reason().c_str());
      return 1;
    }
    const auto position = steady_position(robot, 10);
    if (!position) {
      std::printf("corner (%d,%d): no steady position\n", corner.x, corner.y);
      return 1;
    }
    const double error = (*position - mat.cell_centre(corner)).norm();
    const bool good = error <= mat.tolerance();
    all_good = all_good && good;
    std::printf("corner (%d,%d): stopped at mat (%.0f, %.0f), %.1f units from the cell centre: %s\n", corner.x,
                corner.y, position->x(), position->y(), error, good ? "ok" : "BEYOND TOLERANCE");
  }
  return all_good ? 0 : 1;
}

int identify(const std::string& mat_file, const std::string& cube, const std::string& adapter) {
  ToioRobot robot(cube_settings(cube, adapter), MatCalibration::load(mat_file));
  if (!wait_until([&] { return robot.connected(); }, 60)) {
    std::printf("could not connect to %s: %s\n", cube.c_str(), robot.fault_reason().c_str());
    return 1;
  }
  std::printf("%s: blinking and beeping (it did so on connecting, too)\n", cube.c_str());
  robot.identify();
  std::this_thread::sleep_for(std::chrono::seconds(1));  // let the light stay on before disconnecting
  return 0;
}

int scan(const std::string& adapter, double seconds) {
  BluezClient client(adapter);
  int found = 0;
  for (const BluezClient::Device& device : client.discover(std::chrono::milliseconds(static_cast<int>(seconds * 1000)))) {
    if (!toio::is_cube_name(device.name)) continue;
    std::printf("%-20s %s  %d dBm\n", device.name.c_str(), device.address.c_str(), device.rssi);
    ++found;
  }
  if (found == 0) std::printf("no toio cube found in %.0f s (switched on? in range?)\n", seconds);
  return found > 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  ctsfleet::Program program("ctsfleet-toio-calibrate", "find cubes, fit and check where the grid lies on a toio mat");
  CLI::App& app = program.app();
  app.require_subcommand(1);
  std::string mat_file, out_file, cube, adapter = "hci0", cells = "0,0 1,0 0,1";
  std::vector<std::string> points;

  CLI::App* fit_command = app.add_subcommand("fit", "fit the grid from a cube placed on known cells, write a mat file");
  fit_command->add_option("--mat", mat_file, "mat file with the mat's area and grid size (and a first guess)")
      ->required()
      ->check(CLI::ExistingFile);
  fit_command->add_option("-o,--out", out_file, "mat file to write")->required()->check(ctsfleet::writable_file());
  fit_command->add_option("--cube", cube, "measure with this cube (name or address), placed by hand cell by cell");
  fit_command->add_option("--cells", cells, "cells to measure with --cube, \"x,y x,y x,y ...\"")->capture_default_str();
  fit_command->add_option("--point", points, "a measured point X,Y=MAT_X,MAT_Y instead of a cube (repeat)");
  fit_command->add_option("--adapter", adapter)->capture_default_str();

  CLI::App* corners_command = app.add_subcommand("corners", "drive a cube to the grid's four corners and check");
  corners_command->add_option("--mat", mat_file, "mat file to check")->required()->check(CLI::ExistingFile);
  corners_command->add_option("--cube", cube, "cube name or address")->required();
  corners_command->add_option("--adapter", adapter)->capture_default_str();

  CLI::App* identify_command = app.add_subcommand("identify", "blink and beep a cube");
  identify_command->add_option("--mat", mat_file, "mat file")->required()->check(CLI::ExistingFile);
  identify_command->add_option("--cube", cube, "cube name or address")->required();
  identify_command->add_option("--adapter", adapter)->capture_default_str();
  double scan_seconds = 5;
  CLI::App* scan_command = app.add_subcommand("scan", "list the toio cubes in range");
  scan_command->add_option("--seconds", scan_seconds, "how long to discover")
      ->check(ctsfleet::positive_seconds(600))
      ->capture_default_str();
  scan_command->add_option("--adapter", adapter)->capture_default_str();
  return program.main(argc, argv, [&] {
    if (!app.get_option("--log-level")->count()) spdlog::set_level(spdlog::level::warn);  // the commands print what matters
    if (fit_command->parsed()) {
      if (cube.empty() && points.size() < 3) {
        throw planner_core::InputError("fit needs --cube or at least three --point measurements");
      }
      return fit(mat_file, out_file, points, cube, adapter, cells);
    }
    if (corners_command->parsed()) return corners(mat_file, cube, adapter);
    if (scan_command->parsed()) return scan(adapter, scan_seconds);
    return identify(mat_file, cube, adapter);
  });
}
