// The toio codec against the spec's byte vectors (../shared/docs/PLATFORM-NOTES.md, toio spec
// v2.4.0), every motor result code, and malformed notifications.
#include "robot_agent/toio_protocol.hpp"

#include <gtest/gtest.h>

#include <random>

namespace robot_agent::toio {
namespace {

Bytes hex(const std::string& text) {
  Bytes out;
  for (size_t i = 0; i + 1 < text.size() + 1; i += 3) out.push_back(static_cast<uint8_t>(std::stoi(text.substr(i, 2), nullptr, 16)));
  return out;
}

TEST(ToioProtocol, DecodesThePositionIdVector) {
  const auto decoded = decode_id(hex("01 c5 02 7f 01 32 01 bc 02 82 01 32 01"));
  ASSERT_TRUE(decoded) << decoded.error;
  const auto& p = std::get<PositionId>(*decoded.value);
  EXPECT_EQ(p.x, 709);
  EXPECT_EQ(p.y, 383);
  EXPECT_EQ(p.angle, 306);
  EXPECT_EQ(p.sensor_x, 700);
  EXPECT_EQ(p.sensor_y, 386);
  EXPECT_EQ(p.sensor_angle, 306);
}

TEST(ToioProtocol, DecodesTheStandardIdVectorAndMissedNotifications) {
  const auto standard = decode_id(hex("02 00 00 38 00 15 00"));
  ASSERT_TRUE(standard) << standard.error;
  EXPECT_EQ(std::get<StandardId>(*standard.value).value, 3670016u);
  EXPECT_EQ(std::get<StandardId>(*standard.value).angle, 21);
  EXPECT_TRUE(std::holds_alternative<PositionIdMissed>(*decode_id(hex("03")).value));
  EXPECT_TRUE(std::holds_alternative<StandardIdMissed>(*decode_id(hex("04")).value));
}

TEST(ToioProtocol, EncodesMotorControlVectors) {
  EXPECT_EQ(encode_motor_control_timed(100, -20, 10), hex("02 01 01 64 02 02 14 0a"));
  EXPECT_EQ(encode_motor_control_timed(100, -20, 0), hex("02 01 01 64 02 02 14 00"));
  EXPECT_EQ(encode_motor_control(100, -20), hex("01 01 01 64 02 02 14"));
  EXPECT_EQ(encode_motor_control(0, 0), hex("01 01 01 00 02 01 00"));
  EXPECT_THROW(encode_motor_control(256, 0), std::invalid_argument);
}

TEST(ToioProtocol, EncodesMoveToTargetVector) {
  MoveSettings settings{0x00, 5, MoveType::kRotateWhileMoving, 0x50, SpeedChange::kConstant};
  EXPECT_EQ(encode_move_to_target(settings, {700, 386, 90, RotationType::kAbsoluteShortest}),
            hex("03 00 05 00 50 00 00 bc 02 82 01 5a 00"));
  // No rotation is theta 00 a0; x or y 0xFFFF keeps the current value.
  settings.move_type = MoveType::kRotateAfterMoving;
  settings.control_id = 7;
  EXPECT_EQ(encode_move_to_target(settings, {kKeepCoordinate, 100, 0, RotationType::kNoRotation}),
            hex("03 07 05 02 50 00 00 ff ff 64 00 00 a0"));
  settings.max_speed = 9;
  EXPECT_THROW(encode_move_to_target(settings, {}), std::invalid_argument);
}

TEST(ToioProtocol, EncodesMultipleTargetsVector) {
  const MoveSettings settings{0x00, 5, MoveType::kRotateWhileMoving, 0x50, SpeedChange::kConstant};
  const std::vector<MatTarget> targets = {{100, 100, 0, RotationType::kAbsoluteShortest},
                                          {200, 100, 90, RotationType::kAbsoluteShortest},
                                          {200, 200, 180, RotationType::kAbsoluteShortest}};
  EXPECT_EQ(encode_move_to_targets(settings, true, targets),
            hex("04 00 05 00 50 00 00 01 64 00 64 00 00 00 c8 00 64 00 5a 00 c8 00 c8 00 b4 00"));
  EXPECT_THROW(encode_move_to_targets(settings, false, {}), std::invalid_argument);
  EXPECT_THROW(encode_move_to_targets(settings, false, std::vector<MatTarget>(30)), std::invalid_argument);
  EXPECT_EQ(encode_move_to_targets(settings, false, std::vector<MatTarget>(29)).size(), 8u + 29 * 6);
}

TEST(ToioProtocol, EncodesConfigurationLightAndSound) {
  EXPECT_EQ(encode_protocol_version_request(), hex("01 00"));
  EXPECT_EQ(encode_id_notification_rate(5, IdNotifyCondition::kOnChange), hex("18 00 05 01"));
  EXPECT_EQ(encode_id_notification_rate(0, IdNotifyCondition::kDefault), hex("18 00 00 ff"));
  EXPECT_EQ(encode_id_missed_sensitivity(10), hex("19 00 0a"));
  EXPECT_EQ(encode_speed_information(true), hex("1c 00 01"));
  EXPECT_EQ(encode_connection_interval(0x0006, 0x0c80), hex("30 00 06 00 80 0c"));
  EXPECT_EQ(encode_light_on(100, 255, 0, 0), hex("03 64 01 01 ff 00 00"));
  EXPECT_EQ(encode_light_off(), hex("01"));
  EXPECT_EQ(encode_beep(60, 30, 255, 1), hex("03 01 01 1e 3c ff"));
  EXPECT_THROW(encode_beep(129, 1, 1, 1), std::invalid_argument);
}

TEST(ToioProtocol, DecodesEveryMotorResultCode) {
  for (uint8_t code = 0; code <= 7; ++code) {
    for (uint8_t type : {0x83, 0x84}) {
      const auto decoded = decode_motor(Bytes{type, 42, code});
      ASSERT_TRUE(decoded) << decoded.error;
      const auto& response = std::get<MotorResponse>(*decoded.value);
      EXPECT_EQ(response.multiple_targets, type == 0x84);
      EXPECT_EQ(response.control_id, 42);
      EXPECT_EQ(static_cast<uint8_t>(response.result), code);
      EXPECT_STRNE(describe(response.result), "unknown");
    }
  }
  EXPECT_EQ(describe(MotorResult::kIdMissed), std::string("toio ID missed (cube off the mat)"));
  EXPECT_FALSE(decode_motor(hex("83 01 08")));  // no such code
  EXPECT_FALSE(decode_motor(hex("83 01")));
  const auto speed = decode_motor(hex("e0 32 33"));
  ASSERT_TRUE(speed);
  EXPECT_EQ(std::get<MotorSpeed>(*speed.value).right, 0x33);
}

TEST(ToioProtocol, DecodesConfigurationBatteryAndButton) {
  const auto version = decode_configuration(hex("81 00 32 2e 34 2e 30"));
  ASSERT_TRUE(version) << version.error;
  EXPECT_EQ(version.value->version, "2.4.0");
  const auto rate = decode_configuration(hex("98 00 00"));
  ASSERT_TRUE(rate);
  EXPECT_EQ(rate.value->type, 0x98);
  EXPECT_EQ(rate.value->code, 0);
  EXPECT_EQ(decode_configuration(hex("99 00 01")).value->code, 1);
  EXPECT_FALSE(decode_configuration(hex("81 00 ff")));  // not ASCII
  EXPECT_FALSE(decode_configuration(hex("98 00")));
  EXPECT_EQ(*decode_battery(hex("5a")).value, 90);
  EXPECT_FALSE(decode_battery(hex("65")));  // 101 percent
  EXPECT_FALSE(decode_battery(hex("5a 00")));
  EXPECT_TRUE(decode_button(hex("01 80")).value->pressed);
  EXPECT_FALSE(decode_button(hex("01 00")).value->pressed);
  EXPECT_FALSE(decode_button(hex("02 80")));
}

TEST(ToioProtocol, RejectsMalformedNotificationsWithAReason) {
  const std::vector<Bytes> bad_ids = {{}, hex("01 c5 02 7f 01 32 01 bc 02 82 01 32"), hex("01 c5 02 7f 01 32 01 bc 02 82 01 32 01 00"),
                                      hex("02 00 00 38 00 15"), hex("03 00"), hex("05"), hex("ff 01 02")};
  for (const Bytes& bytes : bad_ids) {
    const auto decoded = decode_id(bytes);
    EXPECT_FALSE(decoded) << to_hex(bytes);
    EXPECT_FALSE(decoded.error.empty()) << to_hex(bytes);
  }
  EXPECT_NE(decode_id(hex("01 c5")).error.find("expected 13 bytes, got 2"), std::string::npos);
  EXPECT_NE(decode_id(hex("07")).error.find("unknown type 0x07"), std::string::npos);
  EXPECT_FALSE(decode_motor({}));
  EXPECT_FALSE(decode_motor(hex("85 00 00")));
  EXPECT_FALSE(decode_configuration({}));
  EXPECT_FALSE(decode_configuration(hex("42 00 00")));
}

// Random bytes through every decoder: nothing is read out of bounds (run under ASan by
// scripts/fuzz-toio) and whatever is accepted has exactly the spec's length.
TEST(ToioProtocol, RandomBytesAreDecodedOrRejectedNeverMisread) {
  std::mt19937 rng(12345);
  for (int round = 0; round < 200000; ++round) {
    Bytes bytes(std::uniform_int_distribution<int>(0, 16)(rng));
    for (uint8_t& b : bytes) b = static_cast<uint8_t>(rng());
    if (!bytes.empty() && round % 2) bytes[0] = static_cast<uint8_t>(std::uniform_int_distribution<int>(1, 4)(rng));
    if (const auto id = decode_id(bytes)) {
      const size_t expected = std::visit(
          [](const auto& v) -> size_t {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, PositionId>) return 13;
            else if constexpr (std::is_same_v<T, StandardId>) return 7;
            else return 1;
          },
          *id.value);
      ASSERT_EQ(bytes.size(), expected) << to_hex(bytes);
    } else {
      ASSERT_FALSE(id.error.empty());
    }
    if (const auto motor = decode_motor(bytes)) {
      ASSERT_EQ(bytes.size(), 3u) << to_hex(bytes);
    }
    if (const auto battery = decode_battery(bytes)) {
      ASSERT_LE(*battery.value, 100);
    }
    if (const auto reply = decode_configuration(bytes)) {
      ASSERT_GE(bytes.size(), 3u);
    }
    (void)decode_button(bytes);
  }
}

TEST(ToioProtocol, RecognisesCubeNames) {
  EXPECT_TRUE(is_cube_name("toio-a1B"));
  EXPECT_TRUE(is_cube_name("toio Core Cube-k2P"));
  EXPECT_FALSE(is_cube_name("Toio-123"));
  EXPECT_FALSE(is_cube_name("my-phone"));
}

}  // namespace
}  // namespace robot_agent::toio
