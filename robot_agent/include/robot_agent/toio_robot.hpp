// ToioRobot: a toio Core Cube on a position mat, driven over BLE through BlueZ. A BLE thread of its
// own finds the cube, connects, configures it and serves it (notifications in, move commands out),
// and reconnects with backoff when the link drops; the agent's thread only exchanges state with it
// under a mutex, so BLE never blocks DDS.
//
// One grid move = one move-to-target write (03) to the centre of the target cell, rotate after
// moving, a fresh control id; with a target heading (plans with turns) the cube ends facing it, and
// a turn in place is the same write to its own cell. Arrival = the 83 response says success, or a
// Position ID within the mat's tolerance of the target's centre (and of its heading, if any). Everything that goes wrong is a fault the coordinator sees
// in the robot's state, never a hang: not connected yet, link lost, cube lifted (ID missed), on a
// card instead of the mat, between cells, a move refused, timed out or preempted.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "robot_agent/mat_calibration.hpp"
#include "robot_agent/robot_backend.hpp"
#include "robot_agent/toio_protocol.hpp"

namespace robot_agent {

class BluezClient;

struct ToioSettings {
  std::string cube;              // advertised name (toio-XXX) or Bluetooth address
  std::string adapter = "hci0";
  uint8_t max_speed = 80;        // toio speed units, 10-255
  uint8_t move_timeout_s = 5;    // the cube gives up a move after this long (83 code 1)
  double expected_move_s = 0.8;  // a guess of one move's duration, for the agent's wake-ups
  double discovery_timeout_s = 10;
  double connect_timeout_s = 10;
  double reconnect_backoff_min_s = 0.5;
  double reconnect_backoff_max_s = 8;
  double fault_hold_s = 1.0;     // a failed move stays a fault at least this long, so it is seen
  uint8_t id_interval_10ms = 5;  // Position ID notifications at most every 50 ms, on change
  bool identify_on_connect = true;  // green light and a short beep when connected
};

class ToioRobot : public RobotBackend {
 public:
  ToioRobot(ToioSettings settings, MatCalibration calibration);
  ~ToioRobot() override;
  ToioRobot(const ToioRobot&) = delete;
  ToioRobot& operator=(const ToioRobot&) = delete;

  std::string kind() const override { return "toio"; }
  bool start_move(Cell target, int target_heading) override;
  BackendReport poll() override;
  std::optional<std::chrono::steady_clock::duration> time_to_arrival() const override;

  // Why the robot is in fault (empty when it is not).
  std::string fault_reason() const;
  bool connected() const;
  // The latest Position ID, in mat coordinates (nullopt while none or off the mat).
  std::optional<toio::PositionId> mat_position() const;
  // Blink and beep the cube so a person can tell which one it is.
  void identify();
  const MatCalibration& calibration() const { return calibration_; }

 private:
  using Clock = std::chrono::steady_clock;
  struct Move {
    Cell target;
    int heading = -1;  // the grid heading to end facing; -1 any
    uint8_t control_id = 0;
    Clock::time_point started;
    bool written = false;
    bool recovery = false;  // our own move back onto a cell after an interrupted one
  };
  // A move that failed part way: the two cells the cube may stand between.
  struct InterruptedMove {
    Cell from, to;
  };

  struct CubeLink;
  void ble_thread();
  // One connection: open (find, connect, subscribe, configure), run until lost or stopped, leave.
  void serve_connection(BluezClient& client);
  void open_link(BluezClient& client, CubeLink& link);
  void run_link(BluezClient& client, const CubeLink& link);
  void write_move(BluezClient& client, const CubeLink& link, const Move& move);
  void flash_and_beep(BluezClient& client, const CubeLink& link);
  void on_id(const toio::Bytes& bytes);
  void on_motor(const toio::Bytes& bytes);
  void on_battery(const toio::Bytes& bytes);
  // Both with mutex_ held.
  void set_fault(const std::string& reason, bool sticky);
  void finish_move(Cell at);
  // After an interrupted move the cube may stand between its two cells, both of which the
  // coordinator keeps clear for it; drive it onto the nearer one (once) so it can rejoin.
  void start_recovery_if_needed();
  void stand_on(Cell cell);
  bool link_open() const { return client_ != nullptr; }
  // The cube faces grid heading `heading`, within kFacingToleranceDeg (false while its angle is unknown).
  bool facing(int heading) const;  // seen standing on a cell while not moving

  const ToioSettings settings_;
  const MatCalibration calibration_;

  mutable std::mutex mutex_;
  std::condition_variable stop_requested_;
  bool stop_ = false;
  bool wake_requested_ = false;
  bool identify_requested_ = false;
  std::optional<toio::PositionId> position_;
  bool have_cell_ = false;
  Cell cell_;
  CellLookup lookup_;
  std::optional<Move> move_;
  std::optional<InterruptedMove> interrupted_;
  uint8_t next_control_id_ = 1;
  std::string fault_ = "not connected yet";
  bool fault_sticky_ = false;
  Clock::time_point fault_since_;
  int battery_percent_ = -1;
  int64_t arrived_ms_ = 0;
  BluezClient* client_ = nullptr;  // set while a connection to the cube is open (also for wake())
  std::thread thread_;
};

}  // namespace robot_agent
