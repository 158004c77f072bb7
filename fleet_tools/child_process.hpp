// Starting the fleet's programs as child processes (launcher and fleet benchmark).
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace coordinator {

// Starts args[0] with args; stdout and stderr go to `log_file` (or stay as they are when it is
// empty); when `results_file` is given, stdout (the program's results) goes there instead.
// Throws std::runtime_error when the program cannot be started.
pid_t start_child(const std::vector<std::string>& args, const std::string& log_file,
                  const std::string& results_file = "");

// Sends SIGINT (then SIGKILL after `grace_s`) and reaps the process.
void stop_child(pid_t pid, double grace_s);

}  // namespace coordinator
