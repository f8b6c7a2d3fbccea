#pragma once
// A displacement map as the displacement chapter defines it (shared/papers/002_6a636dc24396287c.txt,
// §4.4.1): heights at the vertices of a regular grid over a planar patch, bilinear within each
// cell. Vertex (i, j) sits at (i, j) * cell_size; i runs along the image's columns, j along its rows.

#include "libvdbappear/math/vector.h"

#include <string>
#include <vector>

namespace vdbappear {

class HeightField {
 public:
  HeightField() = default;
  // cells_x x cells_y cells (>= 1 each), heights 0; cell_size > 0 in world units.
  HeightField(int cells_x, int cells_y, double cell_size);

  int cellsX() const { return cells_x_; }
  int cellsY() const { return cells_y_; }
  double cellSize() const { return cell_size_; }
  int verticesX() const { return cells_x_ + 1; }
  int verticesY() const { return cells_y_ + 1; }

  double at(int i, int j) const { return heights_[index(i, j)]; }
  double& at(int i, int j) { return heights_[index(i, j)]; }
  const std::vector<double>& heights() const { return heights_; }

  // (dh/dx, dh/dy) of the bilinear cell (i, j) at (x, y) in [0, 1]^2 within it, in world units.
  Point2 gradient(int i, int j, double x, double y) const;
  // The average slope of the bilinear cell (i, j), Eq. (4.9) divided by the cell size:
  // ((h11 + h10 - h01 - h00) / 2, (h11 + h01 - h10 - h00) / 2) / cell_size, the gradient at its centre.
  Point2 cellSlope(int i, int j) const { return gradient(i, j, 0.5, 0.5); }
  // Eq. (4.1) with a box kernel: the mean micro-slope (dh/dx, dh/dy) over the count x count cells
  // whose first cell is (i0, j0) (the mean of their cells' slopes, the cells being equal in area).
  Point2 averageSlope(int i0, int j0, int count) const;
  // The mean height of the bilinear surface (each cell's mean is that of its four corners).
  double meanHeight() const;

 private:
  int index(int i, int j) const { return j * (cells_x_ + 1) + i; }

  int cells_x_ = 0, cells_y_ = 0;
  double cell_size_ = 1;
  std::vector<double> heights_;
};

// Throws MediumError naming `source` and the vertex (i, j) when a height is NaN or infinite.
void validateHeights(const HeightField& field, const std::string& source);

// Throws MediumError naming `source` and the vertex when the map does not tile seamlessly: a vertex
// on one edge and its twin on the opposite edge differ by more than `tolerance` times the map's
// relief (its highest height less its lowest).
void validateSeamless(const HeightField& field, const std::string& source, double tolerance = 1e-3);

}  // namespace vdbappear
