#include "ctsfleet/data_dir.hpp"

#include <cstdlib>

#include "planner_core/input_error.hpp"

namespace ctsfleet {

namespace fs = std::filesystem;

fs::path program_dir() { return fs::canonical("/proc/self/exe").parent_path(); }

fs::path data_dir() {
  std::error_code ec;
  if (const char* from_environment = std::getenv("CTSFLEET_DATA_DIR"); from_environment && *from_environment) {
    if (!fs::is_directory(from_environment, ec)) {
      throw planner_core::InputError(std::string("CTSFLEET_DATA_DIR: '") + from_environment + "' is not a folder");
    }
    return fs::path(from_environment);
  }
  // <prefix>/bin -> <prefix>/share/ctsfleet (the relative path CMake's install dirs give).
  const fs::path installed = (program_dir() / CTSFLEET_BIN_TO_DATA).lexically_normal();
  if (fs::is_directory(installed / "config", ec)) return installed;
  const fs::path source_tree(CTSFLEET_SOURCE_DIR);
  if (fs::is_directory(source_tree / "config", ec)) return source_tree;
  throw planner_core::InputError("no ctsfleet data folder: looked in " + installed.string() + " and " +
                                 source_tree.string() + "; set CTSFLEET_DATA_DIR");
}

fs::path data_path(const std::string& relative) { return data_dir() / relative; }

}  // namespace ctsfleet
