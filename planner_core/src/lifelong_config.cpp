#include "planner_core/lifelong_config.hpp"

#include <set>

#include "planner_core/input_error.hpp"
#include "planner_core/lifelong_auto_rules.hpp"
#include "planner_core/yaml_context.hpp"

namespace planner_core {

namespace {

const std::set<std::string> kOnOffAuto{"on", "off", "auto"};

// Why `value` is no choice of `choices` ("" when it is one).
std::string not_one_of(const std::string& value, const std::set<std::string>& choices) {
  if (choices.count(value)) return "";
  std::string problem = "\"";
  problem.append(cut(value)).append("\" is not one of ");
  bool first = true;
  for (const std::string& choice : choices) {
    if (!first) problem.append(", ");
    problem.append(choice);
    first = false;
  }
  return problem;
}

std::string out_of_range(int64_t value, int64_t low, int64_t high) {
  if (value >= low && value <= high) return "";
  return std::to_string(value) + " is not in [" + std::to_string(low) + ", " + std::to_string(high) + "]";
}

// Every key with its check: "" when the value is fine, else the problem.
std::vector<std::pair<std::string, std::string>> problems(const LifelongConfig& c) {
  return {
      {"lns", not_one_of(c.lns, kOnOffAuto)},
      {"guidance", not_one_of(c.guidance, {"none", "lanes", "ring", "auto"})},
      {"stay_cost", c.stay_cost == 0 ? "" : out_of_range(c.stay_cost, 1, 6)},
      {"rollouts", out_of_range(c.rollouts, 1, 1'000'000)},
      {"rollout_steps", c.rollout_steps == 0 ? "" : out_of_range(c.rollout_steps, 1, 1000)},
      {"lns_rounds", out_of_range(c.lns_rounds, 0, 1'000'000'000)},
      {"keep_window", not_one_of(c.keep_window, kOnOffAuto)},
      {"keep_equal_cost", not_one_of(c.keep_equal_cost, kOnOffAuto)},
      {"neighbourhoods", not_one_of(c.neighbourhoods, {"nearest", "adaptive", "auto"})},
      {"hold_plans", not_one_of(c.hold_plans, {"never", "half", "always", "auto"})},
      {"park_dead_ends", not_one_of(c.park_dead_ends, kOnOffAuto)},
      {"traffic_costs", not_one_of(c.traffic_costs, kOnOffAuto)},
      {"guide_paths", not_one_of(c.guide_paths, kOnOffAuto)},
  };
}

// An integer key that may also say "auto" (0).
void read_count(const YamlContext& r, const YAML::Node& root, const std::string& key, int64_t& out) {
  const YAML::Node node = root[key];
  if (!node) return;
  if (node.IsScalar() && node.Scalar() == "auto") {
    out = 0;
    return;
  }
  try {
    out = node.as<int64_t>();
  } catch (const YAML::Exception&) {
    r.fail(node, key, "must be a whole number" + std::string(key == "rollouts" || key == "lns_rounds" ? "" : " or auto"));
  }
}

void read_word(const YamlContext& r, const YAML::Node& root, const std::string& key, std::string& out) {
  const YAML::Node node = root[key];
  if (!node) return;
  if (!node.IsScalar()) r.fail(node, key, "must be a word");
  out = node.Scalar();
}

}  // namespace

LifelongConfig load_lifelong_config(const std::string& path) {
  const YAML::Node root = load_yaml_file(path);
  const YamlContext r(path);
  LifelongConfig config;
  if (!root || root.IsNull()) return config;  // an empty file: every default
  if (!root.IsMap()) r.fail(root, "top level", "must be a map of settings (docs/ARCHITECTURE.md, lifelong settings)");
  r.only_keys(root,
              {"lns", "guidance", "stay_cost", "rollouts", "rollout_steps", "lns_rounds", "keep_window",
               "keep_equal_cost", "neighbourhoods", "hold_plans", "keep_targets", "park_dead_ends", "traffic_costs",
               "guide_paths"},
              "top level");
  int64_t stay_cost = config.stay_cost, rollouts = config.rollouts, rollout_steps = config.rollout_steps;
  for (const auto& [key, out] : {std::pair{"stay_cost", &stay_cost}, {"rollouts", &rollouts},
                                 {"rollout_steps", &rollout_steps}, {"lns_rounds", &config.lns_rounds}}) {
    read_count(r, root, key, *out);
  }
  for (const auto& [key, out] : {std::pair{"lns", &config.lns}, {"guidance", &config.guidance},
                                 {"keep_window", &config.keep_window}, {"keep_equal_cost", &config.keep_equal_cost},
                                 {"neighbourhoods", &config.neighbourhoods}, {"hold_plans", &config.hold_plans},
                                 {"park_dead_ends", &config.park_dead_ends}, {"traffic_costs", &config.traffic_costs},
                                 {"guide_paths", &config.guide_paths}}) {
    read_word(r, root, key, *out);
  }
  if (const YAML::Node node = root["keep_targets"]) {
    try {
      config.keep_targets = node.as<bool>();
    } catch (const YAML::Exception&) {
      r.fail(node, "keep_targets", "must be true or false");
    }
  }
  // Out of int's range fails as out of range, not as a wrapped number.
  const auto narrow = [](int64_t v) { return static_cast<int>(std::max<int64_t>(-1, std::min<int64_t>(v, 1 << 30))); };
  config.stay_cost = narrow(stay_cost);
  config.rollouts = narrow(rollouts);
  config.rollout_steps = narrow(rollout_steps);
  for (const auto& [key, problem] : problems(config)) {
    if (!problem.empty()) r.fail(root[key], key, problem);
  }
  return config;
}

void check_lifelong_config(const LifelongConfig& config, const std::string& what) {
  for (const auto& [key, problem] : problems(config)) {
    if (!problem.empty()) throw InputError(what + ": " + key + ": " + problem);
  }
}

PibtLifelongSettings settle_lifelong_config(const LifelongConfig& config, const Graph& graph, size_t agents,
                                            ActionModel actions) {
  check_lifelong_config(config, "lifelong settings");
  const auto on = [](const std::string& choice, bool automatic) { return choice == "auto" ? automatic : choice == "on"; };
  PibtLifelongSettings settings;
  settings.actions = actions;
  settings.lns = on(config.lns, lifelong_lns(graph, agents, actions));
  settings.guidance = config.guidance == "auto" ? lifelong_guidance(graph, agents, settings.lns, actions)
                                                : parse_guidance(config.guidance, "guidance");
  settings.stay_cost = config.stay_cost > 0 ? config.stay_cost : lifelong_stay_cost(settings.guidance, settings.lns, actions);
  settings.rollouts = config.rollouts;
  const LifelongWindow window = lifelong_window(graph, agents, actions);
  settings.rollout_steps = config.rollout_steps > 0 ? config.rollout_steps
                           : settings.lns          ? window.steps
                                                   : lifelong_rollout_steps(graph, agents, actions);
  settings.keep_window = settings.lns && on(config.keep_window, window.kept);
  settings.lns_keeps_equal_cost = settings.lns && on(config.keep_equal_cost, window.equal_cost_kept);
  const bool adaptive = config.neighbourhoods == "auto" ? window.adaptive_neighbourhoods : config.neighbourhoods == "adaptive";
  settings.lns_neighbourhoods = settings.lns && adaptive ? WindowLns::Neighbourhoods::kAdaptive : WindowLns::Neighbourhoods::kNearest;
  settings.lns_rounds = config.lns_rounds;
  settings.hold_plans = config.hold_plans == "auto" ? lifelong_plan_holding(graph, agents)
                                                    : parse_plan_holding(config.hold_plans, "hold_plans");
  settings.keep_targets = config.keep_targets;
  settings.park_dead_end_errands = on(config.park_dead_ends, lifelong_parks_dead_ends(graph, agents));
  settings.traffic = lifelong_traffic(graph, agents, settings.guidance);
  if (config.traffic_costs != "auto") settings.traffic.on = config.traffic_costs == "on";
  // Guide paths: auto is off. Rotation model, 0.3 s per step: without LNS they hold CITY-02's rate
  // up (1,500 steps: 22,509 errands against 19,239, flat from step 500 on), but LNS over lanes
  // finishes more there (23,751), and on CITY-01 (1,000 steps) they cost (8,799 against 10,262).
  settings.guide_paths.on = config.guide_paths == "on";
  return settings;
}

}  // namespace planner_core
