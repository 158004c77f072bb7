#include "robot_agent/bluez_client.hpp"

#include <algorithm>
#include <cctype>
#include <thread>

#include "robot_agent/bluez_names.hpp"

namespace robot_agent {

namespace {

using bluez::kAdapter;
using bluez::kDevice;
using bluez::kObjectManager;
using bluez::kProperties;
constexpr const char* kBluez = bluez::kBusName;
constexpr const char* kService = bluez::kGattService;
constexpr const char* kCharacteristic = bluez::kGattCharacteristic;
constexpr uint64_t kCallTimeoutUs = 10'000'000;  // BlueZ's own calls can take seconds over the air

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

template <typename T>
std::optional<T> property(const std::map<std::string, sdbus::Variant>& properties, const std::string& name) {
  const auto it = properties.find(name);
  if (it == properties.end() || !it->second.containsValueOfType<T>()) return std::nullopt;
  return it->second.get<T>();
}

}  // namespace

BluezClient::BluezClient(std::string adapter) : adapter_path_("/org/bluez/" + adapter) {
  try {
    connection_ = sdbus::createSystemBusConnection();
  } catch (const sdbus::Error& e) {
    throw BluezError("cannot connect to the system D-Bus (is BlueZ's bus running? DBUS_SYSTEM_BUS_ADDRESS overrides "
                     "it): " + e.getMessage());
  }
  pump_ = std::make_unique<DbusEventPump>(*connection_);
}

BluezClient::~BluezClient() {
  proxies_.clear();  // proxies before the connection they use
}

template <typename F>
auto BluezClient::guarded(const std::string& what, F&& call) -> decltype(call()) {
  try {
    return call();
  } catch (const sdbus::Error& e) {
    throw BluezError(what + ": " + e.getName() + ": " + e.getMessage());
  }
}

sdbus::IProxy& BluezClient::proxy(const std::string& path) {
  auto it = proxies_.find(path);
  if (it != proxies_.end()) return *it->second;
  auto created = sdbus::createProxy(*connection_, kBluez, path);
  // Every object we talk to may report changes: a characteristic's Value (a notification) or a
  // device's Connected flag.
  created->uponSignal("PropertiesChanged")
      .onInterface(kProperties)
      .call([this, path](const std::string& interface, const std::map<std::string, sdbus::Variant>& changed,
                         const std::vector<std::string>& /*invalidated*/) {
        if (interface == kCharacteristic) {
          const auto callback = notify_callbacks_.find(path);
          const auto value = property<std::vector<uint8_t>>(changed, "Value");
          if (callback != notify_callbacks_.end() && value) callback->second(*value);
        } else if (interface == kDevice) {
          const auto now_connected = property<bool>(changed, "Connected");
          const auto callback = disconnect_callbacks_.find(path);
          if (now_connected && !*now_connected && callback != disconnect_callbacks_.end()) callback->second();
        }
      });
  created->finishRegistration();
  return *proxies_.emplace(path, std::move(created)).first->second;
}

BluezClient::ManagedObjects BluezClient::managed_objects() {
  return guarded("GetManagedObjects", [&] {
    auto root = sdbus::createProxy(*connection_, kBluez, "/");
    ManagedObjects objects;
    root->callMethod("GetManagedObjects").onInterface(kObjectManager).withTimeout(kCallTimeoutUs).storeResultsTo(objects);
    return objects;
  });
}

void BluezClient::start_discovery() {
  guarded("StartDiscovery", [&] {
    std::map<std::string, sdbus::Variant> filter{{"Transport", sdbus::Variant(std::string("le"))}};
    proxy(adapter_path_).callMethod("SetDiscoveryFilter").onInterface(kAdapter).withArguments(filter);
    proxy(adapter_path_).callMethod("StartDiscovery").onInterface(kAdapter);
  });
}

void BluezClient::stop_discovery() {
  try {
    proxy(adapter_path_).callMethod("StopDiscovery").onInterface(kAdapter);
  } catch (const sdbus::Error&) {
    // Another client may have stopped it already; nothing to undo.
  }
}

std::vector<BluezClient::Device> BluezClient::known_devices() {
  const ManagedObjects objects = managed_objects();
  if (!objects.count(sdbus::ObjectPath(adapter_path_))) throw BluezError("no Bluetooth adapter " + adapter_path_ + " in BlueZ");
  std::vector<Device> devices;
  for (const auto& [path, interfaces] : objects) {
    const auto device = interfaces.find(kDevice);
    if (device == interfaces.end()) continue;
    if (property<sdbus::ObjectPath>(device->second, "Adapter").value_or(sdbus::ObjectPath{}) != adapter_path_) continue;
    devices.push_back({path, property<std::string>(device->second, "Name").value_or(""),
                       property<std::string>(device->second, "Alias").value_or(""),
                       property<std::string>(device->second, "Address").value_or(""),
                       property<int16_t>(device->second, "RSSI").value_or(0)});
  }
  return devices;
}

std::optional<std::string> BluezClient::find_device(const std::string& name_or_address,
                                                    std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  const std::string wanted = lower(name_or_address);
  bool discovering = false;
  std::optional<std::string> found;
  while (!found) {
    for (const Device& device : known_devices()) {
      if (lower(device.name) == wanted || lower(device.alias) == wanted || lower(device.address) == wanted) {
        found = device.path;
      }
    }
    if (found || std::chrono::steady_clock::now() >= deadline) break;
    if (!discovering) start_discovery();
    discovering = true;
    process(std::chrono::milliseconds(200));
  }
  if (discovering) stop_discovery();
  return found;
}

std::vector<BluezClient::Device> BluezClient::discover(std::chrono::milliseconds duration) {
  start_discovery();
  const auto deadline = std::chrono::steady_clock::now() + duration;
  while (std::chrono::steady_clock::now() < deadline) process(std::chrono::milliseconds(100));
  stop_discovery();
  return known_devices();
}

void BluezClient::connect(const std::string& device_path, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  guarded("Connect " + device_path, [&] {
    proxy(device_path).callMethod("Connect").onInterface(kDevice).withTimeout(kCallTimeoutUs);
  });
  for (;;) {
    const bool resolved = guarded("ServicesResolved of " + device_path, [&] {
      return proxy(device_path).getProperty("ServicesResolved").onInterface(kDevice).get<bool>();
    });
    if (resolved) return;
    if (std::chrono::steady_clock::now() >= deadline) {
      throw BluezError("services of " + device_path + " not resolved within " + std::to_string(timeout.count()) +
                       " ms of connecting");
    }
    process(std::chrono::milliseconds(20));
  }
}

void BluezClient::disconnect(const std::string& device_path) {
  guarded("Disconnect " + device_path,
          [&] { proxy(device_path).callMethod("Disconnect").onInterface(kDevice).withTimeout(kCallTimeoutUs); });
}

bool BluezClient::connected(const std::string& device_path) {
  return guarded("Connected of " + device_path,
                 [&] { return proxy(device_path).getProperty("Connected").onInterface(kDevice).get<bool>(); });
}

std::map<std::string, std::string> BluezClient::characteristics(const std::string& device_path,
                                                                const std::string& service_uuid) {
  const ManagedObjects objects = managed_objects();
  std::string service_path;
  for (const auto& [path, interfaces] : objects) {
    const auto service = interfaces.find(kService);
    if (service == interfaces.end()) continue;
    if (property<sdbus::ObjectPath>(service->second, "Device").value_or(sdbus::ObjectPath{}) != device_path) continue;
    if (lower(property<std::string>(service->second, "UUID").value_or("")) == lower(service_uuid)) service_path = path;
  }
  if (service_path.empty()) throw BluezError("device " + device_path + " has no GATT service " + service_uuid);
  std::map<std::string, std::string> found;
  for (const auto& [path, interfaces] : objects) {
    const auto characteristic = interfaces.find(kCharacteristic);
    if (characteristic == interfaces.end()) continue;
    if (property<sdbus::ObjectPath>(characteristic->second, "Service").value_or(sdbus::ObjectPath{}) != service_path) {
      continue;
    }
    found[lower(property<std::string>(characteristic->second, "UUID").value_or(""))] = path;
  }
  return found;
}

void BluezClient::start_notify(const std::string& characteristic_path, NotifyCallback on_value) {
  notify_callbacks_[characteristic_path] = std::move(on_value);
  guarded("StartNotify " + characteristic_path, [&] {
    proxy(characteristic_path).callMethod("StartNotify").onInterface(kCharacteristic).withTimeout(kCallTimeoutUs);
  });
}

void BluezClient::write(const std::string& characteristic_path, const Bytes& value, bool with_response) {
  std::map<std::string, sdbus::Variant> options{
      {"type", sdbus::Variant(std::string(with_response ? "request" : "command"))}};
  guarded("WriteValue " + characteristic_path, [&] {
    proxy(characteristic_path)
        .callMethod("WriteValue")
        .onInterface(kCharacteristic)
        .withTimeout(kCallTimeoutUs)
        .withArguments(value, options);
  });
}

BluezClient::Bytes BluezClient::read(const std::string& characteristic_path) {
  return guarded("ReadValue " + characteristic_path, [&] {
    Bytes value;
    std::map<std::string, sdbus::Variant> options;
    proxy(characteristic_path)
        .callMethod("ReadValue")
        .onInterface(kCharacteristic)
        .withTimeout(kCallTimeoutUs)
        .withArguments(options)
        .storeResultsTo(value);
    return value;
  });
}

void BluezClient::on_disconnected(const std::string& device_path, std::function<void()> callback) {
  disconnect_callbacks_[device_path] = std::move(callback);
  proxy(device_path);  // subscribes to its PropertiesChanged
}

void BluezClient::forget(const std::string& device_path) {
  for (auto it = proxies_.begin(); it != proxies_.end();) {
    if (it->first.rfind(device_path, 0) == 0) {
      notify_callbacks_.erase(it->first);
      disconnect_callbacks_.erase(it->first);
      it = proxies_.erase(it);
    } else {
      ++it;
    }
  }
}

void BluezClient::process(std::chrono::milliseconds max_wait) { pump_->run_once(max_wait); }

void BluezClient::wake() { pump_->wake(); }

}  // namespace robot_agent
