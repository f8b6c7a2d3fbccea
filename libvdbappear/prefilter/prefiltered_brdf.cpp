#include "libvdbappear/prefilter/prefiltered_brdf.h"

#include <algorithm>
#include <stdexcept>

namespace vdbappear {

PrefilteredBrdf::PrefilteredBrdf(const PrefilteredSurface& surface, const MicrofacetBrdf& base)
    : cells_x_(surface.height.cellsX()), cells_y_(surface.height.cellsY()), scaling_(surface.scaling) {
  if (surface.ndfs.size() != std::size_t(cells_x_) * std::size_t(cells_y_))
    throw std::invalid_argument("PrefilteredBrdf: one NDF per coarse cell");
  cells_.reserve(surface.ndfs.size());
  for (const VmfMixture& ndf : surface.ndfs) cells_.emplace_back(ndf, base);
}

const MultiLobeBrdf& PrefilteredBrdf::cellAt(const Point2& x) const {
  const int u = std::clamp(int(x.x() * cells_x_), 0, cells_x_ - 1), v = std::clamp(int(x.y() * cells_y_), 0, cells_y_ - 1);
  return cells_[std::size_t(u) + std::size_t(cells_x_) * v];
}

Rgb PrefilteredBrdf::eval(const Point2& x, const Vec3& wi, const Vec3& wo) const {
  const Rgb f = cellAt(x).eval(wi, wo);
  return (f == 0).all() ? f : Rgb(scaling_(x, wi, wo) * f);
}

BrdfSample PrefilteredBrdf::sample(const Point2& x, const Vec3& wo, double u_lobe, const Point2& u) const {
  BrdfSample s = cellAt(x).sample(wo, u_lobe, u);
  if (s.pdf > 0) s.weight *= scaling_(x, s.wi, wo);
  return s;
}

double PrefilteredBrdf::pdf(const Point2& x, const Vec3& wo, const Vec3& wi) const { return cellAt(x).pdf(wo, wi); }

}  // namespace vdbappear
