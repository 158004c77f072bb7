// EmulatedBluez: for tests, a private dbus-daemon with ctsfleet-toio-emulator serving cubes on it,
// and DBUS_SYSTEM_BUS_ADDRESS pointing at it; both processes are stopped on destruction.
#pragma once

#include <sdbus-c++/sdbus-c++.h>
#include <signal.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

namespace robot_agent::testing {

// Polls `done` until it holds or `timeout` passes; the deadline is generous for a loaded machine.
inline bool eventually(const std::function<bool()>& done, std::chrono::seconds timeout = std::chrono::seconds(30)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

struct EmulatedCubePose {
  bool on_mat = false;
  double x = 0, y = 0, angle = 0;
  bool connected = false;
  int light_writes = 0;
};

class EmulatedBluez {
 public:
  explicit EmulatedBluez(const std::vector<std::string>& cube_args, const std::vector<std::string>& extra_args = {}) {
    dir_ = std::filesystem::temp_directory_path() / ("ctsfleet-bluez-" + std::to_string(getpid()) + "-" +
                                                      std::to_string(counter()++));
    std::filesystem::create_directories(dir_);
    const std::string address = "unix:path=" + (dir_ / "bus").string();
    bus_pid_ = spawn({"/usr/bin/dbus-daemon", "--session", "--nofork", "--nopidfile", "--address=" + address},
                     dir_ / "dbus.log");
    if (!eventually([&] { return std::filesystem::exists(dir_ / "bus"); })) throw std::runtime_error("no dbus-daemon");
    setenv("DBUS_SYSTEM_BUS_ADDRESS", address.c_str(), 1);
    std::vector<std::string> args = {CTSFLEET_BIN_DIR "/ctsfleet-toio-emulator", "--bus", address, "--mat",
                                     CTSFLEET_CONFIG_DIR "/mats/toio-collection-ring.yaml"};
    for (const std::string& cube : cube_args) args.insert(args.end(), {"--cube", cube});
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    emulator_pid_ = spawn(args, dir_ / "emulator.log");
    if (!eventually([&] { return log().find("toio-emulator ready") != std::string::npos; })) {
      throw std::runtime_error("the emulator did not start: " + log());
    }
    connection_ = sdbus::createSessionBusConnectionWithAddress(address);
    control_ = sdbus::createProxy(*connection_, "org.bluez", "/io/ctsfleet/emulator");
  }

  ~EmulatedBluez() {
    control_.reset();
    connection_.reset();
    for (pid_t pid : {emulator_pid_, bus_pid_}) {
      if (pid > 0) {
        kill(pid, SIGTERM);
        waitpid(pid, nullptr, 0);
      }
    }
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }

  std::string log() const {
    std::ifstream file(dir_ / "emulator.log");
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
  }

  void lift(const std::string& cube) { control_->callMethod("Lift").onInterface(kControl).withArguments(cube); }
  void place(const std::string& cube, double x, double y, double angle = 0) {
    control_->callMethod("Place").onInterface(kControl).withArguments(cube, x, y, angle);
  }
  void drop_connection(const std::string& cube, double unreachable_s) {
    control_->callMethod("DropConnection").onInterface(kControl).withArguments(cube, unreachable_s);
  }
  void block(const std::string& cube, bool blocked) {
    control_->callMethod("Block").onInterface(kControl).withArguments(cube, blocked);
  }
  // Another program writing to a cube's motor characteristic (the first cube's, address ...:00).
  void write_motor_of_first_cube(const std::vector<uint8_t>& bytes) {
    auto motor = sdbus::createProxy(*connection_, "org.bluez", "/org/bluez/hci0/dev_E0_7C_00_00_00_00/service000b/char000f");
    std::map<std::string, sdbus::Variant> options{{"type", sdbus::Variant(std::string("command"))}};
    motor->callMethod("WriteValue").onInterface("org.bluez.GattCharacteristic1").withArguments(bytes, options);
  }
  EmulatedCubePose pose(const std::string& cube) {
    std::tuple<bool, double, double, double, bool, int> reply;
    control_->callMethod("Pose").onInterface(kControl).withArguments(cube).storeResultsTo(reply);
    return {std::get<0>(reply), std::get<1>(reply), std::get<2>(reply), std::get<3>(reply), std::get<4>(reply),
            std::get<5>(reply)};
  }

 private:
  static constexpr const char* kControl = "io.ctsfleet.ToioEmulator1";
  static int& counter() {
    static int value = 0;
    return value;
  }
  static pid_t spawn(const std::vector<std::string>& args, const std::filesystem::path& log) {
    const pid_t pid = fork();
    if (pid == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(fd, 1);
      dup2(fd, 2);
      std::vector<char*> argv;
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
    return pid;
  }

  std::filesystem::path dir_;
  pid_t bus_pid_ = -1;
  pid_t emulator_pid_ = -1;
  std::unique_ptr<sdbus::IConnection> connection_;
  std::unique_ptr<sdbus::IProxy> control_;
};

}  // namespace robot_agent::testing
