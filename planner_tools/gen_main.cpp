// ctsfleet-gen: writes a random CTS-MAPF instance (FORMATS.md YAML) on a MovingAI map.

#include <filesystem>
#include <fstream>
#include <iostream>

#include "ctsfleet/program.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/instance_generator.hpp"

int main(int argc, char** argv) {
  using namespace planner_core;
  namespace fs = std::filesystem;
  ctsfleet::Program program("ctsfleet-gen", "make a CTS-MAPF instance with the distribution of the benchmark suites");
  CLI::App& app = program.app();
  std::string map_path, out_path;
  GeneratorSettings settings;
  app.add_option("--map", map_path, "MovingAI .map file")->required()->check(CLI::ExistingFile);
  app.add_option("-N,--agents", settings.agents, "number of agents")->required()->check(ctsfleet::count_in(1, 1'000'000));
  app.add_option("-M,--tasks", settings.tasks, "number of tasks")->required()->check(ctsfleet::count_in(0, 10'000'000));
  app.add_option("--kmax", settings.kmax, "each task goes to 1..kmax agents")
      ->check(ctsfleet::count_in(1, 1'000'000))
      ->capture_default_str();
  app.add_option("--seed", settings.seed, "random seed")->capture_default_str();
  app.add_option("-o,--output", out_path, "instance file to write (.yaml)")->required()->check(ctsfleet::writable_file());
  return program.main(argc, argv, [&] {
    auto graph = std::make_shared<const Graph>(load_movingai_map(map_path));
    const Instance instance = generate_instance(graph, settings);
    const fs::path out_dir = fs::absolute(out_path).parent_path();
    const std::string map_reference = fs::relative(fs::absolute(map_path), out_dir).string();
    std::ofstream out(out_path);
    if (!out) throw InputError(out_path + ": cannot write");
    out << instance_to_yaml(instance, map_reference,
                            "CTS-MAPF instance: N=" + std::to_string(settings.agents) + " M=" +
                                std::to_string(settings.tasks) + " seed=" + std::to_string(settings.seed) +
                                " kmax=" + std::to_string(settings.kmax) + " map=" + graph->name + ".map");
    std::cout << "wrote " << out_path << "\n";
    return 0;
  });
}
