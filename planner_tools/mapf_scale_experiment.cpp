#include "mapf_scale_experiment.hpp"

#include "planner_core/benchmark_runner.hpp"

#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace ctsfleet_bench {

namespace fs = std::filesystem;

namespace {

// Ctrl-C or SIGTERM: passed on to the running ctsfleet-solve (which then returns at once with its
// best plan), and no further instance is started.
std::atomic<pid_t> g_child{0};
std::atomic<bool> g_stop{false};
extern "C" void forward_signal(int signal_number) {
  g_stop = true;
  const pid_t child = g_child;
  if (child > 0) kill(child, signal_number);
}

struct Improvement {
  double time_ms;
  double flowtime;
};

struct Run {
  nlohmann::json summary = nlohmann::json::object();  // ctsfleet-solve --json's summary
  std::vector<Improvement> improvements;              // its "improvements" list
  double wall_s = 0;
  double peak_mb = 0;
  int exit_code = -1;
};

// Runs `argv` with its standard output (ctsfleet-solve's JSON summary) captured; its log stays on
// stderr. The child's own peak memory comes from wait4.
Run run_child(const std::vector<std::string>& argv) {
  Run run;
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) return run;
  const auto started = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(pipe_fds[1], STDOUT_FILENO);
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    std::vector<char*> args;
    for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  close(pipe_fds[1]);
  g_child = pid;
  if (g_stop) kill(pid, SIGTERM);  // a signal that came before the child was known
  std::string output;
  std::array<char, 4096> buffer;
  for (ssize_t got; (got = read(pipe_fds[0], buffer.data(), buffer.size())) != 0;) {
    if (got < 0) {
      if (errno == EINTR) continue;
      break;
    }
    output.append(buffer.data(), got);
  }
  close(pipe_fds[0]);
  int status = 0;
  rusage usage{};
  while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  g_child = 0;
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  run.peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.summary = nlohmann::json::parse(output, nullptr, /*allow_exceptions=*/false);
  if (!run.summary.is_object()) run.summary = nlohmann::json::object();
  for (const nlohmann::json& improvement : run.summary.value("improvements", nlohmann::json::array())) {
    run.improvements.push_back({improvement.value("time_ms", 0.0), improvement.value("flowtime", 0.0)});
  }
  return run;
}

// The best flowtime found by `time_ms`, or -1 before the first plan.
double flowtime_at(const Run& run, double time_ms) {
  double best = -1;
  for (const Improvement& improvement : run.improvements) {
    if (improvement.time_ms <= time_ms) best = improvement.flowtime;
  }
  return best;
}

double number(const Run& run, const std::string& key) {
  const auto it = run.summary.find(key);
  if (it == run.summary.end()) return -1;
  if (it->is_boolean()) return it->get<bool>() ? 1 : 0;
  return it->is_number() ? it->get<double>() : -1;
}

}  // namespace

int run_mapf_scale(const MapfScaleSettings& settings) {
  const fs::path solve = fs::read_symlink("/proc/self/exe").parent_path() / "ctsfleet-solve";
  if (!fs::exists(solve)) {
    std::fprintf(stderr, "error: %s not found (build ctsfleet-solve)\n", solve.c_str());
    return 2;
  }
  std::error_code error;
  std::vector<fs::path> instances;
  for (const auto& entry : fs::directory_iterator(settings.suite, error)) {
    if (entry.path().extension() == ".yaml") instances.push_back(entry.path());
  }
  if (error || instances.empty()) {
    std::fprintf(stderr, "error: %s: no instances (run from the repository root, or give --scale-suite)\n",
                 settings.suite.c_str());
    return 2;
  }
  // By map, then by size.
  const auto agents_of = [](const fs::path& p) {
    const std::string stem = p.stem().string();
    return std::atoi(stem.substr(stem.rfind("-N") + 2).c_str());
  };
  std::sort(instances.begin(), instances.end(), [&](const fs::path& a, const fs::path& b) {
    const std::string map_a = a.stem().string().substr(0, a.stem().string().rfind("-N"));
    const std::string map_b = b.stem().string().substr(0, b.stem().string().rfind("-N"));
    return map_a != map_b ? map_a < map_b : agents_of(a) < agents_of(b);
  });
  fs::create_directories(settings.out_dir, error);
  const fs::path csv_path = fs::path(settings.out_dir) / "mapf-scale.csv";
  std::ofstream csv(csv_path);
  if (!csv) {
    std::fprintf(stderr, "error: %s: cannot write\n", csv_path.c_str());
    return 2;
  }
  csv << "instance,solver,agents,limit_s,solved,first_plan_ms,preprocessing_ms,sum_of_costs,lower_bound,ratio,"
         "ratio_every_10s,solver_returned_s,wall_s,overshoot_percent,peak_mb\n";
  std::ostringstream md;
  md << "| instance | solver | limit (s) | first plan (ms, from start) | preprocessing (ms) | sum of costs / lower bound"
        " at the limit | ... at 10 s, 20 s, ... | solver returned (s) | process wall (s) | wall over the limit |"
        " peak memory (MB) |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::printf("%s", md.str().c_str());
  struct sigaction forward {};
  forward.sa_handler = forward_signal;
  sigaction(SIGINT, &forward, nullptr);
  sigaction(SIGTERM, &forward, nullptr);
  const fs::path scratch = fs::temp_directory_path() / ("ctsfleet-mapf-scale-" + std::to_string(getpid()) + ".txt");
  for (const fs::path& instance : instances) {
    for (const std::string& solver : settings.solvers) {
      if (g_stop) break;
      std::ostringstream limit;
      limit << settings.seconds;
      const Run run = run_child({solve.string(), "-i", instance.string(), "--solver", solver, "-t", limit.str(),
                                 "--swap", "--seed", std::to_string(settings.seed), "--iterations",
                                 std::to_string(settings.iterations), "-o", scratch.string(), "--json"});
      const bool solved = number(run, "solved") == 1;
      const double over = 100.0 * (run.wall_s - settings.seconds) / settings.seconds;
      // How the gap to the lower bound closes: the best plan's ratio every 10 s before the limit.
      std::string trajectory;
      const double lower_bound = number(run, "lower_bound");
      for (double at_s = 10; at_s < settings.seconds - 1e-9; at_s += 10) {
        const double flow = flowtime_at(run, at_s * 1000);
        char ratio[32];
        std::snprintf(ratio, sizeof ratio, "%s%.3f", trajectory.empty() ? "" : " ", flow / lower_bound);
        trajectory += flow > 0 && lower_bound > 0 ? ratio : (trajectory.empty() ? "-" : " -");
      }
      if (trajectory.empty()) trajectory = "-";
      char line[640];
      // The solver's own return (its comp_time, from the process's start) and the process's whole
      // life, which adds writing the solution file and freeing memory.
      const double returned_s = number(run, "comp_time_ms") / 1000;
      char ratio_text[32];
      std::snprintf(ratio_text, sizeof ratio_text, "%.3f", number(run, "ratio"));
      std::snprintf(line, sizeof line, "| %s | %s | %g | %s | %.0f | %s | %s | %.2f | %.2f | %+.1f%% | %.0f |\n",
                    instance.stem().c_str(), solver.c_str(), settings.seconds,
                    solved ? std::to_string(static_cast<long>(number(run, "first_ms"))).c_str() : "none",
                    number(run, "preprocessing_ms"), solved ? ratio_text : "-", trajectory.c_str(),
                    returned_s, run.wall_s, over, run.peak_mb);
      md << line;
      std::printf("%s", line);
      std::fflush(stdout);
      csv << planner_core::csv_field(instance.stem().string()) << "," << solver << "," << agents_of(instance) << "," << settings.seconds << ","
          << (solved ? 1 : 0) << "," << number(run, "first_ms") << "," << number(run, "preprocessing_ms") << ","
          << number(run, "flowtime") << "," << number(run, "lower_bound") << "," << number(run, "ratio") << ",\""
          << trajectory << "\"," << returned_s << "," << run.wall_s << "," << over << "," << run.peak_mb << "\n";
    }
  }
  fs::remove(scratch, error);
  if (g_stop) {
    std::fprintf(stderr, "interrupted: the table holds the runs finished so far\n");
    std::ofstream(fs::path(settings.out_dir) / "mapf-scale.md") << md.str();
    return 130;
  }
  std::ofstream(fs::path(settings.out_dir) / "mapf-scale.md") << md.str();
  std::printf("written: %s/mapf-scale.{md,csv}\n", settings.out_dir.c_str());
  return 0;
}

}  // namespace ctsfleet_bench
