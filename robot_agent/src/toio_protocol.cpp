#include "robot_agent/toio_protocol.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace robot_agent::toio {

namespace {

void put_u16(Bytes& out, uint16_t value) {
  out.push_back(static_cast<uint8_t>(value & 0xFF));
  out.push_back(static_cast<uint8_t>(value >> 8));
}

uint16_t u16_at(std::span<const uint8_t> bytes, size_t at) {
  return static_cast<uint16_t>(bytes[at] | (bytes[at + 1] << 8));
}

uint32_t u32_at(std::span<const uint8_t> bytes, size_t at) {
  return static_cast<uint32_t>(bytes[at]) | (static_cast<uint32_t>(bytes[at + 1]) << 8) |
         (static_cast<uint32_t>(bytes[at + 2]) << 16) | (static_cast<uint32_t>(bytes[at + 3]) << 24);
}

// Motor direction byte and speed magnitude for a signed wheel speed.
void put_wheel(Bytes& out, uint8_t wheel_id, int speed) {
  if (speed < -255 || speed > 255) throw std::invalid_argument("toio wheel speed must be within -255..255");
  out.push_back(wheel_id);
  out.push_back(speed < 0 ? 2 : 1);
  out.push_back(static_cast<uint8_t>(speed < 0 ? -speed : speed));
}

void put_move_header(Bytes& out, const MoveSettings& settings) {
  if (settings.max_speed < 10) throw std::invalid_argument("toio max_speed must be within 10..255");
  out.push_back(settings.control_id);
  out.push_back(settings.timeout_s);
  out.push_back(static_cast<uint8_t>(settings.move_type));
  out.push_back(settings.max_speed);
  out.push_back(static_cast<uint8_t>(settings.speed_change));
  out.push_back(0x00);  // reserved
}

void put_target(Bytes& out, const MatTarget& target) {
  put_u16(out, target.x);
  put_u16(out, target.y);
  put_u16(out, static_cast<uint16_t>((static_cast<uint16_t>(target.rotation) << 13) | (target.angle & 0x1FFF)));
}

template <typename T>
Decoded<T> fail(std::string why) {
  return {std::nullopt, std::move(why)};
}

std::string length_error(const char* what, size_t expected, size_t got) {
  return std::string(what) + ": expected " + std::to_string(expected) + " bytes, got " + std::to_string(got);
}

}  // namespace

bool is_cube_name(const std::string& advertised_name) {
  return advertised_name.rfind("toio-", 0) == 0 || advertised_name.rfind("toio Core Cube", 0) == 0;
}

Bytes encode_motor_control(int left_speed, int right_speed) {
  Bytes out{0x01};
  put_wheel(out, 0x01, left_speed);
  put_wheel(out, 0x02, right_speed);
  return out;
}

Bytes encode_motor_control_timed(int left_speed, int right_speed, uint8_t duration_10ms) {
  Bytes out{0x02};
  put_wheel(out, 0x01, left_speed);
  put_wheel(out, 0x02, right_speed);
  out.push_back(duration_10ms);
  return out;
}

Bytes encode_move_to_target(const MoveSettings& settings, const MatTarget& target) {
  Bytes out{0x03};
  put_move_header(out, settings);
  put_target(out, target);
  return out;
}

Bytes encode_move_to_targets(const MoveSettings& settings, bool append, std::span<const MatTarget> targets) {
  if (targets.empty() || targets.size() > 29) throw std::invalid_argument("toio accepts 1 to 29 targets per write");
  Bytes out{0x04};
  put_move_header(out, settings);
  out.push_back(append ? 0x01 : 0x00);
  for (const MatTarget& target : targets) put_target(out, target);
  return out;
}

Bytes encode_protocol_version_request() { return {0x01, 0x00}; }

Bytes encode_id_notification_rate(uint8_t interval_10ms, IdNotifyCondition condition) {
  return {0x18, 0x00, interval_10ms, static_cast<uint8_t>(condition)};
}

Bytes encode_id_missed_sensitivity(uint8_t sensitivity_10ms) { return {0x19, 0x00, sensitivity_10ms}; }

Bytes encode_speed_information(bool enabled) { return {0x1C, 0x00, static_cast<uint8_t>(enabled ? 1 : 0)}; }

Bytes encode_connection_interval(uint16_t min_interval, uint16_t max_interval) {
  Bytes out{0x30, 0x00};
  put_u16(out, min_interval);
  put_u16(out, max_interval);
  return out;
}

Bytes encode_light_on(uint8_t duration_10ms, uint8_t red, uint8_t green, uint8_t blue) {
  return {0x03, duration_10ms, 0x01, 0x01, red, green, blue};
}

Bytes encode_light_off() { return {0x01}; }

Bytes encode_beep(uint8_t note, uint8_t duration_10ms, uint8_t volume, uint8_t repeat) {
  if (note > 128) throw std::invalid_argument("toio note must be a MIDI note 0-127 or 128 (rest)");
  return {0x03, repeat, 0x01, duration_10ms, note, volume};
}

Bytes encode_sound_stop() { return {0x01}; }

const char* describe(MotorResult result) {
  switch (result) {
    case MotorResult::kSuccess: return "success";
    case MotorResult::kTimeout: return "timeout";
    case MotorResult::kIdMissed: return "toio ID missed (cube off the mat)";
    case MotorResult::kBadParameters: return "bad parameter combination";
    case MotorResult::kInvalidState: return "invalid state";
    case MotorResult::kPreempted: return "preempted by another write";
    case MotorResult::kNotSupported: return "not supported";
    case MotorResult::kCannotAppend: return "cannot append";
  }
  return "unknown";
}

Decoded<IdReading> decode_id(std::span<const uint8_t> bytes) {
  if (bytes.empty()) return fail<IdReading>("ID notification: empty");
  switch (bytes[0]) {
    case 0x01: {
      if (bytes.size() != 13) return fail<IdReading>(length_error("Position ID", 13, bytes.size()));
      PositionId p{u16_at(bytes, 1), u16_at(bytes, 3), u16_at(bytes, 5),
                   u16_at(bytes, 7), u16_at(bytes, 9), u16_at(bytes, 11)};
      return {IdReading{p}, {}};
    }
    case 0x02: {
      if (bytes.size() != 7) return fail<IdReading>(length_error("Standard ID", 7, bytes.size()));
      return {IdReading{StandardId{u32_at(bytes, 1), u16_at(bytes, 5)}}, {}};
    }
    case 0x03:
      if (bytes.size() != 1) return fail<IdReading>(length_error("Position ID missed", 1, bytes.size()));
      return {IdReading{PositionIdMissed{}}, {}};
    case 0x04:
      if (bytes.size() != 1) return fail<IdReading>(length_error("Standard ID missed", 1, bytes.size()));
      return {IdReading{StandardIdMissed{}}, {}};
    default: return fail<IdReading>("ID notification: unknown type 0x" + to_hex(bytes.first(1)));
  }
}

Decoded<MotorNotification> decode_motor(std::span<const uint8_t> bytes) {
  if (bytes.empty()) return fail<MotorNotification>("motor notification: empty");
  switch (bytes[0]) {
    case 0x83:
    case 0x84: {
      if (bytes.size() != 3) return fail<MotorNotification>(length_error("motor response", 3, bytes.size()));
      if (bytes[2] > static_cast<uint8_t>(MotorResult::kCannotAppend)) {
        return fail<MotorNotification>("motor response: unknown result code " + std::to_string(bytes[2]));
      }
      return {MotorNotification{MotorResponse{bytes[0] == 0x84, bytes[1], static_cast<MotorResult>(bytes[2])}}, {}};
    }
    case 0xE0:
      if (bytes.size() != 3) return fail<MotorNotification>(length_error("motor speed", 3, bytes.size()));
      return {MotorNotification{MotorSpeed{bytes[1], bytes[2]}}, {}};
    default: return fail<MotorNotification>("motor notification: unknown type 0x" + to_hex(bytes.first(1)));
  }
}

Decoded<ConfigurationReply> decode_configuration(std::span<const uint8_t> bytes) {
  if (bytes.empty()) return fail<ConfigurationReply>("configuration reply: empty");
  ConfigurationReply reply;
  reply.type = bytes[0];
  switch (bytes[0]) {
    case 0x81:
      if (bytes.size() < 3) return fail<ConfigurationReply>("protocol version reply: too short");
      reply.code = bytes[1];
      for (size_t i = 2; i < bytes.size(); ++i) {
        if (bytes[i] < 0x20 || bytes[i] > 0x7E) return fail<ConfigurationReply>("protocol version reply: not ASCII");
        reply.version.push_back(static_cast<char>(bytes[i]));
      }
      return {reply, {}};
    case 0x98:
    case 0x99:
    case 0x9C:
    case 0xB0:
      if (bytes.size() < 3) return fail<ConfigurationReply>(length_error("configuration reply", 3, bytes.size()));
      reply.code = bytes[2];
      return {reply, {}};
    default: return fail<ConfigurationReply>("configuration reply: unknown type 0x" + to_hex(bytes.first(1)));
  }
}

Decoded<int> decode_battery(std::span<const uint8_t> bytes) {
  if (bytes.size() != 1) return fail<int>(length_error("battery", 1, bytes.size()));
  if (bytes[0] > 100) return fail<int>("battery: " + std::to_string(bytes[0]) + " percent is out of range");
  return {bytes[0], {}};
}

Decoded<ButtonState> decode_button(std::span<const uint8_t> bytes) {
  if (bytes.size() != 2) return fail<ButtonState>(length_error("button", 2, bytes.size()));
  if (bytes[0] != 0x01) return fail<ButtonState>("button: unknown button id " + std::to_string(bytes[0]));
  if (bytes[1] != 0x00 && bytes[1] != 0x80) return fail<ButtonState>("button: unknown state " + to_hex(bytes.subspan(1)));
  return {ButtonState{bytes[0], bytes[1] == 0x80}, {}};
}

std::string to_hex(std::span<const uint8_t> bytes) {
  std::string out;
  char two[4];
  for (size_t i = 0; i < bytes.size(); ++i) {
    std::snprintf(two, sizeof two, "%02x", bytes[i]);
    if (i) out.push_back(' ');
    out += two;
  }
  return out;
}

}  // namespace robot_agent::toio
