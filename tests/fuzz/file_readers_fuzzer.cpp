// libFuzzer target for every reader of a user's file (run by scripts/fuzz-readers): the reader
// named by CTSFLEET_FUZZ_READER reads the input as its file. Refusing it with
// planner_core::InputError (exit 2 in the programs) is the only allowed failure: any other
// exception (exit 1 with no file or field named), a crash, a sanitizer report or a hang is a bug.
//
//   instance  a CTS-MAPF instance (.yaml; its map, default/maze-32-32-2.map, beside it)
//   map       a MovingAI map
//   scen      a MovingAI scenario (first 10 rows; the maze map given as --map)
//   solution  a ctsfleet-solve solution, read against the maze map
//   fleet     a fleet config (its mission, default/mission-8.yaml, beside it)
//   mat       a toio mat calibration
//   history   a dashboard history (JSON Lines)
//   journal   a coordinator's mission journal (SQLite)
//
// With CTSFLEET_FUZZ_MAKE_JOURNAL=FILE it writes a small valid journal there (the journal's seed
// corpus) and exits.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <system_error>

#include "coordinator/fleet_config.hpp"
#include "coordinator/mission_journal.hpp"
#include "dashboard/history.hpp"
#include "planner_core/graph.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/instance.hpp"
#include "planner_core/solution.hpp"
#include "robot_agent/mat_calibration.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path& work_dir() {
  static const fs::path dir = fs::temp_directory_path() / ("ctsfleet-fuzz-" + std::to_string(::getpid()));
  return dir;
}

struct Reader {
  std::string file;  // where the input is written, under work_dir()
  std::function<void(const std::string& path)> read;
};

const planner_core::Graph& maze() {
  static const planner_core::Graph graph = planner_core::load_movingai_map((work_dir() / "default/maze-32-32-2.map").string());
  return graph;
}

const std::map<std::string, Reader>& readers() {
  static const std::map<std::string, Reader> all = {
      {"instance", {"default/input.yaml", [](const std::string& p) { planner_core::load_instance(p); }}},
      {"map", {"input.map", [](const std::string& p) { planner_core::load_movingai_map(p); }}},
      {"scen", {"input.scen",
                [](const std::string& p) {
                  planner_core::load_scen(p, 10, (work_dir() / "default/maze-32-32-2.map").string());
                }}},
      {"solution", {"input.txt", [](const std::string& p) { planner_core::read_solution(p, maze()); }}},
      {"fleet", {"input-fleet.yaml", [](const std::string& p) { coordinator::load_fleet_config(p); }}},
      {"mat", {"input-mat.yaml", [](const std::string& p) { robot_agent::MatCalibration::load(p); }}},
      {"history", {"input.jsonl", [](const std::string& p) { dashboard::load_history(p); }}},
      {"journal", {"input.journal",
                   [](const std::string& p) {
                     fs::remove(p + "-wal");
                     fs::remove(p + "-shm");
                     coordinator::MissionJournal journal(p, "fuzz", "fuzz mission");
                   }}},
  };
  return all;
}

const Reader* chosen = nullptr;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fs::create_directories(work_dir() / "default");
  // A run that ends (libFuzzer exits when its runs or time are done) leaves no directory in /tmp; a
  // crash skips this, and the directory stays beside the input libFuzzer saved.
  std::atexit([] {
    std::error_code ignored;
    fs::remove_all(work_dir(), ignored);
  });
  for (const char* name : {"maze-32-32-2.map", "mission-8.yaml"}) {
    fs::copy_file(fs::path(CTSFLEET_SOURCE_DIR) / "config/default" / name, work_dir() / "default" / name,
                  fs::copy_options::overwrite_existing);
  }
  if (const char* seed = std::getenv("CTSFLEET_FUZZ_MAKE_JOURNAL")) {
    coordinator::MissionJournal journal(seed, "fuzz", "fuzz mission");
    journal.claim(1, 0x11, 1000);
    journal.record_binding(0, "robot0");
    journal.record_epoch(1, 1);
    journal.record_visit({3, 0}, "robot0", 1);
    journal.record_task_added(16, 4, 2, 1, "request-1");
    journal.record_task_cancelled(16, "request-2");
    std::exit(0);
  }
  const char* name = std::getenv("CTSFLEET_FUZZ_READER");
  const auto found = name ? readers().find(name) : readers().end();
  if (found == readers().end()) {
    std::cerr << "CTSFLEET_FUZZ_READER must name a reader: instance map scen solution fleet mat history journal\n";
    std::exit(2);
  }
  chosen = &found->second;
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = (work_dir() / chosen->file).string();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    chosen->read(path);
  } catch (const planner_core::InputError&) {
    // Refused with a message naming the file: what every reader must do with a bad file.
  } catch (const std::exception& e) {
    std::cerr << "not an InputError (a program would exit 1 without naming the file): " << e.what() << "\n";
    std::abort();
  }
  return 0;
}
