// Grid <-> mat mapping: the shipped mat files, round trips through rotated and offset grids,
// lookups of poses between cells and off the mat, the least-squares fit, and load errors.
#include "robot_agent/mat_calibration.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <random>

#include "planner_core/input_error.hpp"

namespace robot_agent {
namespace {

namespace fs = std::filesystem;
const std::string kMats = CTSFLEET_CONFIG_DIR "/mats/";
const MatArea kRing{"ring", 45, 455, 45, 455};

// This process's temporary folder, removed when the test program ends.
struct TemporaryFolder {
  fs::path path = fs::temp_directory_path() / ("ctsfleet-mat-" + std::to_string(::getpid()));
  TemporaryFolder() { fs::create_directories(path); }
  ~TemporaryFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

std::string write_temp(const std::string& name, const std::string& text) {
  static TemporaryFolder folder;
  const fs::path path = folder.path / (name + ".yaml");
  std::ofstream(path) << text;
  return path.string();
}

std::string load_error(const std::string& text) {
  const std::string path = write_temp("bad", text);
  try {
    MatCalibration::load(path);
  } catch (const planner_core::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MatCalibration, ShippedMatFilesLoadAndRoundTripEveryCell) {
  for (const char* file : {"toio-collection-ring.yaml", "toio-collection-tiles.yaml", "toio-simple.yaml"}) {
    const MatCalibration mat = MatCalibration::load(kMats + file);
    EXPECT_TRUE(mat.problems().empty()) << file;
    for (int y = 0; y < mat.grid_height(); ++y) {
      for (int x = 0; x < mat.grid_width(); ++x) {
        const CellLookup lookup = mat.cell_at(mat.cell_centre({x, y}));
        EXPECT_EQ(lookup.status, CellLookup::Status::kOnCell) << file;
        EXPECT_EQ(lookup.cell, (Cell{x, y})) << file;
        EXPECT_NEAR(lookup.distance, 0, 1e-9);
      }
    }
  }
  const MatCalibration ring = MatCalibration::load(kMats + "toio-collection-ring.yaml");
  EXPECT_EQ(ring.cell_centre({0, 0}), Eigen::Vector2d(75, 75));
  EXPECT_EQ(ring.cell_centre({7, 7}), Eigen::Vector2d(425, 425));
  EXPECT_NEAR(ring.grid_heading_deg(), 0, 1e-9);
}

TEST(MatCalibration, RotatedGridRoundTripsAndHeadsAlongItsAxis) {
  const MatCalibration mat = MatCalibration::from_pitch(kRing, 6, 6, {250, 100}, 45, 90, 15);
  // Rotated 90 degrees clockwise: grid +x runs along mat +y, grid +y along mat -x.
  EXPECT_TRUE(mat.cell_centre({1, 0}).isApprox(Eigen::Vector2d(250, 145)));
  EXPECT_TRUE(mat.cell_centre({0, 1}).isApprox(Eigen::Vector2d(205, 100)));
  EXPECT_NEAR(mat.grid_heading_deg(), 90, 1e-9);
  for (int x = 0; x < 4; ++x) {
    for (int y = 0; y < 4; ++y) EXPECT_EQ(mat.cell_at(mat.cell_centre({x, y})).cell, (Cell{x, y}));
  }
}

TEST(MatCalibration, PosesBetweenCellsOrOffTheMatAreReportedNotRounded) {
  const MatCalibration mat = MatCalibration::load(kMats + "toio-collection-ring.yaml");
  const CellLookup near = mat.cell_at({75 + 17, 75});
  EXPECT_EQ(near.status, CellLookup::Status::kOnCell);
  const CellLookup between = mat.cell_at({75 + 25, 75});
  EXPECT_EQ(between.status, CellLookup::Status::kBetweenCells);
  EXPECT_NEAR(between.distance, 25, 1e-9);
  EXPECT_EQ(mat.cell_at({700, 383}).status, CellLookup::Status::kOffMat);
  EXPECT_EQ(mat.cell_at({46, 46}).status, CellLookup::Status::kOffGrid);  // on the mat, left of cell (0,0)'s reach
  EXPECT_EQ(std::string(describe(CellLookup::Status::kBetweenCells)), "between cells");
}

TEST(MatCalibration, FitRecoversAnAffineTransformFromThreeOrMoreCells) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(0, 360), pitch(42, 60), offset(100, 300), noise(-1.5, 1.5);
  for (int round = 0; round < 50; ++round) {
    const MatCalibration truth = MatCalibration::from_pitch(kRing, 5, 5, {offset(rng), offset(rng)}, pitch(rng),
                                                            angle(rng), 15);
    std::vector<CalibrationPoint> points;
    for (Cell cell : {Cell{0, 0}, Cell{4, 0}, Cell{0, 4}, Cell{4, 4}}) {
      points.push_back({cell, truth.cell_centre(cell)});
    }
    const CalibrationFit exact = fit_grid_to_mat(points);
    EXPECT_TRUE(exact.linear.isApprox(truth.linear(), 1e-9));
    EXPECT_TRUE(exact.offset.isApprox(truth.offset(), 1e-9));
    EXPECT_NEAR(exact.rms_residual, 0, 1e-6);
    for (CalibrationPoint& point : points) point.mat += Eigen::Vector2d(noise(rng), noise(rng));
    const CalibrationFit noisy = fit_grid_to_mat(points);
    EXPECT_GT(noisy.rms_residual, 0);
    EXPECT_LT(noisy.max_residual, 3.0);
    EXPECT_LT((noisy.offset - truth.offset()).norm(), 3.0);
  }
}

TEST(MatCalibration, FitRefusesTooFewOrCollinearCells) {
  const std::vector<CalibrationPoint> two = {{{0, 0}, {75, 75}}, {{1, 0}, {125, 75}}};
  EXPECT_THROW(fit_grid_to_mat(two), std::invalid_argument);
  const std::vector<CalibrationPoint> line = {{{0, 0}, {75, 75}}, {{1, 1}, {125, 125}}, {{2, 2}, {175, 175}}};
  EXPECT_THROW(fit_grid_to_mat(line), std::invalid_argument);
}

TEST(MatCalibration, SavedFitLoadsBackIdentically) {
  const MatCalibration original = MatCalibration::from_pitch(kRing, 7, 5, {120, 110}, 48, 12, 16);
  ASSERT_TRUE(original.problems().empty()) << original.problems().front();
  MatCalibration saved = original;
  saved.set_fit_residual(0.8);
  const std::string path = write_temp("saved", "");
  saved.save(path, "test");
  const MatCalibration loaded = MatCalibration::load(path);
  EXPECT_TRUE(loaded.linear().isApprox(original.linear(), 1e-6));
  EXPECT_TRUE(loaded.offset().isApprox(original.offset(), 1e-6));
  EXPECT_EQ(loaded.grid_width(), 7);
  EXPECT_EQ(loaded.grid_height(), 5);
  EXPECT_DOUBLE_EQ(loaded.tolerance(), 16);
  EXPECT_DOUBLE_EQ(loaded.fit_residual(), 0.8);
}

TEST(MatCalibration, LoadErrorsNameTheFileAndField) {
  const std::string mat = "mat: {name: m, x_range: [45, 455], y_range: [45, 455]}\n";
  EXPECT_NE(load_error(mat + "grid: {width: 8, height: 8, origin: [75, 75], pitch: 30}\n").find("pitch 30 is below 40"),
            std::string::npos);
  EXPECT_NE(load_error(mat + "grid: {width: 9, height: 8, origin: [75, 75], pitch: 50}\n").find("does not fit on the mat"),
            std::string::npos);
  EXPECT_NE(load_error(mat + "grid: {height: 8, origin: [75, 75], pitch: 50}\n").find("grid.width: missing"),
            std::string::npos);
  EXPECT_NE(load_error(mat + "grid: {width: 8, height: 8, origin: [75], pitch: 50}\n").find("grid.origin"),
            std::string::npos);
  EXPECT_NE(load_error(mat + "grid: {width: 8, height: 8, origin: [75, 75], pitch: 50, colour: red}\n").find("colour"),
            std::string::npos);
  EXPECT_NE(load_error("mat: {x_range: [455, 45], y_range: [45, 455]}\ngrid: {}\n").find("mat.x_range"),
            std::string::npos);
  EXPECT_NE(load_error(mat + "grid: [1, 2\n").find("bad.yaml"), std::string::npos);
  EXPECT_NE(load_error(mat + "grid: {width: 8, height: 8}\ntransform: {matrix: [[1, 2], [2, 4]], offset: [0, 0]}\n")
                .find("singular"),
            std::string::npos);
}

}  // namespace
}  // namespace robot_agent
