#include "planner_core/graph.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "planner_core/input_file.hpp"
#include "planner_core/input_error.hpp"

namespace planner_core {

namespace {
constexpr int kTileWidth = 8;   // 8 x 4 cells of 16-bit distances: one 64-byte cache line
constexpr int kTileHeight = 4;
}  // namespace

static bool is_free_symbol(char c) { return c == '.' || c == 'G'; }

Graph::Graph(int width, int height, const std::vector<std::string>& rows)
    : width_(width), height_(height), rows_(rows) {
  // Every caller reads rows and size from outside (a map file, a mission on the wire, a history):
  // rows that do not cover the size would be read past their end.
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument("a map of " + std::to_string(width) + " x " + std::to_string(height) + " cells");
  }
  if (static_cast<int64_t>(rows.size()) < height) {
    throw std::invalid_argument("a map of height " + std::to_string(height) + " with " + std::to_string(rows.size()) +
                                " rows");
  }
  for (int y = 0; y < height; ++y) {
    if (static_cast<int64_t>(rows[y].size()) < width) {
      throw std::invalid_argument("a map of width " + std::to_string(width) + " whose row " + std::to_string(y) +
                                  " has " + std::to_string(rows[y].size()) + " cells");
    }
  }
  // Vertices are numbered tile by tile (kTileWidth x kTileHeight cells, row by row inside a
  // tile), not row by row over the whole map: a cell's neighbours above and below then mostly
  // have numbers close to its own, so the per-vertex tables read in one step (a distance for each
  // move of an agent) share cache lines. At 10,000 agents those reads are cache misses.
  vertex_of_index_.assign(static_cast<size_t>(width) * height, kNoVertex);
  for (int tile_y = 0; tile_y < height; tile_y += kTileHeight) {
    for (int tile_x = 0; tile_x < width; tile_x += kTileWidth) {
      for (int y = tile_y; y < std::min(height, tile_y + kTileHeight); ++y) {
        for (int x = tile_x; x < std::min(width, tile_x + kTileWidth); ++x) {
          if (is_free_symbol(rows[y][x])) {
            vertex_of_index_[y * width + x] = static_cast<Vertex>(cells_.size());
            cells_.push_back({x, y});
          }
        }
      }
    }
  }
  neighbours_.resize(cells_.size());
  for (Vertex v = 0; v < vertex_count(); ++v) {
    const Cell c = cells_[v];
    for (Cell n : {Cell{c.x, c.y - 1}, Cell{c.x + 1, c.y}, Cell{c.x, c.y + 1}, Cell{c.x - 1, c.y}}) {
      const Vertex u = vertex_at(n);
      if (u == kNoVertex) continue;
      Neighbourhood& around = neighbours_[v];
      if (around.count >= kMaxDegree) throw std::logic_error("grid vertex with more than kMaxDegree neighbours");
      around.vertices[around.count++] = u;
    }
  }
}

bool Graph::inside(Cell cell) const {
  return cell.x >= 0 && cell.y >= 0 && cell.x < width_ && cell.y < height_;
}

Vertex Graph::vertex_at(Cell cell) const {
  if (!inside(cell)) return kNoVertex;
  return vertex_of_index_[cell.y * width_ + cell.x];
}

bool Graph::adjacent(Vertex a, Vertex b) const {
  const auto around = neighbours(a);
  return std::find(around.begin(), around.end(), b) != around.end();
}

bool Graph::is_open(Vertex v) const {
  if (v < 0 || v >= vertex_count()) return false;
  const Cell c = cells_[v];
  return vertex_of_index_[c.y * width_ + c.x] == v;
}

Graph Graph::with_walls(const std::set<Vertex>& walls) const {
  Graph walled = *this;
  for (Vertex w : walls) {
    if (w < 0 || w >= vertex_count()) throw std::out_of_range("with_walls: vertex " + std::to_string(w) + " is not on the map");
    const Cell c = cells_[w];
    walled.rows_[c.y][c.x] = '@';
    walled.vertex_of_index_[c.y * width_ + c.x] = kNoVertex;
    walled.neighbours_[w].count = 0;
  }
  for (Neighbourhood& around : walled.neighbours_) {
    int kept = 0;
    for (int i = 0; i < around.count; ++i) {
      if (!walls.count(around.vertices[i])) around.vertices[kept++] = around.vertices[i];
    }
    around.count = kept;
  }
  return walled;
}

Graph load_movingai_map(const std::string& path, MapSymbols symbols) {
  require_regular_file(path, "map file");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open map file");
  int width = -1, height = -1;
  std::string line;
  int line_no = 0;
  bool saw_map = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key;
    if (!(words >> key)) continue;
    if (key == "map") {
      saw_map = true;
      break;
    }
    if (key == "type") continue;
    if (key != "height" && key != "width") {
      throw InputError(path + ":" + std::to_string(line_no) + ": unknown header line '" + line + "'");
    }
    int value = 0;
    if (!(words >> value) || value <= 0) {
      throw InputError(path + ":" + std::to_string(line_no) + ": " + key + " must be a positive integer");
    }
    if (value > kMaxMapSide) {
      throw InputError(path + ":" + std::to_string(line_no) + ": " + key + " " + std::to_string(value) +
                       " is more than the " + std::to_string(kMaxMapSide) + " cells a map side may have");
    }
    (key == "height" ? height : width) = value;
  }
  if (!saw_map) throw InputError(path + ": missing 'map' line after the header");
  if (width < 0 || height < 0) throw InputError(path + ": header must give both width and height");
  std::vector<std::string> rows;
  while (static_cast<int>(rows.size()) < height && std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (static_cast<int>(line.size()) < width) {
      throw InputError(path + ":" + std::to_string(line_no) + ": row has " + std::to_string(line.size()) +
                       " cells, expected width " + std::to_string(width));
    }
    line.resize(width);
    for (int x = 0; x < width; ++x) {
      char& c = line[x];
      if (symbols == MapSymbols::kLeagueOfRobotRunners) {
        if (c == 'E' || c == 'S') {
          c = '.';
        } else if (c != '.' && c != '@' && c != 'T') {
          throw InputError(path + ":" + std::to_string(line_no) + ": unknown map symbol '" + std::string(1, c) +
                           "' at column " + std::to_string(x) + " (a League of Robot Runners map has . E S @ T)");
        }
      }
      if (!is_free_symbol(c) && c != '@' && c != 'O' && c != 'T' && c != 'S' && c != 'W') {
        throw InputError(path + ":" + std::to_string(line_no) + ": unknown map symbol '" + std::string(1, c) +
                         "' at column " + std::to_string(x));
      }
    }
    rows.push_back(line);
  }
  if (static_cast<int>(rows.size()) < height) {
    throw InputError(path + ": map has " + std::to_string(rows.size()) + " rows, header says height " +
                     std::to_string(height));
  }
  Graph graph(width, height, rows);
  graph.name = std::filesystem::path(path).stem().string();
  return graph;
}

std::vector<int> connected_parts(const Graph& graph) {
  std::vector<int> part(graph.vertex_count(), -1);
  int parts = 0;
  for (Vertex seed = 0; seed < graph.vertex_count(); ++seed) {
    if (part[seed] != -1) continue;
    std::vector<Vertex> stack{seed};
    part[seed] = parts;
    while (!stack.empty()) {
      const Vertex v = stack.back();
      stack.pop_back();
      for (Vertex u : graph.neighbours(v)) {
        if (part[u] == -1) {
          part[u] = parts;
          stack.push_back(u);
        }
      }
    }
    ++parts;
  }
  return part;
}

}  // namespace planner_core
