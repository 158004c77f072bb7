// Transport: publish and subscribe the fleet's messages by robot, with liveliness events, over
// Cyclone DDS or Fast DDS chosen at run time. Topics are keyed by robot id (one DDS instance per
// robot). QoS: commands reliable; state best-effort keep-last 1 with a deadline of two leases
// (missed deadlines are acted on by the coordinator's silence timeout); announcements and fleet status
// reliable transient-local keep-last 1 (coordinator and fleet status: one instance per
// coordinator); liveliness
// automatic with the configured lease; commands with exclusive ownership (strength = the sending
// coordinator's term), so a robot hears one coordinator's commands. Step commands, robot states
// and announcements travel in the robot's own partition, robot/<id>; readers of every robot use
// robot/*, and drop a state or announcement whose id is not its partition's.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "fleet_transport/messages.hpp"
#include "fleet_transport/security.hpp"

namespace fleet_transport {

enum class Vendor { kCyclone, kFastDds };
Vendor parse_vendor(const std::string& name);  // "cyclone" or "fastdds"; throws std::invalid_argument
const char* to_string(Vendor vendor);

struct TransportConfig {
  Vendor vendor = Vendor::kCyclone;
  int domain_id = 0;
  double lease_s = 1.0;
  // Folder with cyclonedds-loopback.xml (cyclonedds-loopback-agent.xml for agents: commands_for
  // set) and fastdds-loopback.xml, exported as CYCLONEDDS_URI /
  // FASTRTPS_DEFAULT_PROFILES_FILE when those variables are not already set ("" = leave the
  // environment alone).
  std::string loopback_config_dir;
  // An agent passes its own id: commands for other robots are dropped in the transport.
  std::string commands_for;
  // Step commands have exclusive ownership: of several live coordinators writing to one robot,
  // only the strongest is heard (a coordinator uses its term).
  int command_strength = 0;
  // Fast DDS only: discover through these discovery servers ("HOST:PORT;HOST:PORT", server i
  // being the one started as `ctsfleet-discovery --server-id i`) instead of with every
  // participant on the network. Empty: simple discovery (the config file's peers).
  std::string discovery_servers;
  // A network instead of loopback (hosts on a LAN): the interface to use, by name or IPv4
  // address, and discovery by multicast on it; with `peers` (IPv4 addresses, comma-separated)
  // discovery is unicast to those hosts instead, for networks without multicast. Either one
  // replaces the loopback files of loopback_config_dir.
  std::string network_interface;
  std::string peers;
  // DDS Security: off when no files are given (see fleet_security_files).
  SecurityFiles security;
  // Tests only: write every robot state and announcement in this robot's partition, whatever id
  // it carries (plays a robot that claims another's id from its own partition).
  std::string test_partition_of;
};

inline constexpr const char* kInterfaceHelp =
    "run on this network interface (name or IPv4 address) instead of loopback, discovering by multicast";
inline constexpr const char* kPeersHelp =
    "with --iface: discover by unicast to these hosts (IPv4, comma-separated) instead of multicast";
inline constexpr const char* kDiscoveryServerHelp =
    "Fast DDS: discover through these ctsfleet-discovery servers, HOST:PORT;HOST:PORT (server i = --server-id i)";

// Fast DDS 2.9.1 (Debian 12) aborts a secure participant that discovers through a server: an
// assertion in SecurityManager::encode_rtps_message with RTPS protection on, and no discovery at
// all with it off. Upstream fixed secure discovery servers in 2.14 / 3.x (Fast-DDS PR #5257).
inline constexpr const char* kSecureDiscoveryServerUnsupported =
    "discovery servers with DDS Security: Fast DDS 2.9.1 (Debian 12) cannot do both (it aborts in "
    "SecurityManager::encode_rtps_message); a secure Fast DDS fleet uses simple discovery, or use Cyclone DDS";

// The IPv4 address of interface `name_or_address` on this host; std::invalid_argument (listing
// the host's interfaces) when there is none.
std::string interface_address(const std::string& name_or_address);
// The peers of a comma-separated list of IPv4 addresses; std::invalid_argument on a bad one.
std::vector<std::string> parse_peers(const std::string& peers);

// The UDP port the sim and the fleet benchmark give a domain's discovery server: above the ports
// of every DDS domain they use (domain d takes 7400 + 250 d onwards) and above Linux's ephemeral
// ports.
inline int default_discovery_server_port(int domain) { return 65000 + domain; }

// Throws std::invalid_argument, naming what is wrong, unless the interface exists on this host
// and the peers parse (both may be empty; peers need an interface).
void check_network(const std::string& network_interface, const std::string& peers);

// Throws std::invalid_argument, naming the bad entry, unless `servers` is empty or a list of
// IPv4 HOST:PORT separated by ';', the vendor is Fast DDS and the participant is not `secure`.
void check_discovery_servers(Vendor vendor, const std::string& servers, bool secure);

// Where this participant looks for the others, for a log line: "cyclone domain 0 (loopback, DDS
// config DIR)", "... (interface eth0, multicast discovery)", "... (interface eth0, unicast to
// PEERS)", "fastdds domain 0 (discovery server HOST:PORT)", with ", DDS Security" when it is on.
std::string describe_network(const TransportConfig& config);
// The options another program of the fleet needs to find this one ("--dds cyclone --domain 0
// --dds-config-dir DIR", "... --iface <its interface on this network> --peers PEERS", ...), and
// with multicast discovery, that the network must carry it.
std::string options_to_join(const TransportConfig& config);

enum class GoneReason { kGoodbye, kLivelinessLost };

// Handlers run on the middleware's threads: keep them short and thread-safe. Unset ones are not
// subscribed.
struct Handlers {
  std::function<void(const Announcement&)> on_announcement;
  std::function<void(const RobotState&)> on_state;
  std::function<void(const StepCommand&)> on_command;
  std::function<void(const CoordinatorStatus&)> on_coordinator_status;
  std::function<void(const FleetStatus&)> on_fleet_status;
  std::function<void(const MissionInfo&)> on_mission_info;
  std::function<void(const FleetPlan&)> on_fleet_plan;
  std::function<void(const FleetEvent&)> on_fleet_event;
  std::function<void(const TaskRequest&)> on_task_request;
  std::function<void(const TaskReply&)> on_task_reply;
  // A robot's announcement instance lost its writer (process died: lease expired) or was disposed.
  std::function<void(const std::string& robot_id, GoneReason reason)> on_robot_gone;
  // Something refused by the transport that the process should log: e.g. a robot state or
  // announcement whose robot id is not the one of the partition it was written in (a robot may
  // write only in its own partition, robot/<id>, and DDS access control binds that to its
  // certificate). Said once per writer.
  std::function<void(const std::string& what)> on_refused;
};

class Transport {
 public:
  virtual ~Transport() = default;
  virtual void announce(const Announcement& announcement) = 0;
  virtual void say_goodbye(const std::string& robot_id) = 0;  // disposes the robot's announcement
  virtual void publish_state(const RobotState& state) = 0;
  virtual void send_command(const StepCommand& command) = 0;
  // Opens the command channel to a robot ahead of its first command, so that the first command
  // does not go out before the robot's agent is matched (volatile data would be lost). Returns
  // once it is open; throws std::runtime_error when the middleware refuses it (access control).
  virtual void open_commands_for(const std::string& robot_id) = 0;
  // The same without waiting: the channel opens soon (Fast DDS: on a background thread, as one
  // writer can take it a second once 200 participants are matched). A refusal goes to
  // Handlers::on_refused, and the first command to that robot meets it again.
  virtual void prepare_commands_for(const std::string& robot_id) { open_commands_for(robot_id); }
  virtual void publish_coordinator_status(const CoordinatorStatus& status) = 0;
  virtual void publish_fleet_status(const FleetStatus& status) = 0;
  // For operators (dashboard, ctsfleet-task): mission, plan and events reliable; mission and plan
  // transient-local keep-last 1 per coordinator, events transient-local keep-last 64 (a
  // dashboard started late sees the recent ones); task requests and replies reliable, volatile.
  virtual void publish_mission_info(const MissionInfo& info) = 0;
  virtual void publish_fleet_plan(const FleetPlan& plan) = 0;
  virtual void publish_fleet_event(const FleetEvent& event) = 0;
  virtual void request_task(const TaskRequest& request) = 0;
  virtual void reply_task(const TaskReply& reply) = 0;
  // Changes the ownership strength of this process's command writers (a standby taking over).
  virtual void set_command_strength(int strength) = 0;
};

// Ends the process with `exit_code` unless it has exited by itself within `seconds`. Armed by the
// fleet's programs when they stop, before the transport is destroyed: Cyclone DDS 0.10.2 with
// security can hang in its handshake state machine while a participant is deleted (upstream
// cyclonedds issue 1548, fixed after the version Debian 12 ships), and a robot process must stop.
void exit_if_shutdown_hangs(double seconds, int exit_code);

// Throws std::runtime_error when the middleware cannot be set up.
std::unique_ptr<Transport> make_transport(const TransportConfig& config, Handlers handlers);

}  // namespace fleet_transport
