#pragma once
// How far each cell of a height field stands above the cells about it: the spatial covariate of
// the scaling function's relief term (docs/displacement.md §6, "The relief term"). At grazing views
// R of Eq. (4.12) depends on it, which the rank-one T(x) S(wi, wo) of Eq. (4.21) cannot hold: past a
// curved base's silhouette only the bumps' upper parts are seen, and over the ball's curvature at a
// view 87 degrees from the normal the upper half of h_low's cells has R 1.055 and the lower 0.896,
// against T S = 1.002 (bench/rim_masking_study.cpp). Defined on h_low, so the renderer has it too:
//   z(u, v) = [m(u, v) - mean of m over the (2r + 1)^2 cells about (u, v)] / rms,
// m the cell's mean height (that of its four corners), the neighbours wrapping about the map as its
// tiles repeat, and rms that of the numerator over the map (z = 0 everywhere where rms is below a
// millionth of the heights' range: a flat map, or one whose cells all hold the same).

#include "libvdbappear/math/vector.h"

#include <algorithm>
#include <vector>

namespace vdbappear {

class HeightField;

struct CellRelief {
  int radius = 0;            // r; 0 with no cells: none
  int cells_x = 0, cells_y = 0;
  std::vector<double> values;  // cell (u, v) at u + cells_x v
  bool empty() const { return values.empty(); }
  double at(int u, int v) const { return values[std::size_t(u) + std::size_t(cells_x) * std::size_t(v)]; }
  // z of the cell under base position x in [0,1]^2 (clamped); 0 when empty.
  double operator()(const Point2& x) const;
};

// The widest radius whose (2r + 1)^2 cells fit in a map of cells_x x cells_y cells (each cell's
// neighbourhood holds no cell twice).
inline int widestReliefRadius(int cells_x, int cells_y) { return (std::min(cells_x, cells_y) - 1) / 2; }

// Throws std::invalid_argument for a radius below 1 or above widestReliefRadius() of the field.
CellRelief cellRelief(const HeightField& field, int radius);

}  // namespace vdbappear
