// PibtLifelong with window LNS: the last step's window carried on one step, its new errands
// planned again (PibtLifelongSettings::keep_window).
#include "planner_core/pibt_lifelong.hpp"

#include <algorithm>

namespace planner_core {

std::vector<Poses> PibtLifelong::kept_window(const Poses& now, const Config& goals) {
  std::vector<Poses> window;
  if (last_window_.size() < 2 || last_window_goals_.size() != goals.size()) return window;
  const Poses& planned = last_window_[1];
  const bool rotate = settings_.actions == ActionModel::kRotate;
  if (planned.cells != now.cells || (rotate && planned.headings != now.headings)) return window;  // not carried out
  std::vector<Poses> shifted(last_window_.begin() + 1, last_window_.end());
  shifted.push_back(shifted.back());  // the last step: everyone waits
  // Agents with a new errand (arrived at the step just taken, or parked or let go) go elsewhere.
  // So does an agent standing on its goal with the same errand (the next one is where it stands,
  // and is done a step later): the window held its cell only until it arrived, so the others'
  // paths may lead through it.
  std::vector<int> again;
  std::vector<char> listed(goals.size(), 0);
  for (size_t a = 0; a < goals.size(); ++a) {
    if (goals[a] == last_window_goals_[a] && now.cells[a] != goals[a]) continue;
    again.push_back(static_cast<int>(a));
    listed[a] = 1;
  }
  // Others may have planned to drive through where such an agent stands. When one finds no way,
  // it goes first and the agents about to pass next to it are planned again too, after it.
  for (int round = 0; round < kReplanRounds; ++round) {
    window = shifted;
    int blocked = -1;
    if (lns_.replan(window, goals, again, &blocked)) {
      ++windows_carried_on_;
      return window;
    }
    const auto first = std::find(again.begin(), again.end(), blocked);
    std::rotate(again.begin(), first, first + 1);
    const Vertex there = shifted[0].cells[blocked];
    for (size_t a = 0; a < goals.size(); ++a) {
      if (listed[a]) continue;
      for (size_t t = 1; t <= 2 && t < shifted.size(); ++t) {
        const Vertex cell = shifted[t].cells[a];
        if (cell == there || graph_.adjacent(cell, there)) {
          again.push_back(static_cast<int>(a));
          listed[a] = 1;
          break;
        }
      }
    }
  }
  return {};
}

}  // namespace planner_core
