// The toio Core Cube's BLE protocol (spec v2.4.0): UUIDs, what we write to the cube and what it
// notifies back. Pure functions over byte vectors, no I/O. Multi-byte values are little-endian.
// Decoders never read past the bytes they are given: a short or unknown message is an error with a
// reason, never a guess.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace robot_agent::toio {

using Bytes = std::vector<uint8_t>;

// BlueZ reports UUIDs in lower case.
inline constexpr const char* kServiceUuid = "10b20100-5b3b-4571-9508-cf3efcd7bbae";
inline constexpr const char* kIdUuid = "10b20101-5b3b-4571-9508-cf3efcd7bbae";
inline constexpr const char* kMotorUuid = "10b20102-5b3b-4571-9508-cf3efcd7bbae";
inline constexpr const char* kLightUuid = "10b20103-5b3b-4571-9508-cf3efcd7bbae";
inline constexpr const char* kSoundUuid = "10b20104-5b3b-4571-9508-cf3efcd7bbae";
inline constexpr const char* kSensorUuid = "10b20106-5b3b-4571-9508-cf3efcd7bbae";
inline constexpr const char* kButtonUuid = "10b20107-5b3b-4571-9508-cf3efcd7bbae";
inline constexpr const char* kBatteryUuid = "10b20108-5b3b-4571-9508-cf3efcd7bbae";
inline constexpr const char* kConfigurationUuid = "10b201ff-5b3b-4571-9508-cf3efcd7bbae";

// A cube advertises "toio-XXX" (older firmware: "toio Core Cube-XXX").
bool is_cube_name(const std::string& advertised_name);

// ---- Motor ----------------------------------------------------------------------------------

// Wheel speed -255..255; negative drives backwards.
Bytes encode_motor_control(int left_speed, int right_speed);
// Same, stopping after duration_10ms x 10 ms (0 = run until the next command).
Bytes encode_motor_control_timed(int left_speed, int right_speed, uint8_t duration_10ms);

enum class MoveType : uint8_t { kRotateWhileMoving = 0, kRotateWithoutReversing = 1, kRotateAfterMoving = 2 };
enum class SpeedChange : uint8_t { kConstant = 0, kAccelerate = 1, kDecelerate = 2, kAccelerateThenDecelerate = 3 };
enum class RotationType : uint8_t {
  kAbsoluteShortest = 0,
  kAbsolutePositive = 1,
  kAbsoluteNegative = 2,
  kRelativePositive = 3,
  kRelativeNegative = 4,
  kNoRotation = 5,
  kSameAsWrite = 6,
};

inline constexpr uint16_t kKeepCoordinate = 0xFFFF;  // x or y: keep the current value

struct MatTarget {
  uint16_t x = 0;
  uint16_t y = 0;
  uint16_t angle = 0;  // degrees, 0-360 (13 bits)
  RotationType rotation = RotationType::kNoRotation;
};

struct MoveSettings {
  uint8_t control_id = 0;
  uint8_t timeout_s = 0;  // 0 = the cube's default, 10 s
  MoveType move_type = MoveType::kRotateAfterMoving;
  uint8_t max_speed = 80;  // 10-255
  SpeedChange speed_change = SpeedChange::kConstant;
};

Bytes encode_move_to_target(const MoveSettings& settings, const MatTarget& target);
// 1 to 29 targets; append = true queues them after the targets in progress.
Bytes encode_move_to_targets(const MoveSettings& settings, bool append, std::span<const MatTarget> targets);

// ---- Configuration --------------------------------------------------------------------------

enum class IdNotifyCondition : uint8_t { kAlways = 0x00, kOnChange = 0x01, kDefault = 0xFF };

Bytes encode_protocol_version_request();
Bytes encode_id_notification_rate(uint8_t interval_10ms, IdNotifyCondition condition);
Bytes encode_id_missed_sensitivity(uint8_t sensitivity_10ms);
Bytes encode_speed_information(bool enabled);
Bytes encode_connection_interval(uint16_t min_interval, uint16_t max_interval);

// ---- Light and sound, to tell cubes apart -----------------------------------------------------

Bytes encode_light_on(uint8_t duration_10ms, uint8_t red, uint8_t green, uint8_t blue);
Bytes encode_light_off();
// One note (MIDI 0-127, 128 = rest) of duration_10ms, played `repeat` times (0 = forever).
Bytes encode_beep(uint8_t note, uint8_t duration_10ms, uint8_t volume, uint8_t repeat);
Bytes encode_sound_stop();

// ---- Notifications --------------------------------------------------------------------------

struct PositionId {
  uint16_t x = 0, y = 0, angle = 0;
  uint16_t sensor_x = 0, sensor_y = 0, sensor_angle = 0;
};
struct StandardId {
  uint32_t value = 0;
  uint16_t angle = 0;
};
struct PositionIdMissed {};
struct StandardIdMissed {};
using IdReading = std::variant<PositionId, StandardId, PositionIdMissed, StandardIdMissed>;

enum class MotorResult : uint8_t {
  kSuccess = 0,
  kTimeout = 1,
  kIdMissed = 2,
  kBadParameters = 3,
  kInvalidState = 4,
  kPreempted = 5,
  kNotSupported = 6,
  kCannotAppend = 7,
};
const char* describe(MotorResult result);

struct MotorResponse {
  bool multiple_targets = false;  // 0x84 (to a 04 write) rather than 0x83 (to 03)
  uint8_t control_id = 0;
  MotorResult result = MotorResult::kSuccess;
};
struct MotorSpeed {  // 0xE0, when speed information is enabled
  uint8_t left = 0, right = 0;
};
using MotorNotification = std::variant<MotorResponse, MotorSpeed>;

struct ConfigurationReply {
  uint8_t type = 0;      // the reply's first byte (0x81, 0x98, 0x99, 0x9C, 0xB0, ...)
  uint8_t code = 0;      // 0 = accepted (for 0x81: the reserved byte)
  std::string version;   // 0x81 only: the protocol version, "2.4.0"
};

struct ButtonState {
  uint8_t button_id = 0;
  bool pressed = false;
};

// The result of decoding: a value, or the reason there is none.
template <typename T>
struct Decoded {
  std::optional<T> value;
  std::string error;
  explicit operator bool() const { return value.has_value(); }
};

Decoded<IdReading> decode_id(std::span<const uint8_t> bytes);
Decoded<MotorNotification> decode_motor(std::span<const uint8_t> bytes);
Decoded<ConfigurationReply> decode_configuration(std::span<const uint8_t> bytes);
Decoded<int> decode_battery(std::span<const uint8_t> bytes);  // percent
Decoded<ButtonState> decode_button(std::span<const uint8_t> bytes);

std::string to_hex(std::span<const uint8_t> bytes);  // "03 00 05 ..."

}  // namespace robot_agent::toio
