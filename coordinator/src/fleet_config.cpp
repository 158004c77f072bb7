#include "coordinator/fleet_config.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "planner_core/input_error.hpp"
#include "planner_core/yaml_context.hpp"
#include "planner_core/solver.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace coordinator {

namespace fs = std::filesystem;
using planner_core::InputError;

namespace {

// Fails unless `value` (read from section.key) is finite and within [low, high] (low excluded
// when `low_open`).
void check_range(const planner_core::YamlContext& r, const YAML::Node& section, const std::string& field,
                 double value, double low, double high, bool low_open) {
  const bool ok = std::isfinite(value) && (low_open ? value > low : value >= low) && value <= high;
  if (ok) return;
  std::ostringstream range;
  range << (low_open ? "(" : "[") << low << ", " << high << "]";
  const std::string key = field.substr(field.find('.') + 1);
  r.fail(section[key] ? section[key] : section, field, "must be a number in " + range.str());
}

// A folder named in the config: relative to the config file's own folder.
std::string beside_config(const FleetConfig& config, const std::string& dir) {
  return fs::path(dir).is_relative() ? (fs::path(config.source).parent_path() / dir).lexically_normal().string() : dir;
}

// robots: which robots may take part, and how many the mission waits for.
void read_robots(const planner_core::YamlContext& r, const YAML::Node& robots, FleetConfig& config) {
  r.only_keys(robots, {"expected", "quorum", "wait_timeout_s"}, "robots");
  if (const YAML::Node expected = robots["expected"]) {
    if (expected.IsScalar() && expected.Scalar() == "any") {
      config.any_robots = true;
    } else if (expected.IsSequence()) {
      config.any_robots = false;
      if (expected.size() == 0) {
        r.fail(expected, "robots.expected", "an empty list: no robot could take part (list robot ids, or say 'any')");
      }
      for (const auto& id : expected) {
        if (!id.IsScalar() || !fleet_transport::is_valid_robot_id(id.Scalar())) {
          r.fail(id, "robots.expected", std::string("robot ids are ") + fleet_transport::kRobotIdRule);
        }
        if (std::find(config.expected_robots.begin(), config.expected_robots.end(), id.Scalar()) !=
            config.expected_robots.end()) {
          r.fail(id, "robots.expected", "robot id '" + id.Scalar() + "' is listed twice");
        }
        config.expected_robots.push_back(id.Scalar());
      }
    } else {
      r.fail(expected, "robots.expected", "expected 'any' or a list of robot ids");
    }
  }
  r.read(robots, "quorum", "robots", config.quorum);
  r.read(robots, "wait_timeout_s", "robots", config.wait_timeout_s);
  check_range(r, robots, "robots.quorum", config.quorum, 1, 100000, false);
  check_range(r, robots, "robots.wait_timeout_s", config.wait_timeout_s, 0, 1e6, true);
}

// planner: the solvers of the first plan and of replans, and their budgets.
void read_planner(const planner_core::YamlContext& r, const YAML::Node& planner, FleetConfig& config) {
  r.only_keys(planner,
              {"solver", "time_limit_s", "replan_solver", "replan_time_limit_s", "pibt_swap", "seed", "iterations",
               "actions", "lns_stall_iterations"},
              "planner");
  if (const YAML::Node actions = planner["actions"]) {
    std::string text;
    r.read(planner, "actions", "planner", text);
    if (text != "move4" && text != "rotate") r.fail(actions, "planner.actions", "must be move4 or rotate, not '" + text + "'");
    config.actions = planner_core::parse_action_model(text, "planner.actions");
  }
  r.read(planner, "solver", "planner", config.solver);
  r.read(planner, "time_limit_s", "planner", config.plan_time_s);
  r.read(planner, "replan_solver", "planner", config.replan_solver);
  r.read(planner, "replan_time_limit_s", "planner", config.replan_time_s);
  r.read(planner, "pibt_swap", "planner", config.pibt_swap);
  r.read(planner, "seed", "planner", config.seed);
  r.read(planner, "iterations", "planner", config.iterations);
  r.read(planner, "lns_stall_iterations", "planner", config.lns_stall_iterations);
  check_range(r, planner, "planner.lns_stall_iterations", config.lns_stall_iterations, 0, 100000000, false);
  check_range(r, planner, "planner.seed", static_cast<double>(config.seed), 0, 4294967295.0, false);
  check_range(r, planner, "planner.iterations", static_cast<double>(config.iterations), 0,
              static_cast<double>(planner_core::kMaxIterations), false);
  check_range(r, planner, "planner.time_limit_s", config.plan_time_s, 0, planner_core::kMaxTimeLimitS, true);
  check_range(r, planner, "planner.replan_time_limit_s", config.replan_time_s, 0, planner_core::kMaxTimeLimitS, true);
  const auto known = planner_core::solver_names();
  for (const std::string* name : {&config.solver, &config.replan_solver}) {
    if (std::find(known.begin(), known.end(), *name) == known.end()) {
      r.fail(planner, "planner", "unknown solver '" + *name + "'");
    }
  }
}

// dds: vendor, domain, lease, loopback XML, discovery server, interface and peers.
void read_dds(const planner_core::YamlContext& r, const YAML::Node& dds, FleetConfig& config) {
  r.only_keys(dds, {"vendor", "domain_id", "lease_s", "config_dir", "discovery_server", "interface", "peers"}, "dds");
  r.read(dds, "vendor", "dds", config.dds_vendor);
  r.read(dds, "domain_id", "dds", config.domain_id);
  r.read(dds, "lease_s", "dds", config.lease_s);
  std::string dir;
  r.read(dds, "config_dir", "dds", dir);
  if (!dir.empty()) config.dds_config_dir = beside_config(config, dir);
  check_range(r, dds, "dds.domain_id", config.domain_id, 0, 232, false);
  check_range(r, dds, "dds.lease_s", config.lease_s, 0, 3600, true);
  if (!config.dds_config_dir.empty() && !fs::is_directory(config.dds_config_dir)) {
    r.fail(dds["config_dir"], "dds.config_dir", "'" + config.dds_config_dir + "' is not a folder");
  }
  r.read(dds, "discovery_server", "dds", config.discovery_server);
  r.read(dds, "interface", "dds", config.network_interface);
  r.read(dds, "peers", "dds", config.peers);
  if (config.dds_vendor != "cyclone" && config.dds_vendor != "fastdds") {
    r.fail(dds["vendor"], "dds.vendor", "expected cyclone or fastdds");
  }
}

// security: whether DDS Security is required, the fleet directory, this identity.
void read_security(const planner_core::YamlContext& r, const YAML::Node& security, FleetConfig& config) {
  r.only_keys(security, {"required", "fleet_dir", "identity"}, "security");
  r.read(security, "required", "security", config.security_required);
  std::string dir;
  r.read(security, "fleet_dir", "security", dir);
  if (!dir.empty()) config.security_dir = beside_config(config, dir);
  r.read(security, "identity", "security", config.security_identity);
  if (config.security_identity.empty() || config.security_identity.size() > 32) {
    r.fail(security["identity"], "security.identity", "must have 1 to 32 characters");
  }
}

// timing: the simulated step and the timeouts, with the limits they must keep to each other.
void read_timing(const planner_core::YamlContext& r, const YAML::Node& timing, FleetConfig& config) {
  r.only_keys(timing, {"step_s", "silence_timeout_s", "command_timeout_s", "mission_timeout_s", "replan_settle_s",
                       "replacement_timeout_s"}, "timing");
  r.read(timing, "step_s", "timing", config.step_s);
  r.read(timing, "silence_timeout_s", "timing", config.silence_timeout_s);
  r.read(timing, "command_timeout_s", "timing", config.command_timeout_s);
  r.read(timing, "mission_timeout_s", "timing", config.mission_timeout_s);
  r.read(timing, "replan_settle_s", "timing", config.replan_settle_s);
  check_range(r, timing, "timing.step_s", config.step_s, 0, 3600, true);
  check_range(r, timing, "timing.silence_timeout_s", config.silence_timeout_s, 0, 3600, true);
  check_range(r, timing, "timing.command_timeout_s", config.command_timeout_s, 0, 3600, true);
  if (!timing["command_timeout_s"]) {  // the default, raised for long steps
    config.command_timeout_s = std::max(config.command_timeout_s, 2 * config.resend_after_s());
  } else if (config.command_timeout_s < 2 * config.resend_after_s()) {
    std::ostringstream least;
    least << 2 * config.resend_after_s();
    r.fail(timing["command_timeout_s"], "timing.command_timeout_s",
           "must be at least " + least.str() + " s: twice the resend interval max(1 s, 5 x step_s), so that a "
           "lost command is sent again before its robot is taken out");
  }
  check_range(r, timing, "timing.mission_timeout_s", config.mission_timeout_s, 0, 1e6, true);
  check_range(r, timing, "timing.replan_settle_s", config.replan_settle_s, 0, 3600, false);
  if (timing["replacement_timeout_s"]) {
    double seconds = 0;
    r.read(timing, "replacement_timeout_s", "timing", seconds);
    check_range(r, timing, "timing.replacement_timeout_s", seconds, 0, 3600, false);
    config.replacement_timeout_s = seconds;
  }
}

}  // namespace

FleetConfig load_fleet_config(const std::string& path) {
  const YAML::Node root = planner_core::load_yaml_file(path);
  const planner_core::YamlContext r(path);
  FleetConfig config;
  config.source = path;
  r.only_keys(root, {"mission", "lifelong", "lifelong_planner", "robots", "planner", "dds", "timing", "security"}, "top level");
  if (const YAML::Node lifelong = root["lifelong"]) {
    try {
      config.lifelong = lifelong.as<bool>();
    } catch (const YAML::Exception&) {
      r.fail(lifelong, "lifelong", "must be true or false");
    }
  }
  if (const YAML::Node planner = root["lifelong_planner"]) {
    if (!planner.IsScalar() || planner.Scalar().empty()) r.fail(planner, "lifelong_planner", "must be a file name");
    fs::path settings = planner.Scalar();
    if (settings.is_relative()) settings = fs::path(path).parent_path() / settings;
    config.lifelong_planner = planner_core::load_lifelong_config(settings.lexically_normal().string());
  }
  if (!root["mission"] || !root["mission"].IsScalar()) r.fail(root, "mission", "missing or not a file name");
  fs::path mission = root["mission"].Scalar();
  if (mission.is_relative()) mission = fs::path(path).parent_path() / mission;
  config.mission = mission.lexically_normal().string();
  if (const YAML::Node robots = root["robots"]) read_robots(r, robots, config);
  if (const YAML::Node planner = root["planner"]) read_planner(r, planner, config);
  if (const YAML::Node dds = root["dds"]) read_dds(r, dds, config);
  if (const YAML::Node security = root["security"]) read_security(r, security, config);
  if (const YAML::Node timing = root["timing"]) read_timing(r, timing, config);
  return config;
}

planner_core::SolverConfig FleetConfig::solver_config(bool first_plan) const {
  planner_core::SolverConfig config;
  config.solver = first_plan ? solver : replan_solver;
  config.forbid_rotations = true;
  config.pibt.swap = pibt_swap;
  config.lns.stall_iterations = lns_stall_iterations;
  config.seed = static_cast<uint32_t>(seed);
  return config;
}

fleet_transport::TransportConfig FleetConfig::transport_config() const {
  fleet_transport::TransportConfig config;
  config.vendor = fleet_transport::parse_vendor(dds_vendor);
  config.domain_id = domain_id;
  config.lease_s = lease_s;
  config.loopback_config_dir = dds_config_dir;
  config.discovery_servers = discovery_server;
  config.network_interface = network_interface;
  config.peers = peers;
  if (security_required && security_dir.empty()) {
    throw InputError(source + ": security.required is true (these robots are real) but no fleet directory is given "
                     "(security.fleet_dir or --security): " + fleet_transport::kFleetCaHint);
  }
  config.security = fleet_transport::load_fleet_security(security_dir, security_identity);
  fleet_transport::check_discovery_servers(config.vendor, discovery_server, config.security.enabled());
  fleet_transport::check_network(network_interface, peers);
  return config;
}

}  // namespace coordinator
