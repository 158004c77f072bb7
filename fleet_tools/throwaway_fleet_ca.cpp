#include "throwaway_fleet_ca.hpp"

#include <sys/wait.h>

#include <stdexcept>

#include "child_process.hpp"

namespace coordinator {

namespace fs = std::filesystem;

void make_throwaway_fleet_ca(const fs::path& program_dir, const fs::path& dir, const std::vector<std::string>& robots) {
  const std::string tool = (program_dir / "ctsfleet-ca").string();
  const std::string log = (dir.parent_path() / "fleet-ca.log").string();
  fs::remove_all(dir);
  const auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), tool);
    int status = 0;
    waitpid(start_child(args, log), &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      throw std::runtime_error("making the throw-away fleet CA failed: '" + args[1] + "' (see " + log + ")");
    }
  };
  run({"init", dir.string(), "--days", "2"});
  run({"add-coordinator", dir.string(), "coordinator", "--days", "1"});
  run({"add-observer", dir.string(), "monitor", "--days", "1"});
  run({"add-operator", dir.string(), "dashboard", "--days", "1"});
  run({"add-operator", dir.string(), "operator", "--days", "1"});
  for (const std::string& robot : robots) run({"add-robot", dir.string(), robot, "--days", "1"});
}

}  // namespace coordinator
