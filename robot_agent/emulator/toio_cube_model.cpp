#include "toio_cube_model.hpp"

#include <cmath>
#include <numbers>

namespace toio_emulator {

namespace {

constexpr double kTurnRateDegPerS = 360;
constexpr double kReachedDistance = 15;  // the spec's "reached": within 15 units

void put_u16(Bytes& out, double value) {
  const auto v = static_cast<uint16_t>(std::lround(std::max(0.0, value)));
  out.push_back(static_cast<uint8_t>(v & 0xFF));
  out.push_back(static_cast<uint8_t>(v >> 8));
}

uint16_t u16(const Bytes& b, size_t at) { return static_cast<uint16_t>(b[at] | (b[at + 1] << 8)); }

double normalized(double angle) {
  angle = std::fmod(angle, 360.0);
  return angle < 0 ? angle + 360.0 : angle;
}

}  // namespace

ToioCubeModel::ToioCubeModel(CubePose pose, double speed_per_unit) : pose_(pose), speed_per_unit_(speed_per_unit) {}

Bytes ToioCubeModel::position_bytes() const {
  if (!on_mat_) return {0x03};
  Bytes out{0x01};
  put_u16(out, pose_.x);
  put_u16(out, pose_.y);
  put_u16(out, normalized(pose_.angle_deg));
  // The sensor sits a little ahead of the centre; reported as the spec's vector does.
  const double r = pose_.angle_deg * std::numbers::pi / 180;
  put_u16(out, pose_.x + 9 * std::cos(r));
  put_u16(out, pose_.y + 9 * std::sin(r));
  put_u16(out, normalized(pose_.angle_deg));
  return out;
}

Notification ToioCubeModel::motor_response(const Move& move, uint8_t code) const {
  return {Characteristic::kMotor, {static_cast<uint8_t>(move.multiple ? 0x84 : 0x83), move.control_id, code}};
}

std::vector<Notification> ToioCubeModel::write(Characteristic characteristic, const Bytes& value) {
  std::vector<Notification> out;
  if (value.empty()) return out;
  switch (characteristic) {
    case Characteristic::kMotor: {
      if (value[0] == 0x03 && value.size() == 13) {
        if (move_) out.push_back(motor_response(*move_, 5));  // preempted
        Move move;
        move.control_id = value[1];
        move.time_left = value[2] == 0 ? 10 : value[2];
        move.max_speed = value[4];
        if (value[4] < 10) {
          out.push_back(motor_response(move, 3));  // bad parameters
          move_.reset();
          return out;
        }
        const uint16_t x = u16(value, 7), y = u16(value, 9);
        move.target_x = x == 0xFFFF ? pose_.x : x;
        move.target_y = y == 0xFFFF ? pose_.y : y;
        const uint16_t theta = u16(value, 11);
        if ((theta >> 13) <= 2) move.target_angle = normalized(theta & 0x1FFF);  // absolute: shortest, +, -
        if (!on_mat_) {
          out.push_back(motor_response(move, 2));  // ID missed
          move_.reset();
          return out;
        }
        move_ = move;
      } else if (value[0] == 0x04 && value.size() >= 14) {
        // Multiple targets: the emulator drives to the last one (enough for the fleet, which
        // sends one target per move).
        if (move_) out.push_back(motor_response(*move_, 5));
        Move move;
        move.multiple = true;
        move.control_id = value[1];
        move.time_left = value[2] == 0 ? 10 : value[2];
        move.max_speed = std::max<uint8_t>(value[4], 10);
        const size_t last = 8 + ((value.size() - 8) / 6 - 1) * 6;
        move.target_x = u16(value, last);
        move.target_y = u16(value, last + 2);
        move_ = move;
      } else if ((value[0] == 0x01 && value.size() == 7) || (value[0] == 0x02 && value.size() == 8)) {
        // Direct wheel control: the emulator only honours "stop" (both speeds 0).
        if (move_) out.push_back(motor_response(*move_, 5));
        move_.reset();
      }
      return out;
    }
    case Characteristic::kConfiguration: {
      if (value.size() >= 2 && value[0] == 0x01) {
        out.push_back({Characteristic::kConfiguration, {0x81, 0x00, '2', '.', '4', '.', '0'}});
      } else if (value.size() >= 4 && value[0] == 0x18) {
        id_interval_s_ = std::max(0.01, value[2] * 0.01);
        id_on_change_only_ = value[3] != 0x00;
        out.push_back({Characteristic::kConfiguration, {0x98, 0x00, 0x00}});
      } else if (value.size() >= 3 && value[0] == 0x19) {
        out.push_back({Characteristic::kConfiguration, {0x99, 0x00, 0x00}});
      } else if (value.size() >= 3 && value[0] == 0x1C) {
        out.push_back({Characteristic::kConfiguration, {0x9C, 0x00, 0x00}});
      } else if (value.size() >= 6 && value[0] == 0x30) {
        out.push_back({Characteristic::kConfiguration, {0xB0, 0x00, 0x00}});
      }
      return out;
    }
    case Characteristic::kLight: ++light_writes_; return out;
    case Characteristic::kSound: ++sound_writes_; return out;
    default: return out;
  }
}

Bytes ToioCubeModel::read(Characteristic characteristic) const {
  switch (characteristic) {
    case Characteristic::kId: return position_bytes();
    case Characteristic::kBattery: return {90};
    case Characteristic::kButton: return {0x01, 0x00};
    case Characteristic::kMotor: return {0x83, 0x00, 0x00};
    default: return {};
  }
}

std::vector<Notification> ToioCubeModel::advance(double dt) {
  std::vector<Notification> out;
  if (move_ && !on_mat_) {
    out.push_back(motor_response(*move_, 2));  // ID missed: the cube was lifted mid-move
    move_.reset();
  }
  if (move_ && !paused_) {
    Move& move = *move_;
    const double dx = move.target_x - pose_.x, dy = move.target_y - pose_.y;
    const double distance = std::hypot(dx, dy);
    double budget = dt;
    if (distance > 0.5 && !blocked_) {  // turn in place towards the target, then drive straight
      const double heading = std::atan2(dy, dx) * 180 / std::numbers::pi;
      const double turn = std::remainder(heading - pose_.angle_deg, 360.0);
      const double turn_step = std::min(std::abs(turn), kTurnRateDegPerS * budget);
      pose_.angle_deg = normalized(pose_.angle_deg + std::copysign(turn_step, turn));
      budget -= turn_step / kTurnRateDegPerS;
      if (std::abs(turn) - turn_step < 1e-6 && budget > 0) {
        const double step = std::min(distance, speed_per_unit_ * move.max_speed * budget);
        pose_.x += dx / distance * step;
        pose_.y += dy / distance * step;
        budget -= step / (speed_per_unit_ * move.max_speed);
      }
    }
    move.time_left -= dt;
    if (std::hypot(move.target_x - pose_.x, move.target_y - pose_.y) < 1.0) {
      pose_.x = move.target_x;
      pose_.y = move.target_y;
      // At the target: the rotation after moving, with what is left of this tick.
      const double turn = move.target_angle ? std::remainder(*move.target_angle - pose_.angle_deg, 360.0) : 0.0;
      if (!blocked_ && std::abs(turn) > 1e-6) {
        const double turn_step = std::min(std::abs(turn), kTurnRateDegPerS * std::max(budget, 0.0));
        pose_.angle_deg = normalized(pose_.angle_deg + std::copysign(turn_step, turn));
      }
      if (std::abs(std::remainder(move.target_angle.value_or(pose_.angle_deg) - pose_.angle_deg, 360.0)) < 1e-6) {
        out.push_back(motor_response(move, 0));
        move_.reset();
      } else if (move.time_left <= 0) {
        out.push_back(motor_response(move, 1));
        move_.reset();
      }
    } else if (move.time_left <= 0) {
      const bool reached = std::hypot(move.target_x - pose_.x, move.target_y - pose_.y) <= kReachedDistance;
      out.push_back(motor_response(move, reached ? 0 : 1));
      move_.reset();
    }
  }
  since_id_notify_ += dt;
  if (!on_mat_) {
    if (!missed_notified_) out.push_back({Characteristic::kId, {0x03}});
    missed_notified_ = true;
  } else if (since_id_notify_ >= id_interval_s_) {
    const bool changed = !last_notified_ || std::abs(last_notified_->x - pose_.x) >= 1 ||
                         std::abs(last_notified_->y - pose_.y) >= 1 ||
                         std::abs(last_notified_->angle_deg - pose_.angle_deg) >= 1;
    if (changed || !id_on_change_only_) {
      out.push_back({Characteristic::kId, position_bytes()});
      last_notified_ = pose_;
      since_id_notify_ = 0;
    }
  }
  return out;
}

void ToioCubeModel::lift() {
  on_mat_ = false;
  missed_notified_ = false;
  last_notified_.reset();
}

void ToioCubeModel::place(CubePose pose) {
  pose_ = pose;
  on_mat_ = true;
  last_notified_.reset();
}

void ToioCubeModel::disconnected() {
  move_.reset();
  id_interval_s_ = 0.01;
  id_on_change_only_ = true;
  last_notified_.reset();
}

}  // namespace toio_emulator
