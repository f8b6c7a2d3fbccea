#include "libvdbappear/surface/cell_relief.h"

#include "libvdbappear/surface/height_field.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

double CellRelief::operator()(const Point2& x) const {
  if (empty()) return 0;
  const int u = std::clamp(int(x.x() * cells_x), 0, cells_x - 1), v = std::clamp(int(x.y() * cells_y), 0, cells_y - 1);
  return at(u, v);
}

CellRelief cellRelief(const HeightField& field, int radius) {
  const int nx = field.cellsX(), ny = field.cellsY();
  if (radius < 1 || radius > widestReliefRadius(nx, ny))
    throw std::invalid_argument("cellRelief: the neighbourhood's radius must be at least 1 cell and its 2 r + 1 cells "
                                "fit in the map");
  std::vector<double> mean(std::size_t(nx) * ny);
  for (int v = 0; v < ny; ++v)
    for (int u = 0; u < nx; ++u)
      mean[std::size_t(u) + std::size_t(nx) * v] =
          (field.at(u, v) + field.at(u + 1, v) + field.at(u, v + 1) + field.at(u + 1, v + 1)) / 4;
  const auto wrapped = [](int k, int n) { return ((k % n) + n) % n; };
  CellRelief relief{radius, nx, ny, std::vector<double>(mean.size())};
  const double count = double(2 * radius + 1) * (2 * radius + 1);
  double square_sum = 0;
  for (int v = 0; v < ny; ++v)
    for (int u = 0; u < nx; ++u) {
      double about = 0;
      for (int dv = -radius; dv <= radius; ++dv)
        for (int du = -radius; du <= radius; ++du)
          about += mean[std::size_t(wrapped(u + du, nx)) + std::size_t(nx) * wrapped(v + dv, ny)];
      const double z = mean[std::size_t(u) + std::size_t(nx) * v] - about / count;
      relief.values[std::size_t(u) + std::size_t(nx) * v] = z;
      square_sum += z * z;
    }
  // Below a millionth of the heights' range, no relief: z = 0. What stands out less is the heights'
  // rounding (a flat map's sums; h_low read back from its 32-bit file, where a map of one bump per
  // coarse cell, every cell's mean the same, would otherwise give its rounding unit RMS).
  const auto [lowest, highest] = std::minmax_element(field.heights().begin(), field.heights().end());
  const double rms = std::sqrt(square_sum / double(mean.size()));
  const double range = *highest - *lowest;
  const bool flat = !(range > 0 && rms > 1e-6 * range);
  for (double& z : relief.values) z = flat ? 0.0 : z / rms;
  return relief;
}

}  // namespace vdbappear
