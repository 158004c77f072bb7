// A run under the league's 2026 rules (league_run.hpp) written as the Start-Kit 3.x output file
// (actionModel MAPF_T, version "2026 LoRR"): the summary, each robot's start, its executed
// actions as compressed segments "[(tick,row,col,heading,counter):(F 3,W 2,...)]" of
// `segment_ticks` ticks each, its delay intervals, errand events, task schedule and the errors the
// tick check found. PlanViz and the league's tools read it. Format: docs/FORMATS.md, "League of
// Robot Runners output, 2026".
#pragma once

#include <string>

#include "planner_core/league_run.hpp"
#include "planner_core/lorr_problem.hpp"

namespace planner_core {

// Throws InputError naming the file when it cannot be written.
void write_league_output(const std::string& path, const LorrProblem& problem, const LeagueRunSettings& settings,
                         const LeagueRunResult& result, const LeagueLog& log, int segment_ticks = 1000);

// Robot r's executed actions as the league's segments (exposed for tests).
std::string league_segments(const Graph& graph, Vertex start, int start_heading, const std::string& letters,
                            int ticks_per_action, int segment_ticks);

}  // namespace planner_core
