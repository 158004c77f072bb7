#include "planner_core/instance.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "planner_core/input_file.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/yaml_context.hpp"

namespace planner_core {

namespace fs = std::filesystem;

void Instance::index_tasks() {
  tasks_of_agent.assign(starts.size(), {});
  for (int t = 0; t < task_count(); ++t) {
    for (int a : tasks[t].agents) tasks_of_agent[a].push_back(t);
  }
}

namespace {

Vertex free_vertex(const Graph& graph, Cell cell, const YamlContext& ctx, const YAML::Node& node,
                   const std::string& field) {
  if (!graph.inside(cell)) ctx.fail(node, field, to_string(cell) + " is outside the map");
  const Vertex v = graph.vertex_at(cell);
  if (v == kNoVertex) ctx.fail(node, field, to_string(cell) + " is on a blocked cell");
  return v;
}

// The map a .scen row names: `map` itself when it is a file; else beside the .scen, then in the
// folder `map`.
std::string scen_map_path(const std::string& where, const std::string& map_name, const std::string& scen_path,
                          const std::string& map) {
  std::error_code ec;
  if (!map.empty() && fs::is_regular_file(map, ec)) return map;
  const fs::path beside = fs::path(scen_path).parent_path() / map_name;
  if (fs::exists(beside, ec)) return beside.string();
  if (!map.empty() && fs::exists(fs::path(map) / map_name, ec)) return (fs::path(map) / map_name).string();
  throw InputError(where + ": map '" + map_name + "' is not beside the .scen" +
                   (map.empty() ? std::string(" (give it with --map FILE or --map FOLDER)")
                                : " nor in '" + map + "'"));
}

}  // namespace

Instance load_instance_yaml(const std::string& path) {
  const YAML::Node root = load_yaml_file(path);
  const YamlContext ctx(path);
  ctx.only_keys(root, {"map", "agents", "tasks"}, "top level");
  if (!root["map"] || !root["map"].IsScalar()) ctx.fail(root, "map", "missing or not a file name");
  if (!root["agents"] || !root["agents"].IsSequence()) ctx.fail(root, "agents", "missing or not a list");

  fs::path map_path = root["map"].Scalar();
  if (map_path.is_relative()) map_path = fs::path(path).parent_path() / map_path;
  Instance instance;
  instance.source = path;
  instance.graph = std::make_shared<const Graph>(load_movingai_map(map_path.lexically_normal().string()));
  const Graph& graph = *instance.graph;

  std::map<Vertex, int> start_owner, goal_owner;
  Headings headings;
  const YAML::Node agents = root["agents"];
  for (size_t i = 0; i < agents.size(); ++i) {
    const std::string field = "agents[" + std::to_string(i) + "]";
    const YAML::Node agent = agents[i];
    ctx.only_keys(agent, {"start", "goal", "heading"}, field);
    if (!agent["start"]) ctx.fail(agent, field, "missing 'start'");
    if (!agent["goal"]) ctx.fail(agent, field, "missing 'goal'");
    const Vertex s = free_vertex(graph, ctx.cell(agent["start"], field + ".start"), ctx, agent["start"], field + ".start");
    const Vertex g = free_vertex(graph, ctx.cell(agent["goal"], field + ".goal"), ctx, agent["goal"], field + ".goal");
    if (auto [it, fresh] = start_owner.emplace(s, static_cast<int>(i)); !fresh) {
      ctx.fail(agent["start"], field + ".start", "same start as agent " + std::to_string(it->second));
    }
    if (auto [it, fresh] = goal_owner.emplace(g, static_cast<int>(i)); !fresh) {
      ctx.fail(agent["goal"], field + ".goal", "same goal as agent " + std::to_string(it->second));
    }
    instance.starts.push_back(s);
    instance.goals.push_back(g);
    // The heading at the start, for the rotation model (E when absent).
    std::string letter = "E";
    ctx.read(agent, "heading", field, letter);
    if (letter.size() != 1 || heading_of_letter(letter[0]) < 0) {
      ctx.fail(agent["heading"], field + ".heading", "\"" + cut(letter) + "\" is no heading (E, S, W or N)");
    }
    headings.push_back(heading_of_letter(letter[0]));
  }
  if (std::any_of(headings.begin(), headings.end(), [](int h) { return h != 0; })) {
    instance.start_headings = std::move(headings);
  }

  const YAML::Node tasks = root["tasks"];
  if (tasks && !tasks.IsNull()) {
    if (!tasks.IsSequence()) ctx.fail(tasks, "tasks", "expected a list");
    for (size_t k = 0; k < tasks.size(); ++k) {
      const std::string field = "tasks[" + std::to_string(k) + "]";
      const YAML::Node node = tasks[k];
      ctx.only_keys(node, {"at", "agents"}, field);
      if (!node["at"]) ctx.fail(node, field, "missing 'at'");
      if (!node["agents"] || !node["agents"].IsSequence()) ctx.fail(node, field + ".agents", "missing or not a list");
      Task task;
      task.at = free_vertex(graph, ctx.cell(node["at"], field + ".at"), ctx, node["at"], field + ".at");
      std::set<int> seen;
      for (size_t j = 0; j < node["agents"].size(); ++j) {
        const std::string agent_field = field + ".agents[" + std::to_string(j) + "]";
        const int a = ctx.integer(node["agents"][j], agent_field);
        if (a < 0 || a >= instance.agent_count()) {
          ctx.fail(node["agents"][j], agent_field, "agent " + std::to_string(a) + " does not exist (there are " +
                                                       std::to_string(instance.agent_count()) + " agents)");
        }
        if (seen.insert(a).second) task.agents.push_back(a);
      }
      if (task.agents.empty()) ctx.fail(node["agents"], field + ".agents", "task has no agents");
      instance.tasks.push_back(task);
    }
  }
  instance.index_tasks();
  check_reachability(instance);
  return instance;
}

Instance load_scen(const std::string& path, int agent_count, const std::string& map) {
  require_regular_file(path, "scenario file");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open scenario file");
  Instance instance;
  instance.source = path;
  std::string line;
  int line_no = 0;
  std::set<Vertex> starts, goals;
  while (std::getline(in, line) && (agent_count <= 0 || instance.agent_count() < agent_count)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line.rfind("version", 0) == 0) continue;
    std::istringstream fields(line);
    int bucket, w, h, sx, sy, gx, gy;
    std::string map_name;
    const std::string where = path + ":" + std::to_string(line_no);
    if (!(fields >> bucket >> map_name >> w >> h >> sx >> sy >> gx >> gy)) {
      throw InputError(where + ": expected 'bucket map width height sx sy gx gy length'");
    }
    if (!instance.graph) instance.graph = std::make_shared<const Graph>(load_movingai_map(scen_map_path(where, map_name, path, map)));
    const Vertex s = instance.graph->vertex_at({sx, sy});
    const Vertex g = instance.graph->vertex_at({gx, gy});
    if (s == kNoVertex) throw InputError(where + ": start " + to_string({sx, sy}) + " is outside the map or blocked");
    if (g == kNoVertex) throw InputError(where + ": goal " + to_string({gx, gy}) + " is outside the map or blocked");
    if (!starts.insert(s).second) throw InputError(where + ": duplicate start " + to_string({sx, sy}));
    if (!goals.insert(g).second) throw InputError(where + ": duplicate goal " + to_string({gx, gy}));
    instance.starts.push_back(s);
    instance.goals.push_back(g);
  }
  if (agent_count > 0 && instance.agent_count() < agent_count) {
    throw InputError(path + ": asked for " + std::to_string(agent_count) + " agents, file has " +
                     std::to_string(instance.agent_count()));
  }
  if (instance.agent_count() == 0) throw InputError(path + ": no agents");
  instance.index_tasks();
  check_reachability(instance);
  return instance;
}

Instance load_instance(const std::string& path, int scen_agent_count, const std::string& map) {
  require_regular_file(path, "instance file");
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".scen") return load_scen(path, scen_agent_count, map);
  if (!map.empty()) throw InputError(path + ": --map is for .scen files; a .yaml instance names its own map");
  if (ext == ".yaml" || ext == ".yml") return load_instance_yaml(path);
  throw InputError(path + ": unknown instance type (expected .yaml, .yml or .scen)");
}

void check_reachability(const Instance& instance) {
  const Graph& graph = *instance.graph;
  const std::vector<int> component = connected_parts(graph);
  for (int a = 0; a < instance.agent_count(); ++a) {
    const int home = component[instance.starts[a]];
    if (component[instance.goals[a]] != home) {
      throw InputError(instance.source + ": agents[" + std::to_string(a) + "]: goal " +
                       to_string(graph.cell_of(instance.goals[a])) + " is unreachable from its start " +
                       to_string(graph.cell_of(instance.starts[a])));
    }
    for (int t : instance.tasks_of_agent[a]) {
      if (component[instance.tasks[t].at] != home) {
        throw InputError(instance.source + ": tasks[" + std::to_string(t) + "]: cell " +
                         to_string(graph.cell_of(instance.tasks[t].at)) + " is unreachable for agent " +
                         std::to_string(a) + " from its start " + to_string(graph.cell_of(instance.starts[a])));
      }
    }
  }
}

std::string instance_to_yaml(const Instance& instance, const std::string& map_reference, const std::string& comment) {
  const Graph& graph = *instance.graph;
  const auto put_cell = [](YAML::Emitter& out, Cell cell) {
    out << YAML::Flow << YAML::BeginSeq << cell.x << cell.y << YAML::EndSeq;
  };
  YAML::Emitter out;
  if (!comment.empty()) out << YAML::Comment(comment) << YAML::Newline;
  out << YAML::BeginMap << YAML::Key << "map" << YAML::Value << map_reference;
  out << YAML::Key << "agents" << YAML::Value << YAML::BeginSeq;
  for (int a = 0; a < instance.agent_count(); ++a) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "start" << YAML::Value;
    put_cell(out, graph.cell_of(instance.starts[a]));
    out << YAML::Key << "goal" << YAML::Value;
    put_cell(out, graph.cell_of(instance.goals[a]));
    if (instance.start_heading(a) != 0) {
      out << YAML::Key << "heading" << YAML::Value << std::string(1, heading_letter(instance.start_heading(a)));
    }
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::Key << "tasks" << YAML::Value << YAML::BeginSeq;
  for (const Task& task : instance.tasks) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "at" << YAML::Value;
    put_cell(out, graph.cell_of(task.at));
    out << YAML::Key << "agents" << YAML::Value << YAML::Flow << task.agents << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace planner_core
