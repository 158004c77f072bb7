#include "planner_core/action_model.hpp"

#include "planner_core/input_error.hpp"

namespace planner_core {

ActionModel parse_action_model(const std::string& text, const std::string& what) {
  if (text == "move4") return ActionModel::kMove4;
  if (text == "rotate") return ActionModel::kRotate;
  throw InputError(what + ": \"" + text + "\" is no action model (move4 or rotate)");
}

std::string to_string(ActionModel model) { return model == ActionModel::kRotate ? "rotate" : "move4"; }

namespace {

constexpr int kColumnStep[kHeadings] = {1, 0, -1, 0};
constexpr int kRowStep[kHeadings] = {0, 1, 0, -1};

}  // namespace

Vertex ahead(const Graph& graph, Vertex v, int heading) {
  const Cell cell = graph.cell_of(v);
  return graph.vertex_at(Cell{cell.x + kColumnStep[heading], cell.y + kRowStep[heading]});
}

int heading_towards(const Graph& graph, Vertex from, Vertex to) {
  const Cell a = graph.cell_of(from);
  const Cell b = graph.cell_of(to);
  for (int h = 0; h < kHeadings; ++h) {
    if (a.x + kColumnStep[h] == b.x && a.y + kRowStep[h] == b.y) return h;
  }
  return -1;
}

char heading_letter(int heading) { return "ESWN"[heading]; }

int heading_of_letter(char letter) {
  switch (letter) {
    case 'E': return 0;
    case 'S': return 1;
    case 'W': return 2;
    case 'N': return 3;
    default: return -1;
  }
}

}  // namespace planner_core
