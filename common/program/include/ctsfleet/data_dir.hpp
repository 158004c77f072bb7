// Where a program finds the data ctsfleet ships (config/, benchmarks/, docs/): the folder named by
// CTSFLEET_DATA_DIR if set; else the install layout beside the executable (<prefix>/bin/.. ->
// <prefix>/share/ctsfleet); else, for a program run from a build tree, the source tree it was
// built from.
#pragma once

#include <filesystem>
#include <string>

namespace ctsfleet {

// The data folder; throws planner_core::InputError naming the places it looked when none exists.
std::filesystem::path data_dir();

// data_dir() / relative.
std::filesystem::path data_path(const std::string& relative);

// The folder of the running executable (where the other ctsfleet programs are).
std::filesystem::path program_dir();

}  // namespace ctsfleet
