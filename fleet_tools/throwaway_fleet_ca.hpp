// A fleet CA made on the fly for a simulated fleet that runs with DDS Security (ctsfleet-sim
// --secure, ctsfleet-fleetbench --secure): the same ctsfleet-ca a real fleet uses, in a folder
// that is made anew every run.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace coordinator {

// Makes a new fleet CA in `dir` (removing what was there) with ctsfleet-ca from `program_dir`,
// enrols a coordinator named "coordinator", an observer named "monitor" and every robot id in
// `robots`. Throws std::runtime_error when ctsfleet-ca fails (its output is in dir/../fleet-ca.log).
void make_throwaway_fleet_ca(const std::filesystem::path& program_dir, const std::filesystem::path& dir,
                             const std::vector<std::string>& robots);

}  // namespace coordinator
