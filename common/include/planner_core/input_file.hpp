// Input files: every path a program reads must be a regular file. A FIFO would block its reader
// for ever (ignoring Ctrl-C, which is only looked at between steps), a device such as /dev/zero
// would grow without end, a folder reads as nothing: each is refused at once, naming the path.
#pragma once

#include <string>

namespace planner_core {

// Throws InputError ("PATH: a FIFO (named pipe), ..., not a map file") when `path` names anything
// but a regular file, following symbolic links; a missing path is left to the caller to report.
// `what` says what the file was for ("map file").
void require_regular_file(const std::string& path, const std::string& what);

// The largest map side read from a file: a bigger map is refused with this limit named.
constexpr int kMaxMapSide = 4096;

}  // namespace planner_core
