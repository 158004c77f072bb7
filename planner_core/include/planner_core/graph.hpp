// Graph: a 4-connected grid map with dense vertex ids for the free cells (MovingAI .map).
#pragma once

#include <array>
#include <set>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "planner_core/cell.hpp"

namespace planner_core {

using Vertex = int;  // dense id of a free cell, 0 .. vertex_count()-1 (numbered in 8 x 4 tiles: graph.cpp)
constexpr Vertex kNoVertex = -1;
using Config = std::vector<Vertex>;  // one vertex per agent at one timestep
constexpr int kMaxDegree = 4;  // 4-connected grid: up, down, left, right

// The moves open to an agent in one step (its neighbours and staying), with a key per move.
using Moves = std::array<Vertex, kMaxDegree + 1>;
using MoveKeys = std::array<int, kMaxDegree + 1>;

// Sorts moves[0..count) by key, smallest first, keeping the order of equal keys (so a shuffle
// before it breaks ties at random).
inline void sort_by_key(Moves& moves, MoveKeys& keys, int count) {
  for (int i = 1; i < count; ++i) {
    for (int j = i; j > 0 && keys[j] < keys[j - 1]; --j) {
      std::swap(keys[j], keys[j - 1]);
      std::swap(moves[j], moves[j - 1]);
    }
  }
}

class Graph {
 public:
  Graph() = default;
  // rows[y][x]: '.' and 'G' are free, anything else is blocked.
  Graph(int width, int height, const std::vector<std::string>& rows);

  int width() const { return width_; }
  int height() const { return height_; }
  int vertex_count() const { return static_cast<int>(cells_.size()); }

  bool inside(Cell cell) const;
  bool is_free(Cell cell) const { return vertex_at(cell) != kNoVertex; }
  Vertex vertex_at(Cell cell) const;  // kNoVertex when outside or blocked
  Cell cell_of(Vertex v) const { return cells_[v]; }
  std::span<const Vertex> neighbours(Vertex v) const {
    return {neighbours_[v].vertices.data(), static_cast<size_t>(neighbours_[v].count)};
  }
  bool adjacent(Vertex a, Vertex b) const;
  // A vertex an agent may stand on: in range and not walled (see with_walls).
  bool is_open(Vertex v) const;

  // The same map with these vertices walled. Vertex ids stay as they are, so instances and plans on
  // the walled map share the original's vertex space: a walled vertex keeps its cell (cell_of) but
  // has no neighbours, no neighbour leads to it, and vertex_at no longer finds it.
  Graph with_walls(const std::set<Vertex>& walls) const;

  // Row strings as read ('.' free, '@' blocked), for drawing.
  const std::vector<std::string>& rows() const { return rows_; }
  std::string name;  // file stem, e.g. "maze-32-32-2"

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<std::string> rows_;
  std::vector<Vertex> vertex_of_index_;  // y * width + x -> vertex or kNoVertex
  std::vector<Cell> cells_;
  // Each vertex's neighbours in one fixed-size record, so that a breadth-first search reads one
  // place per vertex (the hot loop of the distance tables).
  struct Neighbourhood {
    std::array<Vertex, kMaxDegree> vertices{};
    int count = 0;
  };
  std::vector<Neighbourhood> neighbours_;
};

// Reads a MovingAI .map file; throws InputError naming the file and line.
// Which symbols a map file's cells may hold: MovingAI's ('.' and 'G' free; '@', 'O', 'T', 'S'
// (swamp), 'W' blocked), or the League of Robot Runners' ('.', 'E' emitter and 'S' service point
// free; '@' and 'T' blocked).
enum class MapSymbols { kMovingAi, kLeagueOfRobotRunners };
Graph load_movingai_map(const std::string& path, MapSymbols symbols = MapSymbols::kMovingAi);

// Each vertex's part of the map: vertices joined by moves share a label (0, 1, ...).
std::vector<int> connected_parts(const Graph& graph);

}  // namespace planner_core
