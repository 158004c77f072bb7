#include "planner_core/svg_writer.hpp"

#include <algorithm>
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

constexpr int kLegendPx = 48;

double centre(int coordinate) { return coordinate * kCellPx + kCellPx / 2.0; }

// The key below the map: what the marks mean and how time shows along a path.
void draw_legend(std::ostringstream& svg, int width_px, int top_px) {
  const double y = top_px + 16;
  svg << "<g font-family=\"sans-serif\" font-size=\"12\" fill=\"#000\">\n"
      << "<rect x=\"0\" y=\"" << top_px << "\" width=\"" << width_px << "\" height=\"" << kLegendPx
      << "\" fill=\"#f4f4f4\"/>\n"
      << "<circle cx=\"12\" cy=\"" << y << "\" r=\"6\" fill=\"#4a7fd4\" stroke=\"#000\"/>"
      << "<text x=\"22\" y=\"" << y + 4 << "\">start</text>\n"
      << "<rect x=\"66\" y=\"" << y - 6 << "\" width=\"12\" height=\"12\" fill=\"none\" stroke-width=\"3\" "
      << "stroke=\"#4a7fd4\"/><text x=\"84\" y=\"" << y + 4 << "\">goal</text>\n"
      << "<polygon points=\"132," << y - 7 << " 139," << y << " 132," << y + 7 << " 125," << y
      << "\" fill=\"#4a7fd4\" stroke=\"#000\"/><text x=\"144\" y=\"" << y + 4 << "\">task of one agent</text>\n"
      << "<polygon points=\"262," << y - 7 << " 269," << y << " 262," << y + 7 << " 255," << y
      << "\" fill=\"#ffd400\" stroke=\"#000\"/><text x=\"274\" y=\"" << y + 4 << "\">shared task</text>\n";
  const double y2 = top_px + 36;
  for (int i = 0; i < 10; ++i) {
    svg << "<line x1=\"" << 8 + i * 8 << "\" y1=\"" << y2 << "\" x2=\"" << 16 + i * 8 << "\" y2=\"" << y2
        << "\" stroke=\"#4a7fd4\" stroke-width=\"3\" stroke-opacity=\"" << 0.15 + 0.085 * i << "\"/>";
  }
  svg << "<text x=\"94\" y=\"" << y2 + 4 << "\">path: faint early, solid late (one colour per agent)</text>\n</g>\n";
}

}  // namespace

std::string render_svg(const Instance& instance, const Solution& solution) {
  const Graph& graph = *instance.graph;
  const int n = instance.agent_count();
  std::ostringstream svg;
  const int width_px = std::max(graph.width() * kCellPx, 380), map_px = graph.height() * kCellPx;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width_px << "\" height=\"" << map_px + kLegendPx
      << "\" viewBox=\"0 0 " << width_px << " " << map_px + kLegendPx << "\">\n";
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
  // Paths first, so markers stay visible on top. Time shows as opacity: each path is cut into
  // kTimeBands polylines by when its moves happen, faint early, solid late.
  constexpr int kTimeBands = 8;
  const double last_step = std::max<double>(1.0, static_cast<double>(solution.size()) - 1);
  const auto band_of = [&](size_t t) { return std::min(kTimeBands - 1, static_cast<int>(kTimeBands * (t - 1) / last_step)); };
  for (int a = 0; a < n && !solution.empty(); ++a) {
    svg << "<g fill=\"none\" stroke-width=\"2\" stroke-linejoin=\"round\" stroke=\"" << agent_colour(a)
        << "\"><title>agent " << a << "</title>\n";
    const double offset = ((a % 5) - 2) * 2.0;  // side by side where paths share a corridor
    const auto point = [&](Vertex v) {
      const Cell c = graph.cell_of(v);
      std::ostringstream text;
      text << centre(c.x) + offset << "," << centre(c.y) + offset << " ";
      return text.str();
    };
    int open_band = -1;  // the band of the polyline being written, -1 when none is open
    for (size_t t = 1; t < solution.size(); ++t) {
      const Vertex from = solution[t - 1][a], to = solution[t][a];
      if (from == to || from == kNoVertex || to == kNoVertex) continue;
      const int band = band_of(t);
      if (band != open_band) {
        if (open_band >= 0) svg << "\"/>\n";
        svg << "<polyline stroke-opacity=\"" << 0.15 + 0.85 * (band + 1) / kTimeBands << "\" points=\"" << point(from);
        open_band = band;
      }
      svg << point(to);
    }
    if (open_band >= 0) svg << "\"/>\n";
    svg << "</g>\n";
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
  draw_legend(svg, width_px, map_px);
  svg << "</svg>\n";
  return svg.str();
}

void write_svg(const std::string& path, const Instance& instance, const Solution& solution) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot write SVG file");
  out << render_svg(instance, solution);
}

}  // namespace planner_core
