// FakeBluez: the parts of BlueZ's D-Bus API a toio central uses, served for emulated cubes on a
// private bus: ObjectManager at /, Adapter1 (discovery makes the cubes appear), Device1 per cube
// (Connect, Disconnect, Connected, ServicesResolved), the toio GattService1 and its
// GattCharacteristic1 objects (ReadValue, WriteValue, StartNotify, StopNotify; notifications as
// PropertiesChanged of Value). A control interface io.ctsfleet.ToioEmulator1 at
// /io/ctsfleet/emulator lets tests lift, place, block and disconnect cubes.
#pragma once

#include <sdbus-c++/sdbus-c++.h>

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "toio_cube_model.hpp"

namespace toio_emulator {

struct CubeSpec {
  std::string name;  // advertised name, e.g. toio-001
  CubePose pose;
};

class FakeBluez {
 public:
  FakeBluez(sdbus::IConnection& connection, const std::vector<CubeSpec>& cubes, const std::string& adapter,
            double speed_per_unit);
  ~FakeBluez();
  // Advances every cube by dt seconds and sends their notifications.
  void tick(double dt);
  // Cube `index` (in the order given) delayed or not (ToioCubeModel::set_paused).
  void set_paused(size_t index, bool paused) { cubes_.at(index)->model.set_paused(paused); }
  size_t cube_count() const { return cubes_.size(); }

 private:
  struct CharacteristicObject {
    Characteristic kind;
    std::string uuid;
    std::unique_ptr<sdbus::IObject> object;
    Bytes value;
    bool notifying = false;
  };
  struct Cube {
    std::string name;
    std::string address;
    std::string path;
    ToioCubeModel model;
    bool present = false;  // known to BlueZ (after discovery)
    bool connected = false;
    bool services_resolved = false;
    double resolve_in_s = -1;       // ServicesResolved turns true after this delay
    double unreachable_for_s = 0;   // Connect fails until this runs out
    std::unique_ptr<sdbus::IObject> device;
    std::unique_ptr<sdbus::IObject> service;
    std::vector<CharacteristicObject> characteristics;
  };

  void make_present(Cube& cube);
  void register_characteristics(Cube& cube);
  void send(Cube& cube, const std::vector<Notification>& notifications);
  void drop_connection(Cube& cube, const std::string& why);
  Cube& cube_named(const std::string& name);
  void require_connected(const Cube& cube) const;

  sdbus::IConnection& connection_;
  std::string adapter_path_;
  double speed_per_unit_;
  std::unique_ptr<sdbus::IObject> root_;
  std::unique_ptr<sdbus::IObject> adapter_;
  std::unique_ptr<sdbus::IObject> control_;
  bool discovering_ = false;
  std::vector<std::unique_ptr<Cube>> cubes_;
};

}  // namespace toio_emulator
