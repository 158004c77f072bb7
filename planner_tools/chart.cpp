#include "chart.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdio>
#include <exception>
#include <filesystem>

#include "ctsfleet/data_dir.hpp"

extern char** environ;

namespace ctsfleet_bench {

namespace fs = std::filesystem;

// Draws a chart with ctsfleet-plot (matplotlib) beside this program; a missing plotter or
// matplotlib only costs the picture (the tables and CSV are the results), so it is a warning.
void draw_chart(const std::vector<std::string>& arguments) {
  fs::path plotter;
  try {
    plotter = ctsfleet::program_dir() / "ctsfleet-plot";
  } catch (const std::exception& e) {  // e.g. this program's file was replaced while it ran
    std::fprintf(stderr, "warning: %s: chart not drawn\n", e.what());
    return;
  }
  std::vector<std::string> argv = {plotter.string()};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  std::vector<char*> raw;
  for (std::string& argument : argv) raw.push_back(argument.data());
  raw.push_back(nullptr);
  pid_t pid = -1;
  if (!fs::exists(plotter) || posix_spawn(&pid, raw[0], nullptr, nullptr, raw.data(), environ) != 0) {
    std::fprintf(stderr, "warning: %s not found: chart not drawn\n", plotter.c_str());
    return;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "warning: %s %s failed: chart not drawn\n", plotter.c_str(), arguments.front().c_str());
  }
}

}  // namespace ctsfleet_bench
