// MatCalibration: where the planner's grid lies on a toio position mat. A 2-D affine transform maps
// a cell (x, y) to the mat coordinates of its centre, so the grid may sit rotated, mirrored or offset
// on the mat; the inverse maps a reported pose back to a cell, within a tolerance. Loaded from and
// saved to config/mats/*.yaml; fitted by least squares from a cube placed on known cells.
#pragma once

#include <Eigen/Dense>
#include <span>
#include <string>
#include <vector>

#include "robot_agent/robot_backend.hpp"

namespace robot_agent {

// A toio cube is about 32 mat units wide; turning in place it sweeps a circle of radius
// 32 * sqrt(2) / 2 = 22.6. It passes a standing neighbour (half width 16) when cell centres are at
// least 22.6 + 16 = 38.6 apart: the smallest pitch accepted is 40.
inline constexpr double kCubeHalfWidth = 16.0;
inline constexpr double kMinimumPitch = 40.0;

struct MatArea {
  std::string name;
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  bool contains(const Eigen::Vector2d& p, double margin = 0) const {
    return p.x() >= x_min + margin && p.x() <= x_max - margin && p.y() >= y_min + margin && p.y() <= y_max - margin;
  }
};

// Where a mat pose falls on the grid.
struct CellLookup {
  enum class Status { kOnCell, kBetweenCells, kOffGrid, kOffMat };
  Status status = Status::kOffMat;
  Cell cell;            // the nearest cell (meaningful for kOnCell and kBetweenCells)
  double distance = 0;      // mat units from that cell's centre
  Eigen::Vector2d grid{0, 0};  // continuous grid coordinates (cell units)
};
const char* describe(CellLookup::Status status);

struct CalibrationPoint {
  Cell cell;
  Eigen::Vector2d mat;
};

class MatCalibration {
 public:
  // mat = linear * (x, y) + offset.
  MatCalibration(MatArea mat, int grid_width, int grid_height, Eigen::Matrix2d linear, Eigen::Vector2d offset,
                 double tolerance);
  // Origin = centre of cell (0, 0); rotation measured clockwise (the mat's y axis points down).
  static MatCalibration from_pitch(MatArea mat, int grid_width, int grid_height, Eigen::Vector2d origin, double pitch,
                                   double rotation_deg, double tolerance);
  // Reads a mat file; every problem (including a grid that does not fit or a too small pitch) is a
  // planner_core::InputError naming the file and field.
  static MatCalibration load(const std::string& path);
  void save(const std::string& path, const std::string& comment = "") const;

  Eigen::Vector2d cell_centre(Cell cell) const;
  CellLookup cell_at(const Eigen::Vector2d& mat_pose) const;
  // Heading on the mat (degrees, clockwise from +x) that points along the grid's +x axis.
  double grid_heading_deg() const;
  // Heading on the mat (degrees 0-360, clockwise from +x) of a grid heading (0 east ... 3 north,
  // planner_core/compass.hpp): the way a step along it goes on the mat.
  double heading_on_mat_deg(int heading) const;
  // The grid heading whose direction on the mat is nearest to `mat_angle_deg`.
  int nearest_heading(double mat_angle_deg) const;

  // Problems that make the calibration unusable (empty when fine).
  std::vector<std::string> problems() const;

  const MatArea& mat() const { return mat_; }
  int grid_width() const { return grid_width_; }
  int grid_height() const { return grid_height_; }
  double tolerance() const { return tolerance_; }
  double smallest_pitch() const;  // the closest two neighbouring cell centres come, in mat units
  const Eigen::Matrix2d& linear() const { return linear_; }
  const Eigen::Vector2d& offset() const { return offset_; }
  double fit_residual() const { return fit_residual_; }
  void set_fit_residual(double rms) { fit_residual_ = rms; }

 private:
  MatArea mat_;
  int grid_width_ = 0;
  int grid_height_ = 0;
  Eigen::Matrix2d linear_;
  Eigen::Vector2d offset_;
  Eigen::Matrix2d inverse_;
  double tolerance_ = 18;
  double fit_residual_ = -1;  // RMS of the least-squares fit, when fitted
};

struct CalibrationFit {
  Eigen::Matrix2d linear;
  Eigen::Vector2d offset;
  double rms_residual = 0;  // mat units
  double max_residual = 0;
};

// Least-squares affine fit from three or more cells that are not all on one line; throws
// std::invalid_argument otherwise.
CalibrationFit fit_grid_to_mat(std::span<const CalibrationPoint> points);

}  // namespace robot_agent
