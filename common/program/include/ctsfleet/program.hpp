// What every ctsfleet program shares at its edges: --version and --log-level, logs on stderr,
// one rule for input errors (one line naming the option, file or field; exit 2), and Ctrl-C or
// SIGTERM asking the program to stop.
#pragma once

#include <CLI/CLI.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace ctsfleet {

// Exit codes: one table for every program (README "Exit codes"; tests/cli_catalogue.py checks
// that the two agree and that no program exits with a code outside it).
inline constexpr int kExitSuccess = 0;
inline constexpr int kExitFailed = 1;         // the run failed: not solved, a collision seen, a request refused
inline constexpr int kExitInputError = 2;     // bad input: one line naming the option, file:line or field
inline constexpr int kExitUnfinished = 3;     // a mission ended with tasks pending
inline constexpr int kExitHeardNothing = 4;   // nobody answered: no robot heard, no coordinator answered
inline constexpr int kExitStoodDown = 5;      // another coordinator is active
inline constexpr int kExitInternalError = 70; // a bug: e.g. a plan that failed validation (nothing written)
inline constexpr int kExitInterrupted = 130;  // stopped by Ctrl-C or SIGTERM

// "0.1.0" plus `git describe` when built from a git checkout, e.g. "0.1.0 (git 4f2c1e9-dirty)".
std::string version_text();

struct CommonOptions {
  std::string log_level = "info";
};

// A CLI::App that already has --version and --log-level (trace, debug, info, warn, error, off).
class Program {
 public:
  Program(std::string name, const std::string& description);
  CLI::App& app() { return app_; }
  const std::string& name() const { return name_; }

  // Parses the command line. Returns an exit code when the program must end now: 0 after
  // --help or --version, 2 after a command-line error (one line on stderr naming the option).
  std::optional<int> parse(int argc, char** argv);

  // Runs `body` with logs on stderr (level from SPDLOG_LEVEL, then --log-level) and SIGINT/SIGTERM
  // setting stop_requested(). An InputError ends it with exit 2, any other exception with exit 1,
  // each as one line "NAME: error: ..." on stderr; nothing escapes as an abort.
  int run(const std::function<int()>& body);

  // Shorthand for main(): parse, then run.
  int main(int argc, char** argv, const std::function<int()>& body);

 private:
  std::string name_;
  CLI::App app_;
  CommonOptions common_;
};

// True once SIGINT or SIGTERM arrived (after Program::run installed the handlers).
std::atomic<bool>& stop_requested();

// Marks a stretch that does not look at stop_requested() (reading a big input, building its
// tables): while one is alive, a stop request ends the process with exit 130 after `grace_s`,
// saying so on stderr. Nothing it could lose is written yet. One at a time; not nested.
class StopsAtOnce {
 public:
  explicit StopsAtOnce(const std::string& program, const std::string& doing, double grace_s = 0.2);
  ~StopsAtOnce();
  StopsAtOnce(const StopsAtOnce&) = delete;
  StopsAtOnce& operator=(const StopsAtOnce&) = delete;

 private:
  struct Watch;
  std::unique_ptr<Watch> watch_;
};

// Sends logs to stderr at `level` (after SPDLOG_LEVEL); results stay alone on stdout.
void setup_logging(const std::string& level);

// Validators with messages that give the accepted range. Doubles: finite and within [low, high];
// integers: within [low, high] (CLI11 already refuses words and out-of-type values).
CLI::Validator number_in(double low, double high);
CLI::Validator positive_seconds(double high = 1e6);
CLI::Validator count_in(long long low, long long high);
// DDS domain ids: 0..232 (the RTPS port formula's limit).
CLI::Validator dds_domain();
// An output file that can be opened for writing (probed: created and removed again when new); not a folder.
CLI::Validator writable_file();
// An output folder, created if missing, that a file can be written into (probed).
CLI::Validator writable_folder();

}  // namespace ctsfleet
