#include "planner_core/benchmark_runner.hpp"

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <regex>
#include <sstream>
#include <thread>

#include "planner_core/validator.hpp"

namespace planner_core {

namespace {

struct Setting {
  std::string map;
  int agents = 0;
  int tasks = 0;
  bool operator<(const Setting& o) const { return std::tie(map, agents, tasks) < std::tie(o.map, o.agents, o.tasks); }
};

// "<map>-N<n>-M<m>-<index>.yaml" as in FORMATS.md; other names form a setting of their own.
Setting setting_of(const std::string& file) {
  static const std::regex pattern(R"(^(.*)-N(\d+)-M(\d+)-\d+$)");
  const std::string stem = std::filesystem::path(file).stem().string();
  std::smatch match;
  if (std::regex_match(stem, match, pattern)) return {match[1], std::stoi(match[2]), std::stoi(match[3])};
  return {stem, 0, 0};
}

BenchmarkRow run_one(const std::string& file, const SolverConfig& config, double seconds, int64_t iterations,
                     ActionModel actions, const std::atomic<bool>* interrupt) {
  BenchmarkRow row;
  row.file = file;
  const Setting setting = setting_of(file);
  row.map = setting.map;
  try {
    // As ctsfleet-solve: the limit and the times count from before the instance is read.
    const SolveOptions options{Deadline::for_limits(seconds, iterations, interrupt), {}, Clock::now()};
    Instance instance = load_instance(file);
    instance.actions = actions;
    row.map = instance.graph->name;
    row.agents = instance.agent_count();
    row.tasks = instance.task_count();
    const SolveResult result = make_solver(config)->solve(instance, options);
    row.comp_time_ms = result.comp_time_ms;
    row.first_solution_ms = result.first_solution_ms;
    row.lower_bound = result.lower_bound;
    row.sequences = result.sequences_tried;
    if (result.solved) {
      const ValidationReport report =
          validate(instance, result.solution, ValidationOptions{config.forbid_rotations}, result.headings);
      if (!report.ok()) {
        row.error = "invalid plan: " + report.violations.front().message;
      } else {
        row.solved = true;
        row.flowtime = report.flowtime;
        row.makespan = report.makespan;
        row.ratio = row.lower_bound > 0 ? static_cast<double>(row.flowtime) / row.lower_bound : 0;
      }
    }
  } catch (const std::exception& e) {
    row.error = e.what();
  }
  return row;
}

}  // namespace

std::vector<std::string> sample_per_setting(std::vector<std::string> files, int per_setting) {
  std::sort(files.begin(), files.end());
  if (per_setting <= 0) return files;
  std::map<Setting, int> taken;
  std::vector<std::string> kept;
  for (const std::string& file : files) {
    if (taken[setting_of(file)]++ < per_setting) kept.push_back(file);
  }
  return kept;
}

std::vector<BenchmarkRow> run_benchmark(const std::vector<std::string>& files, const SolverConfig& config,
                                        double seconds, int64_t iterations, int threads,
                                        const std::function<void(const BenchmarkRow&, int done)>& on_row,
                                        ActionModel actions, const std::atomic<bool>* interrupt) {
  std::vector<BenchmarkRow> rows(files.size());
  std::atomic<size_t> next{0};
  std::mutex report;
  int done = 0;
  const auto worker = [&] {
    for (size_t i = next++; i < files.size(); i = next++) {
      if (interrupt && interrupt->load()) {  // stopped: the instances left are not run
        rows[i].file = files[i];
        rows[i].error = "not run: interrupted";
        continue;
      }
      rows[i] = run_one(files[i], config, seconds, iterations, actions, interrupt);
      const std::lock_guard<std::mutex> lock(report);
      ++done;
      if (on_row) on_row(rows[i], done);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < std::max(1, threads); ++t) pool.emplace_back(worker);
  for (std::thread& thread : pool) thread.join();
  return rows;
}

std::vector<BenchmarkSummary> summarise(const std::vector<BenchmarkRow>& rows) {
  std::map<Setting, std::vector<const BenchmarkRow*>> groups;
  for (const BenchmarkRow& row : rows) groups[{row.map, row.agents, row.tasks}].push_back(&row);
  std::vector<BenchmarkSummary> out;
  for (const auto& [setting, members] : groups) {
    BenchmarkSummary summary{setting.map, setting.agents, setting.tasks, static_cast<int>(members.size())};
    std::vector<double> first_times;
    double ratio_sum = 0, flow_sum = 0;
    for (const BenchmarkRow* row : members) {
      if (!row->solved) continue;
      ++summary.solved;
      first_times.push_back(row->first_solution_ms);
      ratio_sum += row->ratio;
      flow_sum += static_cast<double>(row->flowtime);
    }
    if (!first_times.empty()) {
      std::sort(first_times.begin(), first_times.end());
      const size_t k = first_times.size();
      summary.median_first_ms = k % 2 ? first_times[k / 2] : (first_times[k / 2 - 1] + first_times[k / 2]) / 2;
      summary.mean_ratio = ratio_sum / summary.solved;
      summary.mean_flowtime = flow_sum / summary.solved;
    }
    out.push_back(summary);
  }
  return out;
}

std::string csv_header() {
  return "file,solver,map,agents,tasks,solved,comp_time_ms,first_solution_ms,flowtime,makespan,lower_bound,ratio,"
         "sequences,error";
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

std::string to_csv(const BenchmarkRow& row, const std::string& solver) {
  std::ostringstream out;
  out << csv_field(row.file) << "," << csv_field(solver) << "," << csv_field(row.map) << "," << row.agents << "," << row.tasks << ","
      << (row.solved ? 1 : 0) << "," << row.comp_time_ms << "," << row.first_solution_ms << "," << row.flowtime
      << "," << row.makespan << "," << row.lower_bound << "," << row.ratio << "," << row.sequences << "," << csv_field(row.error);
  return out.str();
}

}  // namespace planner_core
