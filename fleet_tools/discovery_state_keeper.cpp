#include "discovery_state_keeper.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace coordinator {
namespace {

namespace fs = std::filesystem;

// The server's files in `dir` (server-<prefix>...) whose names end with `suffix`.
std::vector<fs::path> server_files_ending(const fs::path& dir, const std::string& suffix) {
  std::vector<fs::path> files;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("server-") && name.ends_with(suffix) && entry.is_regular_file(error)) {
      files.push_back(entry.path());
    }
  }
  return files;
}

// The server's state files: server-<prefix>.json, not its (unused) queue file nor our copies.
std::vector<fs::path> state_files(const fs::path& dir) {
  std::vector<fs::path> files = server_files_ending(dir, ".json");
  std::erase_if(files, [](const fs::path& file) { return file.filename().string().ends_with("_queue.json"); });
  return files;
}

// Copies `from` to `to` if the copy is one complete JSON document (the server may be writing
// `from` meanwhile). `to` is replaced in one step, so that it is never seen cut short itself.
bool copy_if_complete(const fs::path& from, const fs::path& to) {
  const fs::path partial = to.string() + ".partial";
  std::error_code error;
  fs::copy_file(from, partial, fs::copy_options::overwrite_existing, error);
  if (error) {
    spdlog::warn("cannot copy {}: {}", from.string(), error.message());
    return false;
  }
  if (!is_complete_json(partial)) {
    fs::remove(partial, error);
    return false;
  }
  fs::rename(partial, to, error);
  if (error) spdlog::warn("cannot write {}: {}", to.string(), error.message());
  return !error;
}

}  // namespace

fs::path complete_copy_of(const fs::path& state_file) { return state_file.string() + ".complete"; }

bool is_complete_json(const fs::path& file) {
  std::ifstream in(file);
  return in && nlohmann::json::accept(in);
}

DiscoveryStateKeeper::DiscoveryStateKeeper(fs::path dir) : dir_(std::move(dir)) {
  const fs::path lock_file = dir_ / "lock";
  lock_fd_ = open(lock_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) {
    throw std::invalid_argument("--state-dir: cannot create " + lock_file.string() + " (" + std::strerror(errno) + ")");
  }
  if (flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    close(lock_fd_);
    throw std::invalid_argument("--state-dir: '" + dir_.string() +
                                "' is in use by another ctsfleet-discovery (two servers on one state overwrite "
                                "each other's): give each server its own --state-dir and --server-id");
  }
}

DiscoveryStateKeeper::~DiscoveryStateKeeper() { close(lock_fd_); }

void DiscoveryStateKeeper::keep_complete_copies() {
  for (const fs::path& file : state_files(dir_)) {
    std::error_code error;
    const Seen now{fs::last_write_time(file, error), fs::file_size(file, error)};
    if (error) continue;
    auto kept = kept_.find(file.filename().string());
    if (kept != kept_.end() && kept->second.written == now.written && kept->second.size == now.size) continue;
    // A copy taken while the server writes is cut short and dropped; the next call tries again.
    if (!copy_if_complete(file, complete_copy_of(file))) continue;
    kept_[file.filename().string()] = now;
  }
}

int DiscoveryStateKeeper::restore_cut_short_files() {
  int restored = 0;
  for (const fs::path& file : state_files(dir_)) {
    if (is_complete_json(file)) continue;
    const fs::path copy = complete_copy_of(file);
    std::error_code error;
    if (!fs::exists(copy, error) || !is_complete_json(copy)) {
      spdlog::warn("the server's state file {} was cut short and there is no complete copy: it starts from "
                   "nothing", file.string());
      continue;
    }
    if (!copy_if_complete(copy, file)) continue;
    ++restored;
    spdlog::warn("the server's state file {} was cut short (the server died while writing it): its last "
                 "complete copy is back",
                 file.string());
  }
  return restored;
}

int DiscoveryStateKeeper::forget_what_the_server_received() {
  int deleted = 0;
  // server-<prefix>_reader.db: Fast DDS's SQLite persistence of the server's builtin readers.
  for (const fs::path& file : server_files_ending(dir_, "_reader.db")) {
    std::error_code error;
    if (fs::remove(file, error)) {
      ++deleted;
    } else if (error) {
      spdlog::warn("cannot delete {} ({}): the server may miss discovery data its state file lacks", file.string(),
                   error.message());
    }
  }
  return deleted;
}

}  // namespace coordinator
