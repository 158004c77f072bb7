// ToioCubeModel: one emulated toio Core Cube, the peripheral side of the protocol, without D-Bus.
// It keeps the cube's pose on the mat, obeys motor and configuration writes (move-to-target turns
// in place towards the target, then drives straight at a speed set by max_speed, then turns to the
// target's angle if it has one: absolute rotation types 0-2), and produces the
// notifications a real cube sends: Position ID at the configured rate, ID missed when lifted, 83/84
// motor responses, configuration replies. Written from the spec independently of the central's
// codec (robot_agent/toio_protocol.hpp; only the UUIDs are shared), so the two check each other
// in the end-to-end tests.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace toio_emulator {

using Bytes = std::vector<uint8_t>;

enum class Characteristic { kId, kMotor, kLight, kSound, kSensor, kButton, kBattery, kConfiguration };

struct Notification {
  Characteristic characteristic;
  Bytes value;
};

struct CubePose {
  double x = 0, y = 0;
  double angle_deg = 0;  // clockwise from the mat's +x axis
};

class ToioCubeModel {
 public:
  // linear speed on the mat = speed_per_unit x max_speed (mat units per second).
  explicit ToioCubeModel(CubePose pose, double speed_per_unit = 2.0);

  // A write from the central; returns the immediate replies (configuration answers, preemptions).
  std::vector<Notification> write(Characteristic characteristic, const Bytes& value);
  // What a read of the characteristic returns now.
  Bytes read(Characteristic characteristic) const;
  // Advances the cube by dt seconds; returns what it notifies meanwhile.
  std::vector<Notification> advance(double dt);

  void lift();  // off the mat: ID missed, a move in progress fails
  void place(CubePose pose);
  void disconnected();  // settings reset and motors stop, as on a real cube
  void set_blocked(bool blocked) { blocked_ = blocked; }  // wheels spin, the cube does not move
  // Delayed, as the league delays a robot: it stands still and its move waits (its time-out too),
  // then goes on where it stopped.
  void set_paused(bool paused) { paused_ = paused; }

  const CubePose& pose() const { return pose_; }
  bool on_mat() const { return on_mat_; }
  bool moving() const { return move_.has_value(); }
  int light_writes() const { return light_writes_; }
  int sound_writes() const { return sound_writes_; }

 private:
  struct Move {
    uint8_t control_id = 0;
    bool multiple = false;
    double target_x = 0, target_y = 0;
    std::optional<double> target_angle;  // absolute angle to turn to after moving (none: no rotation)
    double time_left = 10;
    uint8_t max_speed = 80;
  };
  Bytes position_bytes() const;
  Notification motor_response(const Move& move, uint8_t code) const;

  CubePose pose_;
  double speed_per_unit_;
  bool on_mat_ = true;
  bool blocked_ = false;
  bool paused_ = false;
  std::optional<Move> move_;
  // ID notification settings (reset on disconnect).
  double id_interval_s_ = 0.01;
  bool id_on_change_only_ = true;
  double since_id_notify_ = 0;
  std::optional<CubePose> last_notified_;
  bool missed_notified_ = false;
  int light_writes_ = 0;
  int sound_writes_ = 0;
};

}  // namespace toio_emulator
