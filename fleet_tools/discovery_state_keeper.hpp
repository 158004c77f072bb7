// Keeping the Fast DDS discovery server's state file usable across a crash.
//
// Fast DDS 2.9.1's backup server rewrites its state file in place: it truncates the file, then
// writes the whole state again. A crash between the two leaves the file cut short, the server
// restarted on it begins with nothing, and the programs that knew the server ignore it (they have
// seen its sequence numbers already): a robot that starts afterwards is never found. The keeper
// copies every complete version of the file aside and puts the last complete one back before the
// server is started again.
//
// That copy can be a second old, and the server also keeps, in server-<prefix>_reader.db, which
// discovery data of each program it has received. Started on both, it would never ask again for
// what arrived after the copy was taken (a coordinator that joined, a robot's command writer): a
// robot restarted later could not match it. So before every start the keeper deletes that file;
// the server then asks every program it hears for all it has, and learns the last second again.
// Its writers' file (_writer.db) stays: their sequence numbers must go on from where they were.
#pragma once

#include <filesystem>
#include <map>
#include <string>

namespace coordinator {

class DiscoveryStateKeeper {
 public:
  // `dir`: where the server writes its state files (server-<prefix>.json). The keeper locks it
  // while it lives: two servers on one state would overwrite each other's; the second is refused
  // (std::invalid_argument naming --state-dir).
  explicit DiscoveryStateKeeper(std::filesystem::path dir);
  ~DiscoveryStateKeeper();
  DiscoveryStateKeeper(const DiscoveryStateKeeper&) = delete;
  DiscoveryStateKeeper& operator=(const DiscoveryStateKeeper&) = delete;

  // Copies a state file aside once it is complete again after a change. Cheap when nothing
  // changed; call it every second or so while the server runs.
  void keep_complete_copies();

  // Before a (re)start: a state file that is not complete JSON is replaced by its last complete
  // copy, and that is logged. Returns how many files were restored.
  int restore_cut_short_files();

  // Before a (re)start: deletes what the server's readers recorded as received (see above), so
  // that it learns from every program again whatever its state file lacks. Returns how many
  // files were deleted.
  int forget_what_the_server_received();

 private:
  struct Seen {
    std::filesystem::file_time_type written;
    std::uintmax_t size = 0;
  };
  std::filesystem::path dir_;
  int lock_fd_ = -1;
  std::map<std::string, Seen> kept_;  // by file name: the version last copied aside
};

// The name of the complete copy kept of a state file.
std::filesystem::path complete_copy_of(const std::filesystem::path& state_file);

// Whether a file holds one complete JSON document.
bool is_complete_json(const std::filesystem::path& file);

}  // namespace coordinator
