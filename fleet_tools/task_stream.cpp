#include "task_stream.hpp"

namespace coordinator {

TaskStream::TaskStream(const planner_core::Graph& graph, int waiting, int mission_tasks, uint32_t seed,
                       std::string id_prefix)
    : waiting_(waiting), mission_tasks_(mission_tasks), rng_(seed), id_prefix_(std::move(id_prefix)) {
  for (planner_core::Vertex v = 0; v < graph.vertex_count(); ++v) cells_.push_back(graph.cell_of(v));
}

TaskStream::TaskStream(std::vector<planner_core::Cell> cells_in_order, int waiting, int mission_tasks,
                       std::string id_prefix)
    : cells_(std::move(cells_in_order)),
      in_order_(true),
      waiting_(waiting),
      mission_tasks_(mission_tasks),
      id_prefix_(std::move(id_prefix)) {}

std::vector<fleet_transport::TaskRequest> TaskStream::due(int tasks_done, Clock::time_point now) {
  std::vector<fleet_transport::TaskRequest> requests;
  for (auto& [id, asked] : unanswered_) {
    if (now - asked.last_sent >= asked.again_after) {
      asked.last_sent = now;
      requests.push_back(asked.request);
    }
  }
  const int not_done = mission_tasks_ + accepted_ - tasks_done;
  for (int k = not_done + static_cast<int>(unanswered_.size()); k < waiting_ && !cells_.empty(); ++k) {
    const int64_t list_number = in_order_ ? static_cast<int64_t>(next_in_order_) : -1;
    const planner_core::Cell cell = cells_[(in_order_ ? next_in_order_++ : rng_()) % cells_.size()];
    fleet_transport::TaskRequest request;
    request.request_id = id_prefix_ + "-" + std::to_string(next_id_++);
    request.action = fleet_transport::TaskAction::kAdd;
    request.x = cell.x;
    request.y = cell.y;
    unanswered_[request.request_id] = {request, now, std::chrono::seconds(1), list_number};
    requests.push_back(request);
  }
  return requests;
}

void TaskStream::answered(const fleet_transport::TaskReply& reply) {
  const auto asked = unanswered_.find(reply.request_id);
  if (asked == unanswered_.end()) return;  // another's, or a repeat's answer
  if (!reply.accepted && reply.reason.starts_with("duplicate")) {
    Asked again = asked->second;
    unanswered_.erase(asked);
    again.request.request_id = id_prefix_ + "-" + std::to_string(next_id_++);  // a repeat would get the same answer
    again.last_sent = Clock::now();
    again.again_after = std::chrono::milliseconds(250);
    unanswered_[again.request.request_id] = again;
    ++deferred_;
    return;
  }
  const int64_t list_number = asked->second.list_number;
  unanswered_.erase(asked);
  if (reply.accepted) {
    ++accepted_;
    if (list_number >= 0) list_number_of_task_[reply.task] = list_number;
  } else {
    ++refused_;  // e.g. a duplicate of a task still waiting at that cell
    last_refusal_ = reply.reason;
  }
}

}  // namespace coordinator
