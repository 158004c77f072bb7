// BluezClient: a BLE central through BlueZ on the system D-Bus (sdbus-c++). Finds a device by
// advertised name or address, connects, waits for ServicesResolved, finds GATT characteristics by
// UUID through ObjectManager, subscribes to notifications, reads and writes. The bus address comes
// from DBUS_SYSTEM_BUS_ADDRESS when set, so tests point it at a private bus with a fake BlueZ.
// Not thread-safe: one thread owns a client and calls process() between its other calls; wake()
// is the one call any thread may make. D-Bus failures throw BluezError.
#pragma once

#include <sdbus-c++/sdbus-c++.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "robot_agent/dbus_event_pump.hpp"

namespace robot_agent {

class BluezError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class BluezClient {
 public:
  using Bytes = std::vector<uint8_t>;
  using NotifyCallback = std::function<void(const Bytes&)>;

  explicit BluezClient(std::string adapter = "hci0");
  ~BluezClient();

  struct Device {
    std::string path, name, alias, address;
    int rssi = 0;  // dBm, 0 when unknown
  };
  // Every device the adapter knows after discovering for `duration`.
  std::vector<Device> discover(std::chrono::milliseconds duration);
  // The object path of a device whose Name/Alias or Address matches, discovering for up to
  // `timeout` when BlueZ does not know it yet; nullopt when not found.
  std::optional<std::string> find_device(const std::string& name_or_address, std::chrono::milliseconds timeout);
  // Connect and wait until BlueZ has resolved the device's services.
  void connect(const std::string& device_path, std::chrono::milliseconds timeout);
  void disconnect(const std::string& device_path);
  bool connected(const std::string& device_path);
  // Characteristic UUID (lower case) -> object path, for one service of a connected device.
  std::map<std::string, std::string> characteristics(const std::string& device_path, const std::string& service_uuid);

  void start_notify(const std::string& characteristic_path, NotifyCallback on_value);
  // with_response = false writes as a "command" (write without response), true as a "request".
  void write(const std::string& characteristic_path, const Bytes& value, bool with_response);
  Bytes read(const std::string& characteristic_path);
  // Called (from process()) when the device's Connected property turns false or it is removed.
  void on_disconnected(const std::string& device_path, std::function<void()> callback);
  // Forget proxies and subscriptions of a device (before reconnecting it).
  void forget(const std::string& device_path);

  // Dispatches pending D-Bus messages, waiting up to max_wait for some (or for wake()).
  void process(std::chrono::milliseconds max_wait);
  void wake();

 private:
  using ManagedObjects =
      std::map<sdbus::ObjectPath, std::map<std::string, std::map<std::string, sdbus::Variant>>>;
  ManagedObjects managed_objects();
  std::vector<Device> known_devices();  // BlueZ's devices of this adapter, as of now
  void start_discovery();               // LE only
  void stop_discovery();
  sdbus::IProxy& proxy(const std::string& path);
  template <typename F>
  auto guarded(const std::string& what, F&& call) -> decltype(call());

  std::string adapter_path_;
  std::unique_ptr<sdbus::IConnection> connection_;
  std::unique_ptr<DbusEventPump> pump_;
  std::map<std::string, std::unique_ptr<sdbus::IProxy>> proxies_;
  std::map<std::string, NotifyCallback> notify_callbacks_;
  std::map<std::string, std::function<void()>> disconnect_callbacks_;
};

}  // namespace robot_agent
