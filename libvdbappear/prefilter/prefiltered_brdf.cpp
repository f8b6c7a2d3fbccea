#include "libvdbappear/prefilter/prefiltered_brdf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

PrefilteredBrdf::PrefilteredBrdf(const PrefilteredSurface& surface, const MicrofacetBrdf& base, Base shape)
    : cells_x_(surface.height.cellsX()), cells_y_(surface.height.cellsY()), shape_(shape), scaling_(surface.scaling) {
  if (surface.ndfs.size() != std::size_t(cells_x_) * std::size_t(cells_y_))
    throw std::invalid_argument("PrefilteredBrdf: one NDF per coarse cell");
  cells_.reserve(surface.ndfs.size());
  for (const VmfMixture& ndf : surface.ndfs) cells_.emplace_back(ndf, base);
}

const MultiLobeBrdf& PrefilteredBrdf::cellAt(const Point2& x) const {
  const int u = std::clamp(int(x.x() * cells_x_), 0, cells_x_ - 1), v = std::clamp(int(x.y() * cells_y_), 0, cells_y_ - 1);
  return cells_[std::size_t(u) + std::size_t(cells_x_) * v];
}

Rgb PrefilteredBrdf::eval(const Point2& x, const Vec3& wi, const Vec3& wo, const TileStretch& stretch,
                          const Vec3& coarse_normal) const {
  const MultiLobeBrdf& f = cellAt(x);
  if (!stretch.isIdentity()) {
    const Vec3 vi = stretch.toMap(wi), vo = stretch.toMap(wo);
    if (shape_ == Base::kPlane && (vi.z() <= 0 || vo.z() <= 0)) return Rgb::Zero();
    const Rgb projected = f.projected(wi, wo, stretch);
    if ((projected == 0).all()) return projected;
    // 1 / cos theta(vi) = |A^-1 wi| / cos theta_i: limited where the surface's own wi grazes, not
    // where the mapped vi does (toward a sphere's poles most vi graze).
    const double mapped_length = std::abs(wi.z()) / std::max(std::abs(vi.z()), 1e-300);
    const double coarse_weight = stretch.facetWeightOnSurface(coarse_normal.normalized());
    return scaling_(x, vi, vo) * (projected * (mapped_length / (MultiLobeBrdf::limitedCosine(wi.z()) * coarse_weight)));
  }
  if (shape_ == Base::kPlane) {
    const Rgb f_low = f.eval(wi, wo);
    return (f_low == 0).all() ? f_low : Rgb(scaling_(x, wi, wo) * f_low);
  }
  const Rgb projected = f.projected(wi, wo);
  if ((projected == 0).all()) return projected;
  return scaling_(x, wi, wo) * (projected / MultiLobeBrdf::limitedCosine(wi.z()));
}

// Above the horizon the lobes' own draws; below it, with probability kBelowHorizonShare, those
// draws mirrored in the base plane. f'_low's lobes reach below the horizon only as far as their
// facets tilt (a height field's micro-normals, so every mu_k, face up), and wherever a lobe's
// <mu_k, wi> > 0 below the horizon it is also > 0 at wi's mirror image, which the mirrored draws
// cover. Draws of a lobe that land below the horizon are not kept: pdf() leaves them out.
BrdfSample PrefilteredBrdf::sample(const Point2& x, const Vec3& wo, double u_lobe, const Point2& u,
                                    const TileStretch& stretch, const Vec3& coarse_normal) const {
  if (shape_ == Base::kPlane) {
    BrdfSample s = cellAt(x).sample(wo, u_lobe, u);
    if (s.pdf > 0)
      s.weight = stretch.isIdentity() ? Rgb(s.weight * scaling_(x, s.wi, wo))
                                      : Rgb(eval(x, s.wi, wo, stretch, coarse_normal) * (s.wi.z() / s.pdf));
    return s;
  }
  const bool below = u_lobe < kBelowHorizonShare;
  u_lobe = below ? u_lobe / kBelowHorizonShare : (u_lobe - kBelowHorizonShare) / (1 - kBelowHorizonShare);
  BrdfSample s = cellAt(x).sampleLobes(wo, std::min(u_lobe, 1 - 1e-16), u);
  if (!(s.pdf > 0) || !(s.wi.z() > 0)) return {};
  if (below) s.wi.z() = -s.wi.z();
  s.pdf *= below ? kBelowHorizonShare : 1 - kBelowHorizonShare;  // pdf(x, wo, s.wi): the mirror is exact
  s.weight = eval(x, s.wi, wo, stretch, coarse_normal) * (std::abs(s.wi.z()) / s.pdf);
  return s;
}

double PrefilteredBrdf::pdf(const Point2& x, const Vec3& wo, const Vec3& wi) const {
  const MultiLobeBrdf& f = cellAt(x);
  if (shape_ == Base::kPlane) return f.pdf(wo, wi);
  if (wi.z() < 0) return kBelowHorizonShare * f.lobePdf(wo, Vec3(wi.x(), wi.y(), -wi.z()));
  return wi.z() > 0 ? (1 - kBelowHorizonShare) * f.lobePdf(wo, wi) : 0.0;
}

}  // namespace vdbappear
