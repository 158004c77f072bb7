#include <gtest/gtest.h>

#include "planner_core/input_error.hpp"
#include "planner_core/instance.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

using testing::write_temp_file;

const char* kSmallMap =
    "type octile\nheight 3\nwidth 5\nmap\n"
    "..@..\n"
    "..@..\n"
    ".....\n";

// Writes the small map and an instance YAML beside it; returns the YAML path.
std::string instance_file(const std::string& name, const std::string& yaml) {
  write_temp_file("inst/small.map", kSmallMap);
  return write_temp_file("inst/" + name + ".yaml", yaml);
}

// The error must mention every fragment (file, line or field, problem).
void expect_input_error(const std::string& path, const std::vector<std::string>& fragments) {
  try {
    load_instance(path);
    FAIL() << "expected InputError for " << path;
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const std::string& fragment : fragments) {
      EXPECT_NE(message.find(fragment), std::string::npos) << "'" << fragment << "' missing in: " << message;
    }
  }
}

TEST(Graph, LoadsMovingAiMapWithDenseIdsAndNeighbours) {
  const Graph graph = load_movingai_map(testing::data_path("maps/maze-32-32-2.map"));
  EXPECT_EQ(graph.width(), 32);
  EXPECT_EQ(graph.height(), 32);
  EXPECT_EQ(graph.name, "maze-32-32-2");
  for (Vertex v = 0; v < graph.vertex_count(); ++v) {
    EXPECT_EQ(graph.vertex_at(graph.cell_of(v)), v);
    EXPECT_LE(static_cast<int>(graph.neighbours(v).size()), kMaxDegree);
    for (Vertex u : graph.neighbours(v)) EXPECT_TRUE(graph.adjacent(u, v));
  }
}

TEST(Graph, WallsKeepVertexIdsAndCutEveryEdgeToTheWall) {
  const Graph graph(3, 2, {"...", "..."});
  const Vertex middle = graph.vertex_at({1, 0});
  const Graph walled = graph.with_walls({middle});
  ASSERT_EQ(walled.vertex_count(), graph.vertex_count());
  for (Vertex v = 0; v < graph.vertex_count(); ++v) EXPECT_EQ(walled.cell_of(v), graph.cell_of(v));
  EXPECT_FALSE(walled.is_open(middle));
  EXPECT_FALSE(walled.is_free({1, 0}));
  EXPECT_EQ(walled.vertex_at({1, 0}), kNoVertex);
  EXPECT_TRUE(walled.neighbours(middle).empty());
  for (Vertex v = 0; v < walled.vertex_count(); ++v) EXPECT_FALSE(walled.adjacent(v, middle));
  EXPECT_EQ(walled.rows()[0], ".@.");
  EXPECT_TRUE(graph.is_open(middle));  // the original is untouched
  EXPECT_EQ(graph.neighbours(middle).size(), 3u);
  EXPECT_FALSE(walled.is_open(-1));
  EXPECT_FALSE(walled.is_open(graph.vertex_count()));
  EXPECT_THROW(graph.with_walls({graph.vertex_count()}), std::out_of_range);
}

TEST(Graph, RejectsUnknownSymbolWithLineAndColumn) {
  const std::string path = write_temp_file("bad-symbol.map", "type octile\nheight 2\nwidth 3\nmap\n...\n.x.\n");
  try {
    load_movingai_map(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad-symbol.map:6"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'x'"), std::string::npos) << e.what();
  }
}

TEST(Graph, RejectsShortMap) {
  const std::string path = write_temp_file("short.map", "type octile\nheight 3\nwidth 3\nmap\n...\n...\n");
  EXPECT_THROW(load_movingai_map(path), InputError);
}

TEST(Instance, LoadsYamlWithTasksSharedByAgents) {
  const Instance instance = load_instance(instance_file("ok",
                                                        "map: small.map\n"
                                                        "agents:\n"
                                                        "  - {start: [0, 0], goal: [4, 0]}\n"
                                                        "  - {start: [1, 0], goal: [3, 0]}\n"
                                                        "tasks:\n"
                                                        "  - {at: [2, 2], agents: [0, 1]}\n"
                                                        "  - {at: [0, 2], agents: [1]}\n"));
  EXPECT_EQ(instance.agent_count(), 2);
  EXPECT_EQ(instance.task_count(), 2);
  EXPECT_EQ(instance.tasks_of_agent[0], std::vector<int>({0}));
  EXPECT_EQ(instance.tasks_of_agent[1], std::vector<int>({0, 1}));
  EXPECT_EQ(instance.graph->cell_of(instance.goals[0]), (Cell{4, 0}));
}

TEST(Instance, LoadsBenchmarkInstance) {
  const Instance instance = load_instance(testing::data_path("instances/maze-32-32-2-N50-M60-00.yaml"));
  EXPECT_EQ(instance.agent_count(), 50);
  EXPECT_EQ(instance.task_count(), 60);
}

TEST(InstanceErrors, MissingFile) { expect_input_error("/nonexistent/x.yaml", {"/nonexistent/x.yaml", "no such file"}); }

TEST(InstanceErrors, MalformedYaml) {
  expect_input_error(instance_file("malformed", "map: small.map\nagents: [\n  - {start: [0, 0]\n"),
                     {"malformed.yaml", "malformed YAML"});
}

TEST(InstanceErrors, UnknownKey) {
  expect_input_error(instance_file("unknown-key", "map: small.map\nagents:\n  - {start: [0, 0], goal: [4, 0], speed: 2}\n"),
                     {"unknown-key.yaml:3", "agents[0]", "unknown key 'speed'"});
}

TEST(InstanceErrors, WrongType) {
  expect_input_error(instance_file("wrong-type", "map: small.map\nagents:\n  - {start: [zero, 0], goal: [4, 0]}\n"),
                     {"wrong-type.yaml:3", "agents[0].start[0]", "expected an integer"});
}

TEST(InstanceErrors, NumbersPastTheirTypeAreRefusedNotWrapped) {
  expect_input_error(instance_file("wrap", "map: small.map\nagents:\n  - {start: [4294967296, 0], goal: [4, 0]}\n"),
                     {"wrap.yaml:3", "4294967296", "out of range"});
  expect_input_error(instance_file("wrap-task", "map: small.map\nagents:\n  - {start: [0, 0], goal: [4, 0]}\n"
                                                "tasks:\n  - {at: [1, 0], agents: [4294967296]}\n"),
                     {"wrap-task.yaml:5", "out of range"});
  const std::string long_value(10'000, '9');
  try {
    load_instance(instance_file("long", "map: small.map\nagents:\n  - {start: [" + long_value + ", 0], goal: [4, 0]}\n"));
    FAIL() << "a 10,000-digit coordinate was accepted";
  } catch (const InputError& e) {
    EXPECT_LT(std::string(e.what()).size(), 400u) << "the error echoes the whole value";
  }
}

TEST(InstanceErrors, DuplicateAndNonScalarKeysAreRefused) {
  expect_input_error(instance_file("twice", "map: small.map\nmap: other.map\nagents:\n  - {start: [0, 0], goal: [4, 0]}\n"),
                     {"twice.yaml:2", "key 'map' given twice"});
  expect_input_error(instance_file("list-key", "? [a, b]\n: 1\nmap: small.map\nagents: []\n"),
                     {"list-key.yaml:1", "not a plain word"});
}

TEST(InstanceErrors, MissingMapFile) {
  expect_input_error(instance_file("no-map", "map: nowhere.map\nagents:\n  - {start: [0, 0], goal: [4, 0]}\n"),
                     {"nowhere.map", "cannot open"});
}

TEST(InstanceErrors, StartOnWall) {
  expect_input_error(instance_file("start-wall", "map: small.map\nagents:\n  - {start: [2, 0], goal: [4, 0]}\n"),
                     {"start-wall.yaml:3", "agents[0].start", "(2,0) is on a blocked cell"});
}

TEST(InstanceErrors, GoalOutsideMap) {
  expect_input_error(instance_file("goal-out", "map: small.map\nagents:\n  - {start: [0, 0], goal: [9, 0]}\n"),
                     {"agents[0].goal", "outside the map"});
}

TEST(InstanceErrors, TaskOnWall) {
  expect_input_error(instance_file("task-wall", "map: small.map\nagents:\n  - {start: [0, 0], goal: [4, 0]}\n"
                                                "tasks:\n  - {at: [2, 1], agents: [0]}\n"),
                     {"task-wall.yaml:5", "tasks[0].at", "blocked"});
}

TEST(InstanceErrors, DuplicateStarts) {
  expect_input_error(instance_file("dup-start", "map: small.map\nagents:\n  - {start: [0, 0], goal: [4, 0]}\n"
                                                "  - {start: [0, 0], goal: [3, 0]}\n"),
                     {"agents[1].start", "same start as agent 0"});
}

TEST(InstanceErrors, DuplicateGoals) {
  expect_input_error(instance_file("dup-goal", "map: small.map\nagents:\n  - {start: [0, 0], goal: [4, 0]}\n"
                                               "  - {start: [1, 0], goal: [4, 0]}\n"),
                     {"agents[1].goal", "same goal as agent 0"});
}

TEST(InstanceErrors, TaskNamesMissingAgent) {
  expect_input_error(instance_file("ghost-agent", "map: small.map\nagents:\n  - {start: [0, 0], goal: [4, 0]}\n"
                                                  "tasks:\n  - {at: [2, 2], agents: [0, 7]}\n"),
                     {"tasks[0].agents[1]", "agent 7 does not exist"});
}

TEST(InstanceErrors, TaskWithNoAgents) {
  expect_input_error(instance_file("no-agents", "map: small.map\nagents:\n  - {start: [0, 0], goal: [4, 0]}\n"
                                                "tasks:\n  - {at: [2, 2], agents: []}\n"),
                     {"tasks[0].agents", "task has no agents"});
}

TEST(InstanceErrors, UnreachableTaskNamesAgentAndTask) {
  write_temp_file("inst/split.map", "type octile\nheight 2\nwidth 5\nmap\n..@..\n..@..\n");
  expect_input_error(write_temp_file("inst/unreachable.yaml", "map: split.map\nagents:\n"
                                                              "  - {start: [0, 0], goal: [1, 1]}\n"
                                                              "tasks:\n  - {at: [4, 1], agents: [0]}\n"),
                     {"tasks[0]", "unreachable for agent 0"});
}

TEST(InstanceErrors, UnreachableGoal) {
  write_temp_file("inst/split.map", "type octile\nheight 2\nwidth 5\nmap\n..@..\n..@..\n");
  expect_input_error(write_temp_file("inst/unreachable-goal.yaml",
                                     "map: split.map\nagents:\n  - {start: [0, 0], goal: [4, 0]}\n"),
                     {"agents[0]", "goal (4,0) is unreachable"});
}

TEST(Scen, ReadsFirstRowsAsTasklessInstance) {
  write_temp_file("scen/small.map", kSmallMap);
  const std::string path = write_temp_file("scen/small.scen",
                                           "version 1\n0\tsmall.map\t5\t3\t0\t0\t4\t0\t6\n"
                                           "0\tsmall.map\t5\t3\t1\t0\t3\t0\t4\n"
                                           "0\tsmall.map\t5\t3\t0\t2\t4\t2\t4\n");
  const Instance instance = load_instance(path, 2);
  EXPECT_EQ(instance.agent_count(), 2);
  EXPECT_EQ(instance.task_count(), 0);
  EXPECT_THROW(load_instance(path, 5), InputError);
}

TEST(Scen, StartOnWallNamesLine) {
  write_temp_file("scen/small.map", kSmallMap);
  const std::string path = write_temp_file("scen/wall.scen", "version 1\n0\tsmall.map\t5\t3\t2\t0\t4\t0\t6\n");
  try {
    load_instance(path, 1);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("wall.scen:2"), std::string::npos) << e.what();
  }
}

TEST(Instance, YamlRoundTrip) {
  const Instance original = load_instance(testing::data_path("instances/random-32-32-20-N10-M30-00.yaml"));
  const std::string map = std::string(CTSFLEET_TEST_DATA) + "/maps/random-32-32-20.map";
  const Instance copy = load_instance(write_temp_file("roundtrip.yaml", instance_to_yaml(original, map)));
  EXPECT_EQ(copy.starts, original.starts);
  EXPECT_EQ(copy.goals, original.goals);
  ASSERT_EQ(copy.task_count(), original.task_count());
  for (int t = 0; t < copy.task_count(); ++t) {
    EXPECT_EQ(copy.tasks[t].at, original.tasks[t].at);
    EXPECT_EQ(copy.tasks[t].agents, original.tasks[t].agents);
  }
}

}  // namespace
}  // namespace planner_core
