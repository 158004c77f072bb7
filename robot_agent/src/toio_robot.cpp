#include "robot_agent/toio_robot.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <numbers>

#include "robot_agent/bluez_client.hpp"

namespace robot_agent {

namespace {

std::chrono::milliseconds millis(double seconds) {
  return std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000));
}

// The spec's "target reached": within 15 mat units of it.
constexpr double kReachedDistance = 15;
// A cube within this of a heading faces it: more than the spec's 4 degrees of "reached", so that a
// cube nudged a little is not turned again, far less than the 45 degrees that make another heading.
constexpr double kFacingToleranceDeg = 10;

std::string cell_text(Cell cell) { return "(" + std::to_string(cell.x) + "," + std::to_string(cell.y) + ")"; }

}  // namespace

ToioRobot::ToioRobot(ToioSettings settings, MatCalibration calibration)
    : settings_(std::move(settings)), calibration_(std::move(calibration)), fault_since_(Clock::now()) {
  thread_ = std::thread([this] { ble_thread(); });
}

ToioRobot::~ToioRobot() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    if (client_) client_->wake();
  }
  stop_requested_.notify_all();
  thread_.join();
}

// ---- Agent side -------------------------------------------------------------------------------

bool ToioRobot::start_move(Cell target, int target_heading) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!fault_.empty() || !have_cell_ || move_) return false;
  const bool turn = target == cell_ && target_heading >= 0 && !facing(target_heading);
  if (target == cell_ && !turn) {  // a wait: nothing to drive
    arrived_ms_ = wall_clock_ms();
    return true;
  }
  if (target.x < 0 || target.y < 0 || target.x >= calibration_.grid_width() || target.y >= calibration_.grid_height()) {
    spdlog::warn("toio {}: target {} is outside the {}x{} grid of mat {}", settings_.cube, cell_text(target),
                 calibration_.grid_width(), calibration_.grid_height(), calibration_.mat().name);
    return false;
  }
  move_ = Move{target, target_heading, next_control_id_++, Clock::now(), false};
  wake_requested_ = true;
  if (client_) client_->wake();
  return true;
}

BackendReport ToioRobot::poll() {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (fault_sticky_ && !move_ && link_open() && lookup_.status == CellLookup::Status::kOnCell &&
      Clock::now() - fault_since_ >= millis(settings_.fault_hold_s)) {
    spdlog::info("toio {}: fault cleared, on cell {}", settings_.cube, cell_text(lookup_.cell));
    fault_.clear();
    fault_sticky_ = false;
    stand_on(lookup_.cell);
  }
  BackendReport report;
  report.cell = cell_;
  report.pose_x = lookup_.grid.x();
  report.pose_y = lookup_.grid.y();
  if (position_) {
    // The cube's angle is clockwise from the mat's +x axis; report it relative to the grid's x axis.
    double heading = position_->angle - calibration_.grid_heading_deg();
    report.pose_theta = std::remainder(heading, 360.0) * std::numbers::pi / 180.0;
    report.heading = calibration_.nearest_heading(position_->angle);
  }
  report.moving = move_.has_value();
  report.fault = !fault_.empty() || !have_cell_;
  report.battery_percent = battery_percent_;
  report.arrived_ms = arrived_ms_;
  return report;
}

std::optional<std::chrono::steady_clock::duration> ToioRobot::time_to_arrival() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!move_) return std::nullopt;
  const auto expected = move_->started + millis(settings_.expected_move_s);
  return std::max<Clock::duration>(expected - Clock::now(), std::chrono::milliseconds(20));
}

std::string ToioRobot::fault_reason() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return fault_;
}

bool ToioRobot::connected() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return link_open();
}

std::optional<toio::PositionId> ToioRobot::mat_position() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return position_;
}

void ToioRobot::identify() {
  const std::lock_guard<std::mutex> lock(mutex_);
  identify_requested_ = true;
  if (client_) client_->wake();
}

// ---- Shared helpers (mutex_ held) -------------------------------------------------------------

void ToioRobot::set_fault(const std::string& reason, bool sticky) {
  if (sticky) {
    if (move_ && !move_->recovery) interrupted_ = InterruptedMove{cell_, move_->target};
    move_.reset();  // a failed move is over
    fault_sticky_ = true;
    fault_since_ = Clock::now();
  } else if (fault_sticky_) {
    return;  // keep the reason that needs to be seen
  }
  if (fault_ != reason) spdlog::warn("toio {}: fault: {}", settings_.cube, reason);
  fault_ = reason;
}

bool ToioRobot::facing(int heading) const {
  if (!position_) return false;
  return std::abs(std::remainder(position_->angle - calibration_.heading_on_mat_deg(heading), 360.0)) <=
         kFacingToleranceDeg;
}

void ToioRobot::stand_on(Cell cell) {
  if (!have_cell_ || cell_ != cell) arrived_ms_ = wall_clock_ms();  // found (or put) there now
  cell_ = cell;
  have_cell_ = true;
}

void ToioRobot::start_recovery_if_needed() {
  if (!interrupted_ || move_ || !link_open() || !position_) return;
  const InterruptedMove interrupted = *interrupted_;
  if (lookup_.status == CellLookup::Status::kOnCell) {
    interrupted_.reset();  // it stopped on a cell (or was put on one): nothing to do
    return;
  }
  if (lookup_.status != CellLookup::Status::kBetweenCells ||
      (lookup_.cell != interrupted.from && lookup_.cell != interrupted.to)) {
    return;  // somewhere else: a person has to put it on a cell
  }
  interrupted_.reset();
  spdlog::info("toio {}: stopped between {} and {}: driving onto {}", settings_.cube, cell_text(interrupted.from),
               cell_text(interrupted.to), cell_text(lookup_.cell));
  move_ = Move{lookup_.cell, -1, next_control_id_++, Clock::now(), false, true};
}

void ToioRobot::finish_move(Cell at) {
  cell_ = at;
  have_cell_ = true;
  move_.reset();
  arrived_ms_ = wall_clock_ms();
}

// ---- BLE thread -------------------------------------------------------------------------------

void ToioRobot::on_id(const toio::Bytes& bytes) {
  const toio::Decoded<toio::IdReading> decoded = toio::decode_id(bytes);
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!decoded) {
    spdlog::warn("toio {}: ignored ID notification [{}]: {}", settings_.cube, toio::to_hex(bytes), decoded.error);
    return;
  }
  if (const auto* p = std::get_if<toio::PositionId>(&*decoded.value)) {
    position_ = *p;
    lookup_ = calibration_.cell_at(Eigen::Vector2d(p->x, p->y));
    if (move_) {
      if (lookup_.cell == move_->target && lookup_.distance <= std::min(calibration_.tolerance(), kReachedDistance) &&
          (move_->heading < 0 || facing(move_->heading))) {
        finish_move(move_->target);
      }
      return;
    }
    if (lookup_.status == CellLookup::Status::kOnCell) {
      if (!fault_sticky_ && link_open()) {
        if (!fault_.empty()) spdlog::info("toio {}: ready on cell {}", settings_.cube, cell_text(lookup_.cell));
        fault_.clear();
        stand_on(lookup_.cell);
      }
      return;
    }
    set_fault("cube is " + std::string(describe(lookup_.status)) + " at mat (" + std::to_string(p->x) + ", " +
                  std::to_string(p->y) + "), " + std::to_string(static_cast<int>(lookup_.distance)) +
                  " units from the centre of cell " + cell_text(lookup_.cell),
              false);
    return;
  }
  position_.reset();
  lookup_ = CellLookup{};
  if (std::holds_alternative<toio::StandardId>(*decoded.value)) {
    set_fault("cube is on a Standard ID card, not on the mat", move_.has_value());
  } else {
    set_fault("cube lost the mat (ID missed: lifted or off the mat)", move_.has_value());
  }
}

void ToioRobot::on_motor(const toio::Bytes& bytes) {
  const toio::Decoded<toio::MotorNotification> decoded = toio::decode_motor(bytes);
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!decoded) {
    spdlog::warn("toio {}: ignored motor notification [{}]: {}", settings_.cube, toio::to_hex(bytes), decoded.error);
    return;
  }
  const auto* response = std::get_if<toio::MotorResponse>(&*decoded.value);
  if (!response || !move_ || response->control_id != move_->control_id) return;  // speed info, or an older move
  if (response->result == toio::MotorResult::kSuccess) {
    finish_move(move_->target);
  } else {
    set_fault("move to " + cell_text(move_->target) + " failed: " + toio::describe(response->result), true);
  }
}

void ToioRobot::on_battery(const toio::Bytes& bytes) {
  const toio::Decoded<int> decoded = toio::decode_battery(bytes);
  const std::lock_guard<std::mutex> lock(mutex_);
  if (decoded) battery_percent_ = *decoded.value;
}

// The D-Bus objects of one connected cube, and what its notifications told us.
struct ToioRobot::CubeLink {
  std::string device, id, motor, configuration;
  std::optional<std::string> battery, light, sound;
  std::string protocol_version;
  bool lost = false;  // BlueZ reported the device disconnected
};

void ToioRobot::open_link(BluezClient& client, CubeLink& link) {
  const std::string& cube = settings_.cube;
  const auto device = client.find_device(cube, millis(settings_.discovery_timeout_s));
  if (!device) throw BluezError("cube " + cube + " not found by adapter " + settings_.adapter);
  link.device = *device;
  client.forget(link.device);
  client.on_disconnected(link.device, [&link] { link.lost = true; });
  spdlog::info("toio {}: connecting to {}", cube, link.device);
  client.connect(link.device, millis(settings_.connect_timeout_s));

  const auto found = client.characteristics(link.device, toio::kServiceUuid);
  auto required = [&](const char* uuid, const char* what) {
    const auto it = found.find(uuid);
    if (it == found.end()) throw BluezError("cube " + cube + " has no " + what + " characteristic " + uuid);
    return it->second;
  };
  auto optional = [&](const char* uuid) {
    const auto it = found.find(uuid);
    return it == found.end() ? std::nullopt : std::optional<std::string>(it->second);
  };
  link.id = required(toio::kIdUuid, "ID");
  link.motor = required(toio::kMotorUuid, "motor");
  link.configuration = required(toio::kConfigurationUuid, "configuration");
  link.battery = optional(toio::kBatteryUuid);
  link.light = optional(toio::kLightUuid);
  link.sound = optional(toio::kSoundUuid);

  client.start_notify(link.configuration, [&link, &cube](const toio::Bytes& bytes) {
    const auto reply = toio::decode_configuration(bytes);
    if (!reply) {
      spdlog::warn("toio {}: ignored configuration reply [{}]: {}", cube, toio::to_hex(bytes), reply.error);
    } else if (reply.value->type == 0x81) {
      link.protocol_version = reply.value->version;
    } else if (reply.value->code != 0) {
      spdlog::warn("toio {}: configuration 0x{:02x} refused with code {}", cube, reply.value->type, reply.value->code);
    }
  });
  client.start_notify(link.id, [this](const toio::Bytes& bytes) { on_id(bytes); });
  client.start_notify(link.motor, [this](const toio::Bytes& bytes) { on_motor(bytes); });
  if (link.battery) {
    client.start_notify(*link.battery, [this](const toio::Bytes& bytes) { on_battery(bytes); });
    on_battery(client.read(*link.battery));
  }
  client.write(link.configuration, toio::encode_protocol_version_request(), true);
  client.write(link.configuration,
               toio::encode_id_notification_rate(settings_.id_interval_10ms, toio::IdNotifyCondition::kOnChange), true);
  const auto version_deadline = Clock::now() + std::chrono::seconds(2);
  while (link.protocol_version.empty() && Clock::now() < version_deadline && !link.lost) {
    client.process(std::chrono::milliseconds(20));
  }
  if (settings_.identify_on_connect) flash_and_beep(client, link);
  spdlog::info("toio {}: connected (protocol {}), battery {}%", cube,
               link.protocol_version.empty() ? "unknown" : link.protocol_version, battery_percent_);
}

void ToioRobot::flash_and_beep(BluezClient& client, const CubeLink& link) {
  if (link.light) client.write(*link.light, toio::encode_light_on(100, 0, 255, 0), false);
  if (link.sound) client.write(*link.sound, toio::encode_beep(72, 15, 255, 1), false);
}

void ToioRobot::write_move(BluezClient& client, const CubeLink& link, const Move& move) {
  const Eigen::Vector2d centre = calibration_.cell_centre(move.target);
  toio::MoveSettings settings;
  settings.control_id = move.control_id;
  settings.timeout_s = settings_.move_timeout_s;
  settings.move_type = toio::MoveType::kRotateAfterMoving;
  settings.max_speed = settings_.max_speed;
  settings.speed_change = toio::SpeedChange::kConstant;
  toio::MatTarget target{static_cast<uint16_t>(std::lround(centre.x())),
                         static_cast<uint16_t>(std::lround(centre.y())), 0, toio::RotationType::kNoRotation};
  if (move.heading >= 0) {
    target.angle = static_cast<uint16_t>(std::lround(calibration_.heading_on_mat_deg(move.heading)) % 360);
    target.rotation = toio::RotationType::kAbsoluteShortest;
  }
  client.write(link.motor, toio::encode_move_to_target(settings, target), false);
}

void ToioRobot::run_link(BluezClient& client, const CubeLink& link) {
  for (;;) {
    client.process(std::chrono::milliseconds(100));
    std::optional<Move> to_write;
    bool identify_now = false;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
      if (link.lost) {
        set_fault("BLE link to the cube lost", true);
        return;
      }
      start_recovery_if_needed();
      if (move_ && !move_->written) {
        move_->written = true;
        to_write = move_;
      } else if (move_ && Clock::now() - move_->started > std::chrono::seconds(settings_.move_timeout_s + 2)) {
        set_fault("move to " + cell_text(move_->target) + " got no answer from the cube", true);
      }
      identify_now = identify_requested_;
      identify_requested_ = false;
    }
    if (to_write) write_move(client, link, *to_write);
    if (identify_now) flash_and_beep(client, link);
  }
}

void ToioRobot::serve_connection(BluezClient& client) {
  CubeLink link;
  auto leave = [&] {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      client_ = nullptr;
    }
    if (!link.device.empty()) client.forget(link.device);  // drops the callbacks that refer to `link`
  };
  try {
    open_link(client, link);
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      client_ = &client;
      if (!fault_sticky_) fault_ = "no position from the cube yet";
    }
    on_id(client.read(link.id));  // where the cube stands now, without waiting for it to move
  } catch (...) {
    leave();
    throw;
  }
  try {
    run_link(client, link);
  } catch (const BluezError& e) {
    // A call failed on an open link (the cube went away between BlueZ's signal and our write):
    // the same as a lost link, and a move under way has failed.
    const std::lock_guard<std::mutex> lock(mutex_);
    set_fault(std::string("BLE link to the cube lost (") + e.what() + ")", true);
  }
  bool stopping = false;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopping = stop_;
  }
  if (stopping) {
    try {
      client.write(link.motor, toio::encode_motor_control(0, 0), false);
      client.disconnect(link.device);
    } catch (const BluezError&) {
      // Leaving anyway.
    }
  }
  leave();
}

void ToioRobot::ble_thread() {
  double backoff = settings_.reconnect_backoff_min_s;
  std::unique_ptr<BluezClient> client;
  for (;;) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
    }
    const auto attempt_started = Clock::now();
    std::string failure;
    try {
      if (!client) client = std::make_unique<BluezClient>(settings_.adapter);
      serve_connection(*client);
    } catch (const std::exception& e) {
      const std::lock_guard<std::mutex> lock(mutex_);
      failure = e.what();
      set_fault("BLE: " + failure, false);
      client.reset();  // a fresh bus connection next time, in case this one is what failed
    }
    // A connection that lasted a while earns a quick retry; repeated failures back off.
    if (Clock::now() - attempt_started > std::chrono::seconds(10)) backoff = settings_.reconnect_backoff_min_s;
    std::unique_lock<std::mutex> lock(mutex_);
    if (stop_) return;
    spdlog::info("toio {}: {}; reconnecting in {:.1f} s", settings_.cube,
                 failure.empty() ? "connection ended" : failure, backoff);
    stop_requested_.wait_for(lock, millis(backoff), [this] { return stop_; });
    backoff = std::min(backoff * 2, settings_.reconnect_backoff_max_s);
  }
}

}  // namespace robot_agent
