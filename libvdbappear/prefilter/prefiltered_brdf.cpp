#include "libvdbappear/prefilter/prefiltered_brdf.h"

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <limits>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

PrefilteredBrdf::PrefilteredBrdf(const PrefilteredSurface& surface, const MicrofacetBrdf& base, Base shape)
    : cells_x_(surface.height.cellsX()), cells_y_(surface.height.cellsY()), shape_(shape) {
  if (surface.ndfs.size() != std::size_t(cells_x_) * std::size_t(cells_y_))
    throw std::invalid_argument("PrefilteredBrdf: one NDF per coarse cell");
  cells_.reserve(surface.ndfs.size());
  for (const VmfMixture& ndf : surface.ndfs) cells_.emplace_back(ndf, base);
  tables_.push_back({TileStretch(), surface.scaling});
  tables_.insert(tables_.end(), surface.stretched.begin(), surface.stretched.end());
}

namespace {

// d_k of scalingOnTile(): how far the residual stretch R is from none, either way.
double residualDistance(const TileStretch& residual) {
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  return (residual.matrix() - I).norm() + (residual.inverse() - I).norm();
}

}  // namespace

Rgb PrefilteredBrdf::scalingOnTile(const Point2& x, const Vec3& wi, const Vec3& wo, const TileStretch& stretch) const {
  const auto read = [&](const StretchedScaling& table, const TileStretch& residual) {
    return table.scaling(x, residual.toMap(wi), residual.toMap(wo));
  };
  if (tables_.size() == 1) return read(tables_.front(), stretch);
  // The three nearest tables, kept in order as the tables are read (no allocation: this runs at
  // every shading point).
  struct Candidate {
    double distance = std::numeric_limits<double>::infinity();
    std::size_t table = 0;
    TileStretch residual;
  };
  std::array<Candidate, 3> nearest;
  for (std::size_t k = 0; k < tables_.size(); ++k) {
    Candidate c{0, k, TileStretch(stretch.matrix() * tables_[k].stretch.inverse())};
    c.distance = residualDistance(c.residual);
    for (Candidate& slot : nearest)
      if (c.distance < slot.distance) std::swap(c, slot);
  }
  if (nearest[0].distance <= 1e-12) return read(tables_[nearest[0].table], nearest[0].residual);
  const double beyond = 1 / nearest[2].distance;  // 0 with two tables
  const double w0 = 1 / nearest[0].distance - beyond, w1 = std::max(1 / nearest[1].distance - beyond, 0.0);
  return (read(tables_[nearest[0].table], nearest[0].residual) * w0 +
          read(tables_[nearest[1].table], nearest[1].residual) * w1) / (w0 + w1);
}

const MultiLobeBrdf& PrefilteredBrdf::cellAt(const Point2& x) const {
  const int u = std::clamp(int(x.x() * cells_x_), 0, cells_x_ - 1), v = std::clamp(int(x.y() * cells_y_), 0, cells_y_ - 1);
  return cells_[std::size_t(u) + std::size_t(cells_x_) * v];
}

Rgb PrefilteredBrdf::eval(const Point2& x, const Vec3& wi, const Vec3& wo, const TileStretch& stretch,
                          const Vec3& coarse_normal) const {
  const MultiLobeBrdf& f = cellAt(x);
  if (!stretch.isIdentity()) {
    if (shape_ == Base::kPlane && (wi.z() <= 0 || wo.z() <= 0)) return Rgb::Zero();  // the sign of vi.z, vo.z
    const Rgb f_low = f.onStretchedTile(wi, wo, stretch, coarse_normal);
    return (f_low == 0).all() ? f_low : Rgb(scalingOnTile(x, wi, wo, stretch) * f_low);
  }
  if (shape_ == Base::kPlane) {
    const Rgb f_low = f.eval(wi, wo);
    return (f_low == 0).all() ? f_low : Rgb(square(x, wi, wo) * f_low);
  }
  const Rgb projected = f.projected(wi, wo);
  if ((projected == 0).all()) return projected;
  return square(x, wi, wo) * (projected / MultiLobeBrdf::limitedCosine(wi.z()));
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
      s.weight = stretch.isIdentity() ? Rgb(s.weight * square(x, s.wi, wo))
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
