#include "paper_experiments.hpp"

#include "chart.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "ctsfleet/data_dir.hpp"
#include "planner_core/benchmark_runner.hpp"
#include "planner_core/input_error.hpp"


namespace ctsfleet_bench {

namespace fs = std::filesystem;
using namespace planner_core;

namespace {

struct SolverRun {
  std::string solver;
  std::map<std::string, BenchmarkRow> by_file;
};

std::vector<std::string> yaml_files(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(dir + ": no such benchmark suite folder (see --benchmarks)");
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".yaml") files.push_back(entry.path().string());
  }
  return files;
}

SolverRun run_solver(const std::vector<std::string>& files, const std::string& solver, double seconds,
                     const ExperimentSettings& settings, std::ofstream& csv) {
  SolverConfig config;
  config.solver = solver;
  config.seed = settings.seed;
  config.complete_fallback = false;  // the paper's algorithms as published, side by side with its figures
  std::fprintf(stderr, "%s: %zu instances x %.0f s\n", solver.c_str(), files.size(), seconds);
  SolverRun run{solver, {}};
  for (BenchmarkRow& row : run_benchmark(files, config, seconds, settings.iterations, settings.threads, [&](const BenchmarkRow&, int done) {
         std::fprintf(stderr, "\r  %d/%zu", done, files.size());
       })) {
    csv << to_csv(row, solver) << "\n";
    if (!row.error.empty()) std::fprintf(stderr, "\n  %s: %s\n", row.file.c_str(), row.error.c_str());
    run.by_file[row.file] = row;
  }
  std::fprintf(stderr, "\n");
  return run;
}

struct Aggregate {
  int instances = 0, solved = 0;
  double first_ms_sum = 0;
  std::vector<double> first_ms;
  double flow_sum = 0, ratio_sum = 0;
  int both = 0;  // instances solved by both solvers compared
};

double median(std::vector<double> values) {
  if (values.empty()) return -1;
  std::sort(values.begin(), values.end());
  const size_t k = values.size();
  return k % 2 ? values[k / 2] : (values[k / 2 - 1] + values[k / 2]) / 2;
}

std::string percent(int part, int whole) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f%%", whole ? 100.0 * part / whole : 0.0);
  return text;
}

// Rows grouped by (map, N, M) setting, in name order.
std::map<std::tuple<std::string, int, int>, std::vector<std::string>> by_setting(const SolverRun& run) {
  std::map<std::tuple<std::string, int, int>, std::vector<std::string>> groups;
  for (const auto& [file, row] : run.by_file) groups[{row.map, row.agents, row.tasks}].push_back(file);
  return groups;
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  if (!(out << text)) throw std::runtime_error(path.string() + ": cannot write");
}

// Flowtime over time of two anytime solvers on one instance, as CSV rows solver,time_s,flowtime.
std::string anytime_csv(const std::string& file, double seconds, unsigned seed) {
  std::ostringstream csv;
  csv << "solver,time_s,flowtime\n";
  const Instance instance = load_instance(file);
  for (const std::string solver : {"cts-pibt-anytime", "cts-pll-v3"}) {
    SolverConfig config;
    config.solver = solver;
    config.seed = seed;
    config.complete_fallback = false;
    const SolveResult result = make_solver(config)->solve(instance, {Deadline::in_seconds(seconds), {}});
    for (const Improvement& step : result.improvements) {
      csv << solver << "," << step.time_ms / 1000.0 << "," << step.flowtime << "\n";
    }
    if (!result.improvements.empty()) {
      csv << solver << "," << result.comp_time_ms / 1000.0 << "," << result.improvements.back().flowtime << "\n";
    }
  }
  return csv.str();
}

int dense(const ExperimentSettings& settings, std::ostringstream& md, std::ofstream& csv) {
  const std::vector<std::string> files =
      sample_per_setting(yaml_files(settings.benchmarks + "/dense"), settings.dense_per_setting);
  const SolverRun pibt = run_solver(files, "cts-pibt", settings.seconds, settings, csv);
  const SolverRun v1 = run_solver(files, "cts-pll-v1", settings.seconds, settings, csv);
  const SolverRun anytime = run_solver(files, "cts-pibt-anytime", settings.seconds, settings, csv);
  const SolverRun v3 = run_solver(files, "cts-pll-v3", settings.seconds, settings, csv);
  const std::map<int, std::pair<int, int>> paper_success = {
      {60, {76, 98}}, {90, {68, 92}}, {120, {66, 96}}, {150, {50, 92}}, {180, {38, 72}}};
  const std::map<int, double> paper_gain = {{60, 17.5}, {90, 12.4}, {120, 4.8}, {150, 8.1}, {180, 1.3}};

  md << "### Dense: maze-32-32-2, N=50 (" << settings.dense_per_setting << " instances per M, " << settings.seconds
     << " s per run)\n\n";
  md << "| M | cts-pibt success | cts-pll-v1 success | paper CTS-PIBT | paper CTS-PLL-v1 | cts-pll-v1 median first (ms) |\n"
        "|---|---|---|---|---|---|\n";
  for (const auto& [setting, members] : by_setting(pibt)) {
    const int m = std::get<2>(setting);
    int solved_pibt = 0, solved_v1 = 0, solved_v3 = 0;
    std::vector<double> first;
    for (const std::string& f : members) {
      solved_pibt += pibt.by_file.at(f).solved;
      solved_v1 += v1.by_file.at(f).solved;
      solved_v3 += v3.by_file.at(f).solved;
      if (v1.by_file.at(f).solved) first.push_back(v1.by_file.at(f).first_solution_ms);
    }
    const int n = static_cast<int>(members.size());
    md << "| " << m << " | " << percent(solved_pibt, n) << " | " << percent(solved_v1, n) << " | "
       << (paper_success.count(m) ? std::to_string(paper_success.at(m).first) + "%" : "-") << " | "
       << (paper_success.count(m) ? std::to_string(paper_success.at(m).second) + "%" : "-") << " | "
       << [&] {
            char text[32];
            std::snprintf(text, sizeof text, "%.1f", median(first));
            return std::string(text);
          }() << " |\n";
  }

  md << "\n| M | cts-pibt-anytime flowtime | cts-pll-v3 flowtime | v3 gain | paper gain | anytime F/LB | v3 F/LB | "
        "v3 success | v3 median first (ms) |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& [setting, members] : by_setting(anytime)) {
    const int m = std::get<2>(setting);
    double flow_a = 0, flow_v = 0, ratio_a = 0, ratio_v = 0;
    int both = 0, solved_v3 = 0;
    std::vector<double> first;
    for (const std::string& f : members) {
      const BenchmarkRow &a = anytime.by_file.at(f), &v = v3.by_file.at(f);
      if (v.solved) {
        ++solved_v3;
        first.push_back(v.first_solution_ms);
      }
      if (!a.solved || !v.solved) continue;
      ++both;
      flow_a += static_cast<double>(a.flowtime), flow_v += static_cast<double>(v.flowtime);
      ratio_a += a.ratio, ratio_v += v.ratio;
    }
    char line[512];
    std::snprintf(line, sizeof line, "| %d | %.1f | %.1f | %.1f%% | %.1f%% | %.3f | %.3f | %s | %.1f |\n", m,
                  both ? flow_a / both : 0, both ? flow_v / both : 0, both ? 100.0 * (flow_a - flow_v) / flow_a : 0,
                  paper_gain.count(m) ? paper_gain.at(m) : 0.0, both ? ratio_a / both : 0, both ? ratio_v / both : 0,
                  percent(solved_v3, static_cast<int>(members.size())).c_str(), median(first));
    md << line;
  }
  md << "\nFlowtimes are means over the instances both solvers solved. Gain = (anytime - v3) / anytime.\n\n";
  const std::string plotted = settings.benchmarks + "/dense/maze-32-32-2-N50-M120-00.yaml";
  if (fs::exists(plotted)) {
    const fs::path anytime_file = fs::path(settings.out_dir) / "dense-anytime.csv";
    write_file(anytime_file, anytime_csv(plotted, settings.seconds, settings.seed));
    draw_chart({"anytime", anytime_file.string(), "-o", (fs::path(settings.out_dir) / "dense-anytime.svg").string(),
                "--title", "Flowtime over time: " + fs::path(plotted).stem().string()});
  }
  return 0;
}

int sparse(const ExperimentSettings& settings, std::ostringstream& md, std::ofstream& csv) {
  const std::vector<std::string> files =
      sample_per_setting(yaml_files(settings.benchmarks + "/sparse"), settings.sparse_per_setting);
  const std::vector<std::string> names = {"cts-pibt", "cts-pll-v2", "cts-pll-v3"};
  std::vector<SolverRun> runs;
  for (const std::string& name : names) runs.push_back(run_solver(files, name, settings.seconds, settings, csv));
  md << "### Sparse: 4 maps, N=5/10/20, M=10..50 (" << settings.sparse_per_setting << " instances per setting, "
     << settings.seconds << " s per run)\n\n";
  md << "| map | N | success cts-pibt / v2 / v3 | first solution ms cts-pibt / v2 / v3 (median) | flowtime cts-pibt / "
        "v2 / v3 (mean, all solved) |\n|---|---|---|---|---|\n";
  // One row per (map, N), over all M.
  std::map<std::pair<std::string, int>, std::vector<std::string>> groups;
  for (const auto& [file, row] : runs[0].by_file) groups[{row.map, row.agents}].push_back(file);
  double total_pibt = 0, total_v3 = 0;
  int total_success[3] = {0, 0, 0}, total = 0;
  for (const auto& [key, members] : groups) {
    int success[3] = {0, 0, 0};
    std::vector<double> first[3];
    double flow[3] = {0, 0, 0};
    int all_solved = 0;
    for (const std::string& f : members) {
      bool every = true;
      for (int s = 0; s < 3; ++s) {
        const BenchmarkRow& row = runs[s].by_file.at(f);
        success[s] += row.solved;
        if (row.solved) first[s].push_back(row.first_solution_ms);
        every = every && row.solved;
      }
      if (!every) continue;
      ++all_solved;
      for (int s = 0; s < 3; ++s) flow[s] += static_cast<double>(runs[s].by_file.at(f).flowtime);
    }
    const int n = static_cast<int>(members.size());
    total += n;
    for (int s = 0; s < 3; ++s) total_success[s] += success[s];
    total_pibt += flow[0], total_v3 += flow[2];
    char line[512];
    std::snprintf(line, sizeof line, "| %s | %d | %s / %s / %s | %.1f / %.1f / %.1f | %.1f / %.1f / %.1f |\n",
                  key.first.c_str(), key.second, percent(success[0], n).c_str(), percent(success[1], n).c_str(),
                  percent(success[2], n).c_str(), median(first[0]), median(first[1]), median(first[2]),
                  all_solved ? flow[0] / all_solved : 0, all_solved ? flow[1] / all_solved : 0,
                  all_solved ? flow[2] / all_solved : 0);
    md << line;
  }
  char line[512];
  std::snprintf(line, sizeof line,
                "\nOverall: success cts-pibt %s, cts-pll-v2 %s, cts-pll-v3 %s; cts-pll-v3 flowtime %.1f%% below "
                "cts-pibt on the instances all three solved (paper: 100%% success, 10.4%% lower).\n\n",
                percent(total_success[0], total).c_str(), percent(total_success[1], total).c_str(),
                percent(total_success[2], total).c_str(),
                total_pibt > 0 ? 100.0 * (total_pibt - total_v3) / total_pibt : 0.0);
  md << line;
  return 0;
}

int scale(const ExperimentSettings& settings, std::ostringstream& md, std::ofstream& csv) {
  const std::vector<std::string> files =
      sample_per_setting(yaml_files(settings.benchmarks + "/scale"), settings.scale_per_setting);
  const double seconds = std::max(30.0, settings.seconds);
  const SolverRun v2 = run_solver(files, "cts-pll-v2", seconds, settings, csv);
  md << "### Scale: time to the first feasible plan with cts-pll-v2 (" << seconds << " s limit)\n\n";
  md << "| map | N | M | instances | found | median first (s) | max first (s) | F/LB of the first plan |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const auto& [setting, members] : by_setting(v2)) {
    std::vector<double> first;
    double ratio = 0;
    for (const std::string& f : members) {
      const BenchmarkRow& row = v2.by_file.at(f);
      if (!row.solved) continue;
      first.push_back(row.first_solution_ms / 1000.0);
      ratio += row.ratio;
    }
    char line[512];
    std::snprintf(line, sizeof line, "| %s | %d | %d | %zu | %zu | %.2f | %.2f | %.3f |\n",
                  std::get<0>(setting).c_str(), std::get<1>(setting), std::get<2>(setting), members.size(),
                  first.size(), median(first), first.empty() ? -1.0 : *std::max_element(first.begin(), first.end()),
                  first.empty() ? 0.0 : ratio / static_cast<double>(first.size()));
    md << line;
  }
  md << "\n";
  return 0;
}

}  // namespace

int run_experiments(const std::string& which, const ExperimentSettings& settings) {
  fs::create_directories(settings.out_dir);
  std::ofstream csv(fs::path(settings.out_dir) / (which + ".csv"));
  if (!csv) throw InputError("--out-dir: cannot write " + (fs::path(settings.out_dir) / (which + ".csv")).string());
  csv << csv_header() << "\n";
  std::ostringstream md;
  int code = 0;
  if (which == "dense" || which == "all") code |= dense(settings, md, csv);
  if (which == "sparse" || which == "all") code |= sparse(settings, md, csv);
  if (which == "scale" || which == "all") code |= scale(settings, md, csv);
  csv.close();
  write_file(fs::path(settings.out_dir) / (which + ".md"), md.str());
  if (which == "dense" || which == "all") {
    const std::string results = (fs::path(settings.out_dir) / (which + ".csv")).string();
    draw_chart({"success", results, "--match", "/dense/", "-o", (fs::path(settings.out_dir) / "dense-success.svg").string(),
                "--title", "Success rate per M (maze-32-32-2, N=50)"});
    draw_chart({"ratio", results, "--match", "/dense/", "-o", (fs::path(settings.out_dir) / "dense-ratio.svg").string(),
                "--title", "Flowtime / lower bound per M (maze-32-32-2, N=50)"});
  }
  std::printf("%s", md.str().c_str());
  std::printf("written: %s/%s.{md,csv}\n", settings.out_dir.c_str(), which.c_str());
  return code;
}

}  // namespace ctsfleet_bench
