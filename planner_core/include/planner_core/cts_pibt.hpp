// CtsPibt: the CTS-PIBT baseline (Jiang et al.): K-best joint task sequencing with Extended-PIBT
// for each sequence, either on the single best sequence or anytime over sequences until the deadline.
#pragma once

#include "planner_core/solver.hpp"

namespace planner_core {

class CtsPibt : public Solver {
 public:
  CtsPibt(const SolverConfig& config, bool anytime) : config_(config), anytime_(anytime) {}
  SolveResult solve(const Instance& instance, const SolveOptions& options) override;

 private:
  SolverConfig config_;
  bool anytime_;
};

}  // namespace planner_core
