#include "ctsfleet/program.hpp"

#include <spdlog/cfg/env.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <cmath>
#include <stdexcept>
#include <csignal>
#include <cstdio>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>
#include <sstream>

#include "ctsfleet/version.hpp"
#include "planner_core/input_error.hpp"

namespace ctsfleet {

namespace fs = std::filesystem;

namespace {

extern "C" void on_stop_signal(int) { stop_requested().store(true); }

const std::vector<std::string> kLogLevels = {"trace", "debug", "info", "warn", "error", "off"};

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

std::string number_text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// A validator for finite numbers that `accept` takes; `range` says which, in messages and --help.
CLI::Validator finite_number(const std::string& range, std::function<bool(double)> accept) {
  return CLI::Validator(
      [range, accept](std::string& input) -> std::string {
        double value = 0;
        if (!CLI::detail::lexical_cast(input, value) || !std::isfinite(value) || !accept(value)) {
          return "must be " + range + ", not '" + input + "'";
        }
        return {};
      },
      range);
}

// Opens `path` for writing (creating it if missing, removing it again when `remove_after`): what
// permissions alone do not tell (root, read-only or virtual file systems). "" when it worked.
std::string probe_write(const fs::path& path, bool remove_after) {
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return std::strerror(errno);
  close(fd);
  std::error_code ignored;
  if (remove_after) fs::remove(path, ignored);
  return {};
}

}  // namespace

std::string version_text() {
  std::string text = kVersion;
  if (std::string(kGitDescribe).size() > 0) text += std::string(" (git ") + kGitDescribe + ")";
  return text;
}

struct StopsAtOnce::Watch {
  std::mutex mutex;
  std::condition_variable done;
  bool finished = false;
  std::thread thread;
};

StopsAtOnce::StopsAtOnce(const std::string& program, const std::string& doing, double grace_s)
    : watch_(std::make_unique<Watch>()) {
  watch_->thread = std::thread([watch = watch_.get(), program, doing, grace_s] {
    constexpr auto kLook = std::chrono::milliseconds(50);
    std::unique_lock<std::mutex> lock(watch->mutex);
    while (!watch->done.wait_for(lock, kLook, [&] { return watch->finished; })) {
      if (!stop_requested()) continue;
      const auto grace = std::chrono::duration<double>(grace_s);
      if (watch->done.wait_for(lock, grace, [&] { return watch->finished; })) return;
      const std::string line = program + ": stopped while " + doing + "\n";
      [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, line.data(), line.size());
      std::_Exit(kExitInterrupted);
    }
  });
}

StopsAtOnce::~StopsAtOnce() {
  {
    const std::lock_guard<std::mutex> lock(watch_->mutex);
    watch_->finished = true;
  }
  watch_->done.notify_all();
  watch_->thread.join();
}

std::atomic<bool>& stop_requested() {
  static std::atomic<bool> requested{false};
  return requested;
}

void setup_logging(const std::string& level) {
  auto logger = spdlog::stderr_color_mt("ctsfleet");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::info);
  spdlog::cfg::load_env_levels();  // SPDLOG_LEVEL=debug, or SPDLOG_LEVEL=off
  if (!level.empty() && level != "info") spdlog::set_level(spdlog::level::from_str(level));
}

Program::Program(std::string name, const std::string& description)
    : name_(std::move(name)), app_(name_ + ": " + description, name_) {
  app_.set_version_flag("--version", name_ + " " + version_text());
  app_.add_option("--log-level", common_.log_level, "log detail on stderr (SPDLOG_LEVEL works too)")
      ->check(CLI::IsMember(kLogLevels))
      ->capture_default_str();
}

std::optional<int> Program::parse(int argc, char** argv) {
  try {
    app_.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app_.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app_.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app_.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: error: %s (see --help)\n", name_.c_str(), first_line(e.what()).c_str());
    return kExitInputError;
  }
  return std::nullopt;
}

int Program::run(const std::function<int()>& body) {
  try {
    setup_logging(common_.log_level);
    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    std::signal(SIGPIPE, SIG_IGN);
    return body();
  } catch (const planner_core::InputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", name_.c_str(), first_line(e.what()).c_str());
    return kExitInputError;
  } catch (const std::invalid_argument& e) {  // bad input found below the program (e.g. security files)
    std::fprintf(stderr, "%s: error: %s\n", name_.c_str(), first_line(e.what()).c_str());
    return kExitInputError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", name_.c_str(), first_line(e.what()).c_str());
    return 1;
  }
}

int Program::main(int argc, char** argv, const std::function<int()>& body) {
  if (const auto exit_code = parse(argc, argv)) return *exit_code;
  return run(body);
}

CLI::Validator number_in(double low, double high) {
  return finite_number("a number in [" + number_text(low) + ", " + number_text(high) + "]",
                       [low, high](double value) { return value >= low && value <= high; });
}

CLI::Validator positive_seconds(double high) {
  return finite_number("seconds in (0, " + number_text(high) + "]",
                       [high](double value) { return value > 0 && value <= high; });
}

CLI::Validator count_in(long long low, long long high) {
  const std::string range = "an integer in [" + std::to_string(low) + ", " + std::to_string(high) + "]";
  return CLI::Validator(
      [low, high, range](std::string& input) -> std::string {
        long long value = 0;
        if (!CLI::detail::lexical_cast(input, value) || value < low || value > high) {
          return "must be " + range + ", not '" + input + "'";
        }
        return {};
      },
      range);
}

CLI::Validator dds_domain() { return count_in(0, 232); }

CLI::Validator writable_file() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        if (input.empty()) return "an empty path is not a file";
        std::error_code ec;
        const fs::path path(input);
        if (fs::is_directory(path, ec)) return "'" + input + "' is a folder, not a file";
        // Opening a FIFO waits for a reader, for ever and deaf to Ctrl-C; a device (/dev/null) is
        // written as it is, without a probe.
        if (fs::is_fifo(path, ec)) return "'" + input + "' is a FIFO (named pipe), not a file";
        if (fs::is_character_file(path, ec) || fs::is_block_file(path, ec)) return {};
        const bool existed = fs::exists(path, ec);
        if (const std::string problem = probe_write(path, !existed); !problem.empty()) {
          return "cannot write '" + input + "': " + problem;
        }
        return {};
      },
      "FILE (writable)");
}

CLI::Validator writable_folder() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        if (input.empty()) return "an empty path is not a folder";
        std::error_code ec;
        const fs::path path(input);
        if (fs::exists(path, ec) && !fs::is_directory(path, ec)) return "'" + input + "' is a file, not a folder";
        fs::create_directories(path, ec);  // the program would make it anyway
        if (ec) return "cannot create the folder '" + input + "': " + ec.message();
        const fs::path probe = path / (".ctsfleet-write-probe-" + std::to_string(getpid()));
        if (const std::string problem = probe_write(probe, true); !problem.empty()) {
          return "cannot write into '" + input + "': " + problem;
        }
        return {};
      },
      "FOLDER (writable)");
}

}  // namespace ctsfleet
