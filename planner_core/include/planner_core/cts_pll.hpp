// CtsPll: CTS-PLL (Jiang et al., CTS-PLL paper Algorithm 2): K-best joint task sequencing,
// Extended-PIBT with lock detection and release by LaCAM, and LNS refinement of each feasible
// plan. Variants: v1 = best sequence + lock release; v2 = sequences in order until the first
// feasible plan; v3 = full anytime loop with LNS until the deadline.
#pragma once

#include "planner_core/solver.hpp"

namespace planner_core {

class CtsPll : public Solver {
 public:
  enum class Variant { kV1, kV2, kV3 };
  CtsPll(const SolverConfig& config, Variant variant) : config_(config), variant_(variant) {}
  SolveResult solve(const Instance& instance, const SolveOptions& options) override;

 private:
  SolverConfig config_;
  Variant variant_;
};

}  // namespace planner_core
