#include "fake_bluez.hpp"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <tuple>

#include "robot_agent/bluez_names.hpp"
#include "robot_agent/toio_protocol.hpp"

namespace toio_emulator {

namespace {

using robot_agent::bluez::kAdapter;
using robot_agent::bluez::kDevice;
using robot_agent::toio::kServiceUuid;
constexpr const char* kService = robot_agent::bluez::kGattService;
constexpr const char* kCharacteristic = robot_agent::bluez::kGattCharacteristic;
constexpr const char* kControl = "io.ctsfleet.ToioEmulator1";

struct CharacteristicInfo {
  Characteristic kind;
  const char* uuid;
  std::vector<std::string> flags;
};

const std::vector<CharacteristicInfo>& toio_characteristics() {
  static const std::vector<CharacteristicInfo> list = {
      {Characteristic::kId, robot_agent::toio::kIdUuid, {"read", "notify"}},
      {Characteristic::kMotor, robot_agent::toio::kMotorUuid, {"write-without-response", "read", "notify"}},
      {Characteristic::kLight, robot_agent::toio::kLightUuid, {"write", "read"}},
      {Characteristic::kSound, robot_agent::toio::kSoundUuid, {"write", "read"}},
      {Characteristic::kSensor, robot_agent::toio::kSensorUuid, {"write", "read", "notify"}},
      {Characteristic::kButton, robot_agent::toio::kButtonUuid, {"read", "notify"}},
      {Characteristic::kBattery, robot_agent::toio::kBatteryUuid, {"read", "notify"}},
      {Characteristic::kConfiguration, robot_agent::toio::kConfigurationUuid, {"write", "read", "notify"}},
  };
  return list;
}

sdbus::Error failed(const std::string& message) { return sdbus::Error("org.bluez.Error.Failed", message); }

}  // namespace

FakeBluez::FakeBluez(sdbus::IConnection& connection, const std::vector<CubeSpec>& cubes, const std::string& adapter,
                     double speed_per_unit)
    : connection_(connection), adapter_path_("/org/bluez/" + adapter), speed_per_unit_(speed_per_unit) {
  root_ = sdbus::createObject(connection_, "/");
  root_->addObjectManager();

  adapter_ = sdbus::createObject(connection_, adapter_path_);
  adapter_->registerMethod("StartDiscovery").onInterface(kAdapter).implementedAs([this] {
    discovering_ = true;
    adapter_->emitPropertiesChangedSignal(kAdapter, {"Discovering"});
    for (auto& cube : cubes_) make_present(*cube);
  });
  adapter_->registerMethod("StopDiscovery").onInterface(kAdapter).implementedAs([this] {
    if (!discovering_) throw sdbus::Error("org.bluez.Error.Failed", "No discovery started");
    discovering_ = false;
    adapter_->emitPropertiesChangedSignal(kAdapter, {"Discovering"});
  });
  adapter_->registerMethod("SetDiscoveryFilter")
      .onInterface(kAdapter)
      .implementedAs([](const std::map<std::string, sdbus::Variant>&) {});
  adapter_->registerProperty("Address").onInterface(kAdapter).withGetter([] { return std::string("00:AA:01:00:00:01"); });
  adapter_->registerProperty("Powered").onInterface(kAdapter).withGetter([] { return true; });
  adapter_->registerProperty("Discovering").onInterface(kAdapter).withGetter([this] { return discovering_; });
  adapter_->finishRegistration();

  int index = 0;
  for (const CubeSpec& spec : cubes) {
    auto cube = std::make_unique<Cube>(Cube{spec.name, "", "", ToioCubeModel(spec.pose, speed_per_unit_)});
    char address[18];
    std::snprintf(address, sizeof address, "E0:7C:00:00:%02X:%02X", (index >> 8) & 0xFF, index & 0xFF);
    cube->address = address;
    cube->path = adapter_path_ + "/dev_E0_7C_00_00_" + std::string(address).substr(12, 2) + "_" +
                 std::string(address).substr(15, 2);
    cubes_.push_back(std::move(cube));
    ++index;
  }

  control_ = sdbus::createObject(connection_, "/io/ctsfleet/emulator");
  control_->registerMethod("Lift").onInterface(kControl).implementedAs([this](const std::string& name) {
    spdlog::info("{}: lifted off the mat", name);
    cube_named(name).model.lift();
  });
  control_->registerMethod("Place")
      .onInterface(kControl)
      .implementedAs([this](const std::string& name, double x, double y, double angle) {
        spdlog::info("{}: placed at ({:.0f}, {:.0f}) angle {:.0f}", name, x, y, angle);
        cube_named(name).model.place({x, y, angle});
      });
  control_->registerMethod("DropConnection")
      .onInterface(kControl)
      .implementedAs([this](const std::string& name, double unreachable_s) {
        Cube& cube = cube_named(name);
        cube.unreachable_for_s = unreachable_s;
        drop_connection(cube, "dropped on request, unreachable for " + std::to_string(unreachable_s) + " s");
      });
  control_->registerMethod("Block")
      .onInterface(kControl)
      .implementedAs([this](const std::string& name, bool blocked) {
        spdlog::info("{}: {}", name, blocked ? "blocked (cannot move)" : "free to move");
        cube_named(name).model.set_blocked(blocked);
      });
  control_->registerMethod("Pose").onInterface(kControl).implementedAs([this](const std::string& name) {
    const Cube& cube = cube_named(name);
    const CubePose& pose = cube.model.pose();
    return std::make_tuple(cube.model.on_mat(), pose.x, pose.y, pose.angle_deg, cube.connected,
                           cube.model.light_writes());
  });
  control_->finishRegistration();
}

FakeBluez::~FakeBluez() {
  for (auto& cube : cubes_) {
    for (auto& c : cube->characteristics) c.object.reset();
    cube->service.reset();
    cube->device.reset();
  }
}

FakeBluez::Cube& FakeBluez::cube_named(const std::string& name) {
  for (auto& cube : cubes_) {
    if (cube->name == name) return *cube;
  }
  throw sdbus::Error("io.ctsfleet.Error.UnknownCube", "no emulated cube named '" + name + "'");
}

void FakeBluez::require_connected(const Cube& cube) const {
  if (!cube.connected) throw failed("Not connected");
}

void FakeBluez::make_present(Cube& cube) {
  if (cube.present) return;
  cube.present = true;
  Cube* c = &cube;
  cube.device = sdbus::createObject(connection_, cube.path);
  auto& device = *cube.device;
  device.registerMethod("Connect").onInterface(kDevice).implementedAs([this, c] {
    if (c->unreachable_for_s > 0) throw sdbus::Error("org.bluez.Error.Failed", "le-connection-abort-by-local");
    if (c->connected) return;
    c->connected = true;
    c->resolve_in_s = 0.05;
    spdlog::info("{}: connected", c->name);
    c->device->emitPropertiesChangedSignal(kDevice, {"Connected"});
  });
  device.registerMethod("Disconnect").onInterface(kDevice).implementedAs([this, c] {
    drop_connection(*c, "disconnected by the central");
  });
  device.registerProperty("Address").onInterface(kDevice).withGetter([c] { return c->address; });
  device.registerProperty("Name").onInterface(kDevice).withGetter([c] { return c->name; });
  device.registerProperty("Alias").onInterface(kDevice).withGetter([c] { return c->name; });
  device.registerProperty("Adapter").onInterface(kDevice).withGetter([this] {
    return sdbus::ObjectPath(adapter_path_);
  });
  device.registerProperty("Connected").onInterface(kDevice).withGetter([c] { return c->connected; });
  device.registerProperty("ServicesResolved").onInterface(kDevice).withGetter([c] { return c->services_resolved; });
  device.registerProperty("RSSI").onInterface(kDevice).withGetter([] { return int16_t{-55}; });
  device.registerProperty("UUIDs").onInterface(kDevice).withGetter([] {
    return std::vector<std::string>{std::string(kServiceUuid)};
  });
  device.finishRegistration();
  device.emitInterfacesAddedSignal();
  register_characteristics(cube);
  spdlog::info("{}: discovered as {}", cube.name, cube.address);
}

void FakeBluez::register_characteristics(Cube& cube) {
  Cube* c = &cube;
  const std::string service_path = cube.path + "/service000b";
  cube.service = sdbus::createObject(connection_, service_path);
  cube.service->registerProperty("UUID").onInterface(kService).withGetter([] { return std::string(kServiceUuid); });
  cube.service->registerProperty("Device").onInterface(kService).withGetter([c] { return sdbus::ObjectPath(c->path); });
  cube.service->registerProperty("Primary").onInterface(kService).withGetter([] { return true; });
  cube.service->finishRegistration();
  cube.service->emitInterfacesAddedSignal();

  cube.characteristics.reserve(toio_characteristics().size());
  int handle = 0x0c;
  for (const CharacteristicInfo& info : toio_characteristics()) {
    char suffix[16];
    std::snprintf(suffix, sizeof suffix, "/char%04x", handle);
    handle += 3;
    cube.characteristics.push_back({info.kind, info.uuid, sdbus::createObject(connection_, service_path + suffix), {}, false});
    CharacteristicObject* ch = &cube.characteristics.back();
    auto& object = *ch->object;
    object.registerMethod("ReadValue")
        .onInterface(kCharacteristic)
        .implementedAs([this, c, ch](const std::map<std::string, sdbus::Variant>&) {
          require_connected(*c);
          return c->model.read(ch->kind);
        });
    object.registerMethod("WriteValue")
        .onInterface(kCharacteristic)
        .implementedAs([this, c, ch](const std::vector<uint8_t>& value, const std::map<std::string, sdbus::Variant>&) {
          require_connected(*c);
          send(*c, c->model.write(ch->kind, value));
        });
    object.registerMethod("StartNotify").onInterface(kCharacteristic).implementedAs([this, c, ch] {
      require_connected(*c);
      ch->notifying = true;
      ch->object->emitPropertiesChangedSignal(kCharacteristic, {"Notifying"});
    });
    object.registerMethod("StopNotify").onInterface(kCharacteristic).implementedAs([ch] { ch->notifying = false; });
    object.registerProperty("UUID").onInterface(kCharacteristic).withGetter([ch] { return ch->uuid; });
    object.registerProperty("Service").onInterface(kCharacteristic).withGetter([service_path] {
      return sdbus::ObjectPath(service_path);
    });
    object.registerProperty("Value").onInterface(kCharacteristic).withGetter([ch] { return ch->value; });
    object.registerProperty("Notifying").onInterface(kCharacteristic).withGetter([ch] { return ch->notifying; });
    object.registerProperty("Flags").onInterface(kCharacteristic).withGetter([info] { return info.flags; });
    object.finishRegistration();
    object.emitInterfacesAddedSignal();
  }
}

void FakeBluez::send(Cube& cube, const std::vector<Notification>& notifications) {
  if (!cube.connected) return;
  for (const Notification& notification : notifications) {
    for (CharacteristicObject& ch : cube.characteristics) {
      if (ch.kind != notification.characteristic || !ch.notifying) continue;
      ch.value = notification.value;
      ch.object->emitPropertiesChangedSignal(kCharacteristic, {"Value"});
    }
  }
}

void FakeBluez::drop_connection(Cube& cube, const std::string& why) {
  if (!cube.connected) return;
  spdlog::info("{}: connection {}", cube.name, why);
  cube.connected = false;
  cube.services_resolved = false;
  cube.resolve_in_s = -1;
  for (CharacteristicObject& ch : cube.characteristics) ch.notifying = false;
  cube.model.disconnected();
  cube.device->emitPropertiesChangedSignal(kDevice, {"Connected", "ServicesResolved"});
}

void FakeBluez::tick(double dt) {
  for (auto& owned : cubes_) {
    Cube& cube = *owned;
    if (cube.unreachable_for_s > 0) cube.unreachable_for_s -= dt;
    if (cube.connected && cube.resolve_in_s >= 0) {
      cube.resolve_in_s -= dt;
      if (cube.resolve_in_s < 0) {
        cube.services_resolved = true;
        cube.device->emitPropertiesChangedSignal(kDevice, {"ServicesResolved"});
      }
    }
    std::vector<Notification> notifications = cube.model.advance(dt);
    if (cube.connected && cube.services_resolved) send(cube, notifications);
  }
}

}  // namespace toio_emulator
