#include "planner_core/svg_writer.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "planner_core/input_error.hpp"

namespace planner_core {

namespace {

constexpr int kCellPx = 20;

// Evenly spread hues, so neighbouring agent ids get distinct colours.
std::string agent_colour(int agent) {
  const double golden = 0.618033988749895;
  const double hue = std::fmod(agent * golden, 1.0) * 360.0;
  const int lightness = 35 + (agent * 7 % 3) * 10;
  std::ostringstream out;
  out << "hsl(" << static_cast<int>(hue) << ",80%," << lightness << "%)";
  return out.str();
}

double centre(int coordinate) { return coordinate * kCellPx + kCellPx / 2.0; }

}  // namespace

std::string render_svg(const Instance& instance, const Solution& solution) {
  const Graph& graph = *instance.graph;
  const int n = instance.agent_count();
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << graph.width() * kCellPx << "\" height=\""
      << graph.height() * kCellPx << "\" viewBox=\"0 0 " << graph.width() * kCellPx << " "
      << graph.height() * kCellPx << "\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n<g fill=\"#3a3a3a\">\n";
  for (int y = 0; y < graph.height(); ++y) {
    for (int x = 0; x < graph.width(); ++x) {
      if (!graph.is_free({x, y})) {
        svg << "<rect x=\"" << x * kCellPx << "\" y=\"" << y * kCellPx << "\" width=\"" << kCellPx << "\" height=\""
            << kCellPx << "\"/>\n";
      }
    }
  }
  svg << "</g>\n";
  // Paths first, so markers stay visible on top.
  for (int a = 0; a < n && !solution.empty(); ++a) {
    svg << "<polyline fill=\"none\" stroke-width=\"2\" stroke-opacity=\"0.8\" stroke-linejoin=\"round\" stroke=\""
        << agent_colour(a) << "\" points=\"";
    Vertex previous = kNoVertex;
    const double offset = ((a % 5) - 2) * 2.0;  // side by side where paths share a corridor
    for (const Config& config : solution) {
      if (config[a] == previous || config[a] == kNoVertex) continue;
      const Cell c = graph.cell_of(config[a]);
      svg << centre(c.x) + offset << "," << centre(c.y) + offset << " ";
      previous = config[a];
    }
    svg << "\"><title>agent " << a << "</title></polyline>\n";
  }
  for (int k = 0; k < instance.task_count(); ++k) {
    const Task& task = instance.tasks[k];
    const Cell c = graph.cell_of(task.at);
    const double r = kCellPx * 0.4;
    const std::string fill = task.agents.size() == 1 ? agent_colour(task.agents[0]) : "#ffd400";
    svg << "<polygon stroke=\"#000\" stroke-width=\"1\" fill=\"" << fill << "\" points=\"" << centre(c.x) << ","
        << centre(c.y) - r << " " << centre(c.x) + r << "," << centre(c.y) << " " << centre(c.x) << ","
        << centre(c.y) + r << " " << centre(c.x) - r << "," << centre(c.y) << "\"><title>task " << k << " agents";
    for (int a : task.agents) svg << " " << a;
    svg << "</title></polygon>\n";
  }
  for (int a = 0; a < n; ++a) {
    const Cell s = graph.cell_of(instance.starts[a]);
    const Cell g = graph.cell_of(instance.goals[a]);
    const std::string colour = agent_colour(a);
    svg << "<circle cx=\"" << centre(s.x) << "\" cy=\"" << centre(s.y) << "\" r=\"" << kCellPx * 0.35 << "\" fill=\""
        << colour << "\" stroke=\"#000\"><title>start of agent " << a << "</title></circle>\n";
    svg << "<rect x=\"" << g.x * kCellPx + 3 << "\" y=\"" << g.y * kCellPx + 3 << "\" width=\""
        << kCellPx - 6 << "\" height=\"" << kCellPx - 6 << "\" fill=\"none\" stroke-width=\"3\" stroke=\"" << colour
        << "\"><title>goal of agent " << a << "</title></rect>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

void write_svg(const std::string& path, const Instance& instance, const Solution& solution) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot write SVG file");
  out << render_svg(instance, solution);
}

}  // namespace planner_core
