// A lifelong run written as the League of Robot Runners' output file (the Start-Kit's JSON, read
// by its PlanViz visualiser), in the move-in-four-directions model the league calls "MAPF"
// (actions U D L R W, starts without a heading) or its rotation model "MAPF_T" (actions F R C W,
// starts facing E S W or N). Format: docs/FORMATS.md, "League of Robot Runners
// output".
#pragma once

#include <string>

#include "planner_core/lifelong.hpp"
#include "planner_core/lorr_problem.hpp"

namespace planner_core {

// Writes `log` of a run of `problem` to `path`; throws InputError naming the file when it cannot.
void write_lorr_output(const std::string& path, const LorrProblem& problem, const LifelongResult& result,
                       const LifelongLog& log);

}  // namespace planner_core
