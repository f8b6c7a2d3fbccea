#include "libvdbappear/lightgrid/sh_light_grid.h"

#include "libvdbappear/lightgrid/zonal_factorisation.h"
#include "libvdbappear/math/spherical_harmonics.h"
#include "libvdbappear/util/progress.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

ShGridLayout ShGridLayout::covering(const Vec3& lo, const Vec3& hi, int resolution) {
  if (resolution < 2) throw std::invalid_argument("SH light grid: the resolution must be at least 2 nodes");
  const double extent = (hi - lo).maxCoeff();
  if (!(extent > 0)) throw std::invalid_argument("SH light grid: the bounding box is empty");
  return withSpacing(lo, hi, extent / (resolution - 1));
}

ShGridLayout ShGridLayout::withSpacing(const Vec3& lo, const Vec3& hi, double spacing) {
  if (!(spacing > 0)) throw std::invalid_argument("SH light grid: the voxel size must be > 0");
  if (!((hi - lo).array() >= 0).all()) throw std::invalid_argument("SH light grid: the bounding box is empty");
  if (!lo.allFinite() || !hi.allFinite() || !std::isfinite(spacing))
    throw std::invalid_argument("SH light grid: the bounding box and the voxel size must be finite");
  ShGridLayout layout;
  layout.origin = lo;
  layout.spacing = spacing;
  double count = 1;
  Vec3 nodes;
  for (int axis = 0; axis < 3; ++axis) {
    nodes[axis] = std::max(2.0, std::ceil((hi[axis] - lo[axis]) / spacing - 1e-9) + 1);
    count *= nodes[axis];
  }
  if (count > 1e8) throw std::invalid_argument("SH light grid: more than 1e8 nodes; use a coarser resolution");
  layout.nodes = nodes.cast<int>();
  return layout;
}

ShLightGrid::ShLightGrid(int lmax, const ShGridLayout& layout)
    : lmax_(lmax), layout_(layout), nodes_(layout.count(), ShLighting(shCount(lmax))) {}

ShLightGrid ShLightGrid::evaluate(const std::vector<PolygonLight>& lights, int lmax, const ShGridLayout& layout,
                                  ProgressBar* progress) {
  return evaluate(lights, ZonalFactorisation(lmax), layout, progress);
}

ShLightGrid ShLightGrid::evaluate(const std::vector<PolygonLight>& lights, const ZonalFactorisation& zh,
                                  const ShGridLayout& layout, ProgressBar* progress) {
  ShLightGrid grid(zh.lmax(), layout);
  if (progress) progress->setTotal(layout.count());
  const Eigen::Vector3i n = layout.nodes;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, layout.count()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t node = r.begin(); node != r.end(); ++node) {
      const int i = int(node % n.x()), j = int(node / n.x() % n.y()), k = int(node / (std::size_t(n.x()) * n.y()));
      grid.nodes_[node] = shLighting(lights, layout.position(i, j, k), zh);
    }
    if (progress) progress->advance(r.size());
  });
  return grid;
}

void ShLightGrid::interpolate(const Vec3& x, CellInterpolation method, std::vector<Vec3>& out) const {
  if (!x.allFinite()) {
    out.assign(shCount(lmax_), Vec3::Zero());
    return;
  }
  // The cell holding x, and x relative to its corner 0.
  const Vec3 local = (x - layout_.origin) / layout_.spacing;
  Eigen::Vector3i cell;
  Vec3 p;
  for (int axis = 0; axis < 3; ++axis) {
    const double t = std::clamp(local[axis], 0.0, double(layout_.nodes[axis] - 1));
    cell[axis] = std::min(int(t), layout_.nodes[axis] - 2);
    p[axis] = (t - cell[axis]) * layout_.spacing;
  }
  const CellWeights w = cellWeights(method, p, Vec3::Constant(layout_.spacing));
  const ShLighting* corner[8];
  for (int c = 0; c < 8; ++c) corner[c] = &node(cell.x() + (c & 1), cell.y() + (c >> 1 & 1), cell.z() + (c >> 2 & 1));
  out.assign(shCount(lmax_), Vec3::Zero());
  const bool gradients = method != CellInterpolation::kTrilinear;
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int c = 0; c < 8; ++c) {
      out[i] += w.value[c] * corner[c]->coeffs[i];
      if (gradients) out[i] += corner[c]->gradients[i] * w.gradient[c];
    }
}

void ShLightGrid::forEachNode(const std::function<void(const LatticeIndex&, const ShLighting&)>& visit) const {
  for (int k = 0; k < layout_.nodes.z(); ++k)
    for (int j = 0; j < layout_.nodes.y(); ++j)
      for (int i = 0; i < layout_.nodes.x(); ++i) visit({i, j, k}, node(i, j, k));
}

}  // namespace vdbappear
