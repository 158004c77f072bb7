#include "robot_agent/mat_calibration.hpp"

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "planner_core/input_error.hpp"
#include "planner_core/yaml_context.hpp"

namespace robot_agent {

const char* describe(CellLookup::Status status) {
  switch (status) {
    case CellLookup::Status::kOnCell: return "on a cell";
    case CellLookup::Status::kBetweenCells: return "between cells";
    case CellLookup::Status::kOffGrid: return "on the mat but off the grid";
    case CellLookup::Status::kOffMat: return "off the mat";
  }
  return "unknown";
}

MatCalibration::MatCalibration(MatArea mat, int grid_width, int grid_height, Eigen::Matrix2d linear,
                               Eigen::Vector2d offset, double tolerance)
    : mat_(std::move(mat)),
      grid_width_(grid_width),
      grid_height_(grid_height),
      linear_(linear),
      offset_(offset),
      tolerance_(tolerance) {
  if (std::abs(linear_.determinant()) < 1e-9) throw std::invalid_argument("the grid-to-mat transform is singular");
  inverse_ = linear_.inverse();
}

MatCalibration MatCalibration::from_pitch(MatArea mat, int grid_width, int grid_height, Eigen::Vector2d origin,
                                          double pitch, double rotation_deg, double tolerance) {
  const double r = rotation_deg * std::numbers::pi / 180.0;
  Eigen::Matrix2d linear;
  // Clockwise on a mat whose y axis points down is the usual counter-clockwise matrix.
  linear << std::cos(r), -std::sin(r), std::sin(r), std::cos(r);
  return MatCalibration(std::move(mat), grid_width, grid_height, pitch * linear, origin, tolerance);
}

Eigen::Vector2d MatCalibration::cell_centre(Cell cell) const {
  return linear_ * Eigen::Vector2d(cell.x, cell.y) + offset_;
}

CellLookup MatCalibration::cell_at(const Eigen::Vector2d& mat_pose) const {
  CellLookup lookup;
  lookup.grid = inverse_ * (mat_pose - offset_);
  lookup.cell = {static_cast<int>(std::lround(lookup.grid.x())), static_cast<int>(std::lround(lookup.grid.y()))};
  lookup.distance = (cell_centre(lookup.cell) - mat_pose).norm();
  if (!mat_.contains(mat_pose)) {
    lookup.status = CellLookup::Status::kOffMat;
  } else if (lookup.cell.x < 0 || lookup.cell.y < 0 || lookup.cell.x >= grid_width_ || lookup.cell.y >= grid_height_) {
    lookup.status = CellLookup::Status::kOffGrid;
  } else {
    lookup.status = lookup.distance <= tolerance_ ? CellLookup::Status::kOnCell : CellLookup::Status::kBetweenCells;
  }
  return lookup;
}

double MatCalibration::grid_heading_deg() const {
  const Eigen::Vector2d axis = linear_.col(0);
  double heading = std::atan2(axis.y(), axis.x()) * 180.0 / std::numbers::pi;
  if (heading < 0) heading += 360.0;
  return heading;
}

double MatCalibration::heading_on_mat_deg(int heading) const {
  const Cell ahead[] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  const Cell step = ahead[((heading % 4) + 4) % 4];
  const Eigen::Vector2d direction = linear_ * Eigen::Vector2d(step.x, step.y);
  double angle = std::atan2(direction.y(), direction.x()) * 180.0 / std::numbers::pi;
  if (angle < 0) angle += 360.0;
  return angle;
}

int MatCalibration::nearest_heading(double mat_angle_deg) const {
  int best = 0;
  double best_difference = 360;
  for (int heading = 0; heading < 4; ++heading) {
    const double difference = std::abs(std::remainder(mat_angle_deg - heading_on_mat_deg(heading), 360.0));
    if (difference < best_difference) best = heading, best_difference = difference;
  }
  return best;
}

double MatCalibration::smallest_pitch() const {
  // Neighbours differ by one grid axis; the mat distance is the length of that column.
  return std::min(linear_.col(0).norm(), linear_.col(1).norm());
}

std::vector<std::string> MatCalibration::problems() const {
  std::vector<std::string> found;
  std::ostringstream text;
  if (grid_width_ < 1 || grid_height_ < 1) found.push_back("the grid must be at least 1x1");
  if (smallest_pitch() < kMinimumPitch) {
    text << "the cell pitch " << smallest_pitch() << " is below " << kMinimumPitch
         << " mat units: a turning cube (about 32 wide) would touch its neighbour";
    found.push_back(text.str());
  }
  for (Cell corner : {Cell{0, 0}, Cell{grid_width_ - 1, 0}, Cell{0, grid_height_ - 1},
                          Cell{grid_width_ - 1, grid_height_ - 1}}) {
    const Eigen::Vector2d centre = cell_centre(corner);
    if (!mat_.contains(centre, kCubeHalfWidth)) {
      std::ostringstream corner_text;
      corner_text << "cell (" << corner.x << "," << corner.y << ") is centred at (" << centre.x() << ", " << centre.y()
                  << "), not at least " << kCubeHalfWidth << " inside the mat's area x " << mat_.x_min << "-"
                  << mat_.x_max << ", y " << mat_.y_min << "-" << mat_.y_max << ": the grid does not fit on the mat";
      found.push_back(corner_text.str());
    }
  }
  if (tolerance_ <= 0 || tolerance_ >= smallest_pitch() / 2) {
    found.push_back("the tolerance must be positive and below half the pitch, or one pose could match two cells");
  }
  return found;
}

namespace {

Eigen::Vector2d read_pair(const planner_core::YamlContext& context, const YAML::Node& node, const std::string& field) {
  if (!node || !node.IsSequence() || node.size() != 2) context.fail(node, field, "must be a list of two numbers");
  try {
    return {node[0].as<double>(), node[1].as<double>()};
  } catch (const YAML::Exception&) {
    context.fail(node, field, "must be a list of two numbers");
  }
}

double read_number(const planner_core::YamlContext& context, const YAML::Node& map, const std::string& key,
                   const std::string& field) {
  const YAML::Node node = map[key];
  if (!node) context.fail(map, field + "." + key, "missing");
  try {
    return node.as<double>();
  } catch (const YAML::Exception&) {
    context.fail(node, field + "." + key, "must be a number");
  }
}

}  // namespace

MatCalibration MatCalibration::load(const std::string& path) {
  const YAML::Node root = planner_core::load_yaml_file(path);
  const planner_core::YamlContext context(path);
  if (!root.IsMap()) context.fail(root, "(top level)", "must be a map with keys mat and grid");
  context.only_keys(root, {"mat", "grid", "transform"}, "(top level)");

  const YAML::Node mat_node = root["mat"];
  if (!mat_node || !mat_node.IsMap()) context.fail(root, "mat", "missing or not a map");
  context.only_keys(mat_node, {"name", "x_range", "y_range"}, "mat");
  MatArea mat;
  context.read(mat_node, "name", "mat", mat.name);
  const Eigen::Vector2d xs = read_pair(context, mat_node["x_range"], "mat.x_range");
  const Eigen::Vector2d ys = read_pair(context, mat_node["y_range"], "mat.y_range");
  if (xs[0] >= xs[1]) context.fail(mat_node["x_range"], "mat.x_range", "must be [min, max] with min < max");
  if (ys[0] >= ys[1]) context.fail(mat_node["y_range"], "mat.y_range", "must be [min, max] with min < max");
  mat.x_min = xs[0], mat.x_max = xs[1], mat.y_min = ys[0], mat.y_max = ys[1];

  const YAML::Node grid = root["grid"];
  if (!grid || !grid.IsMap()) context.fail(root, "grid", "missing or not a map");
  context.only_keys(grid, {"width", "height", "origin", "pitch", "rotation_deg", "tolerance"}, "grid");
  if (!grid["width"]) context.fail(grid, "grid.width", "missing");
  if (!grid["height"]) context.fail(grid, "grid.height", "missing");
  const int width = context.integer(grid["width"], "grid.width");
  const int height = context.integer(grid["height"], "grid.height");
  if (width < 1) context.fail(grid["width"], "grid.width", "must be at least 1");
  if (height < 1) context.fail(grid["height"], "grid.height", "must be at least 1");
  double tolerance = 18;
  if (grid["tolerance"]) tolerance = read_number(context, grid, "tolerance", "grid");

  Eigen::Matrix2d linear;
  Eigen::Vector2d offset;
  double residual = -1;
  if (const YAML::Node transform = root["transform"]) {
    context.only_keys(transform, {"matrix", "offset", "rms_residual"}, "transform");
    const YAML::Node matrix = transform["matrix"];
    if (!matrix || !matrix.IsSequence() || matrix.size() != 2) {
      context.fail(transform, "transform.matrix", "must be [[a, b], [c, d]]");
    }
    linear.row(0) = read_pair(context, matrix[0], "transform.matrix[0]");
    linear.row(1) = read_pair(context, matrix[1], "transform.matrix[1]");
    offset = read_pair(context, transform["offset"], "transform.offset");
    if (transform["rms_residual"]) residual = read_number(context, transform, "rms_residual", "transform");
    if (std::abs(linear.determinant()) < 1e-9) context.fail(matrix, "transform.matrix", "is singular");
  } else {
    const Eigen::Vector2d origin = read_pair(context, grid["origin"], "grid.origin");
    const double pitch = read_number(context, grid, "pitch", "grid");
    if (pitch <= 0) context.fail(grid["pitch"], "grid.pitch", "must be positive");
    double rotation = 0;
    if (grid["rotation_deg"]) rotation = read_number(context, grid, "rotation_deg", "grid");
    const MatCalibration c = from_pitch(mat, width, height, origin, pitch, rotation, tolerance);
    linear = c.linear_;
    offset = c.offset_;
  }
  MatCalibration calibration(mat, width, height, linear, offset, tolerance);
  calibration.fit_residual_ = residual;
  const std::vector<std::string> problems = calibration.problems();
  if (!problems.empty()) context.fail(grid, "grid", problems.front());
  return calibration;
}

void MatCalibration::save(const std::string& path, const std::string& comment) const {
  auto tidy = [](double value) { return std::round(value * 1e4) / 1e4 + 0.0; };  // no 1e-14 noise, no -0
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "mat" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << mat_.name;
  out << YAML::Key << "x_range" << YAML::Value << YAML::Flow << YAML::BeginSeq << mat_.x_min << mat_.x_max << YAML::EndSeq;
  out << YAML::Key << "y_range" << YAML::Value << YAML::Flow << YAML::BeginSeq << mat_.y_min << mat_.y_max << YAML::EndSeq;
  out << YAML::EndMap;
  out << YAML::Key << "grid" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "width" << YAML::Value << grid_width_;
  out << YAML::Key << "height" << YAML::Value << grid_height_;
  out << YAML::Key << "tolerance" << YAML::Value << tolerance_;
  out << YAML::EndMap;
  out << YAML::Key << "transform" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "matrix" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int row = 0; row < 2; ++row) {
    out << YAML::Flow << YAML::BeginSeq << tidy(linear_(row, 0)) << tidy(linear_(row, 1)) << YAML::EndSeq;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "offset" << YAML::Value << YAML::Flow << YAML::BeginSeq << tidy(offset_.x()) << tidy(offset_.y()) << YAML::EndSeq;
  if (fit_residual_ >= 0) out << YAML::Key << "rms_residual" << YAML::Value << tidy(fit_residual_);
  out << YAML::EndMap;
  out << YAML::EndMap;
  std::ofstream file(path);
  if (!file) throw std::runtime_error("cannot write " + path);
  if (!comment.empty()) file << "# " << comment << "\n";
  file << out.c_str() << "\n";
  if (!file) throw std::runtime_error("error writing " + path);
}

CalibrationFit fit_grid_to_mat(std::span<const CalibrationPoint> points) {
  if (points.size() < 3) throw std::invalid_argument("calibration needs at least three cells");
  // Unknowns (a b c d e f): mat_x = a x + b y + e, mat_y = c x + d y + f.
  Eigen::MatrixXd design(points.size(), 3);
  Eigen::MatrixXd targets(points.size(), 2);
  for (size_t i = 0; i < points.size(); ++i) {
    design.row(static_cast<Eigen::Index>(i)) << points[i].cell.x, points[i].cell.y, 1.0;
    targets.row(static_cast<Eigen::Index>(i)) = points[i].mat.transpose();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
  if (qr.rank() < 3) throw std::invalid_argument("the calibration cells lie on one line; use three or more cells not in a line");
  const Eigen::MatrixXd solution = qr.solve(targets);  // 3 x 2
  CalibrationFit fit;
  fit.linear << solution(0, 0), solution(1, 0), solution(0, 1), solution(1, 1);
  fit.offset << solution(2, 0), solution(2, 1);
  double sum_squares = 0;
  for (const CalibrationPoint& point : points) {
    const double error = (fit.linear * Eigen::Vector2d(point.cell.x, point.cell.y) + fit.offset - point.mat).norm();
    sum_squares += error * error;
    fit.max_residual = std::max(fit.max_residual, error);
  }
  fit.rms_residual = std::sqrt(sum_squares / static_cast<double>(points.size()));
  return fit;
}

}  // namespace robot_agent
