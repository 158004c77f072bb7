#include "planner_core/input_file.hpp"

#include <filesystem>
#include <system_error>

#include "planner_core/input_error.hpp"

namespace planner_core {

void require_regular_file(const std::string& path, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  // A missing file is the caller's to report, in its own words ("no such file", "cannot open").
  if (error || !fs::exists(status) || fs::is_regular_file(status)) return;
  std::string kind = "not a regular file";
  if (fs::is_directory(status)) kind = "a folder";
  if (fs::is_fifo(status)) kind = "a FIFO (named pipe), which would wait for a writer";
  if (fs::is_character_file(status) || fs::is_block_file(status)) kind = "a device, which may never end";
  if (fs::is_socket(status)) kind = "a socket";
  throw InputError(path + ": " + kind + ", not a " + what + " (give a regular file)");
}

}  // namespace planner_core
