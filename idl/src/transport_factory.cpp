#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "transport_factories.hpp"

namespace fleet_transport {

void exit_if_shutdown_hangs(double seconds, int exit_code) {
  std::thread([seconds, exit_code] {
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    std::fprintf(stderr, "the middleware did not shut down within %.1f s: exiting anyway\n", seconds);
    std::fflush(nullptr);
    _exit(exit_code);
  }).detach();
}

std::unique_ptr<Transport> make_transport(const TransportConfig& config, Handlers handlers) {
  // The middleware reads its configuration file from the environment at participant creation.
  if (const std::string& dir = config.loopback_config_dir; !dir.empty()) {
    // Robot agents (they read one robot's commands) discover coordinators and observers only.
    const char* cyclone_file = config.commands_for.empty() ? "/cyclonedds-loopback.xml" : "/cyclonedds-loopback-agent.xml";
    setenv("CYCLONEDDS_URI", ("file://" + dir + cyclone_file).c_str(), 0);
    setenv("FASTRTPS_DEFAULT_PROFILES_FILE", (dir + "/fastdds-loopback.xml").c_str(), 0);
  }
  if (config.vendor == Vendor::kCyclone) return make_cyclone_transport(config, std::move(handlers));
  return make_fastdds_transport(config, std::move(handlers));
}

}  // namespace fleet_transport
