// PibtLifelong in the rotation model: the cells PIBT chose (targets) carried out as a plan until
// every agent stands on its own (PibtLifelongSettings::hold_plans).
#include "planner_core/pibt_lifelong.hpp"

#include "planner_core/step_faults.hpp"

namespace planner_core {

bool PibtLifelong::short_of_target(const Poses& now, int agent) const {
  if (settings_.actions != ActionModel::kRotate || targets_.size() != now.cells.size()) return false;
  const Vertex target = targets_[agent];
  return target != now.cells[agent] && graph_.adjacent(now.cells[agent], target);
}

bool PibtLifelong::plan_unfinished(const Poses& now) const {
  bool unfinished = false;
  Config planned = now.cells;
  for (size_t a = 0; a < now.cells.size(); ++a) {
    if (short_of_target(now, static_cast<int>(a))) {
      unfinished = true;
      planned[a] = targets_[a];
    }
  }
  // Targets come from one PIBT step, so they hold together; but window LNS may since have sent
  // some agents elsewhere, onto a cell another still heads for. Such a plan is not held.
  return unfinished && find_step_fault(graph_, now.cells, planned).what.empty();
}

Poses PibtLifelong::carry_out_targets(const Poses& now, const Config& goals) {
  const int n = static_cast<int>(now.cells.size());
  ++held_steps_;
  next_.headings = now.headings;
  next_.cells.assign(n, kNoVertex);
  for (int a = 0; a < n; ++a) {
    // A target is a neighbour or the agent's own cell; plan_unfinished checked they make a valid step.
    next_.cells[a] = short_of_target(now, a) ? targets_[a] : now.cells[a];
    entering_[next_.cells[a]] = a;
  }
  const Config planned = next_.cells;
  take_rotation_actions(now, goals);
  end_step(now, planned);
  return next_;
}

}  // namespace planner_core
