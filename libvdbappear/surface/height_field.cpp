#include "libvdbappear/surface/height_field.h"

#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

HeightField::HeightField(int cells_x, int cells_y, double cell_size)
    : cells_x_(cells_x), cells_y_(cells_y), cell_size_(cell_size) {
  if (cells_x < 1 || cells_y < 1) throw std::invalid_argument("a height field needs at least one cell per side");
  if (!(cell_size > 0) || !std::isfinite(cell_size)) throw std::invalid_argument("cell size must be positive");
  heights_.assign(static_cast<std::size_t>(cells_x + 1) * (cells_y + 1), 0.0);
}

Point2 HeightField::gradient(int i, int j, double x, double y) const {
  const double h00 = at(i, j), h10 = at(i + 1, j), h01 = at(i, j + 1), h11 = at(i + 1, j + 1);
  return Point2((h10 - h00) * (1 - y) + (h11 - h01) * y, (h01 - h00) * (1 - x) + (h11 - h10) * x) / cell_size_;
}

Point2 HeightField::averageSlope(int i0, int j0, int count) const {
  Point2 sum = Point2::Zero();
  for (int j = j0; j < j0 + count; ++j)
    for (int i = i0; i < i0 + count; ++i) sum += cellSlope(i, j);
  return sum / (static_cast<double>(count) * count);
}

double HeightField::meanHeight() const {
  double sum = 0;
  for (int j = 0; j < cells_y_; ++j)
    for (int i = 0; i < cells_x_; ++i) sum += at(i, j) + at(i + 1, j) + at(i, j + 1) + at(i + 1, j + 1);
  return sum / (4.0 * cells_x_ * cells_y_);
}

void validateHeights(const HeightField& field, const std::string& source) {
  for (int j = 0; j < field.verticesY(); ++j)
    for (int i = 0; i < field.verticesX(); ++i)
      if (!std::isfinite(field.at(i, j)))
        throw MediumError(source + ": height at vertex (" + std::to_string(i) + ", " + std::to_string(j) +
                          ") is not a finite number");
}

void validateSeamless(const HeightField& field, const std::string& source, double tolerance) {
  double lowest = field.heights().front(), highest = lowest;
  for (double h : field.heights()) lowest = std::min(lowest, h), highest = std::max(highest, h);
  const double allowed = tolerance * (highest - lowest);
  const int nx = field.cellsX(), ny = field.cellsY();
  const auto check = [&](int i, int j, int i_twin, int j_twin) {
    const double step = std::abs(field.at(i, j) - field.at(i_twin, j_twin));
    if (step > allowed)
      throw MediumError(fmt::format("{}: the map does not tile seamlessly: vertex ({}, {}) and its twin on the opposite "
                                    "edge ({}, {}) differ by {:.4g}, more than {:g}% of the map's relief ({:.4g})",
                                    source, i, j, i_twin, j_twin, step, tolerance * 100, highest - lowest));
  };
  for (int j = 0; j <= ny; ++j) check(0, j, nx, j);
  for (int i = 0; i <= nx; ++i) check(i, 0, i, ny);
}

}  // namespace vdbappear
