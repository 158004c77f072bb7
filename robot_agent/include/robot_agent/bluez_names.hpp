// Names of BlueZ's D-Bus API (doc/org.bluez.*.rst in BlueZ), shared by the BLE client and the
// fake BlueZ of the cube emulator.
#pragma once

namespace robot_agent::bluez {

inline constexpr const char* kBusName = "org.bluez";
inline constexpr const char* kAdapter = "org.bluez.Adapter1";
inline constexpr const char* kDevice = "org.bluez.Device1";
inline constexpr const char* kGattService = "org.bluez.GattService1";
inline constexpr const char* kGattCharacteristic = "org.bluez.GattCharacteristic1";
inline constexpr const char* kProperties = "org.freedesktop.DBus.Properties";
inline constexpr const char* kObjectManager = "org.freedesktop.DBus.ObjectManager";

}  // namespace robot_agent::bluez
