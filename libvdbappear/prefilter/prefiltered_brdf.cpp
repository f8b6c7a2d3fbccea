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

// The density of f'_low's lobe draws folded onto the upper hemisphere (PrefilteredBrdf::sample on a
// plane): a draw below the base horizon, where Eq. (4.5) is zero, is mirrored to wi above it, so wi
// is reached by its own draw and by its mirror image's.
double foldedPdf(const MultiLobeBrdf& cell, const Vec3& wo, const Vec3& wi) {
  if (!(wo.z() > 0) || !(wi.z() > 0)) return 0;
  return cell.lobePdf(wo, wi) + cell.lobePdf(wo, Vec3(wi.x(), wi.y(), -wi.z()));
}

// d_k of scalingOnTile(): how far the residual stretch R is from none, either way.
double residualDistance(const TileStretch& residual) {
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  return (residual.matrix() - I).norm() + (residual.inverse() - I).norm();
}

// A viewer below a curved base's horizon (a sphere's rim) sees h_low's facets that face it and, of
// each coarse cell's lobes, those that face it, each by the area it shows: the lobes' visible mean
// V (MultiLobeBrdf::visibleMean). Eq. (4.5)'s sum F (MultiLobeBrdf::projected) weighs them by area
// alone and so fades as fewer of them face wo, while S, read there at the horizon node, holds the
// ratio of the original to F at the horizon. So below it f_low is taken times
//   c = [V(wo) / F(wo)] / [V(h) / F(h)],   h = wo's direction on the horizon (the same azimuth),
// 1 at the horizon, where f_low stays continuous, and beyond it the visible lobes' mean scaled as S
// scales it at the horizon. Per channel; 1 where a ratio has no value (no light on the lobes).
Rgb viewBelowHorizonFactor(const MultiLobeBrdf& f, const Vec3& wi, const Vec3& wo, const TileStretch& stretch) {
  const Vec3 h = Vec3(wo.x(), wo.y(), 0).normalized();
  const Rgb below = f.visibleMean(wi, wo, stretch) * f.projected(wi, h, stretch);
  const Rgb at_horizon = f.visibleMean(wi, h, stretch) * f.projected(wi, wo, stretch);
  return (below > 0 && at_horizon > 0).select(below / at_horizon, Rgb::Ones());
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
  if (shape_ == Base::kPlane && (wi.z() <= 0 || wo.z() <= 0)) return Rgb::Zero();  // the sign of vi.z, vo.z
  Rgb f_low;
  if (!stretch.isIdentity()) {
    const Rgb lobes = f.onStretchedTile(wi, wo, stretch, coarse_normal);
    if ((lobes == 0).all()) return lobes;
    f_low = scalingOnTile(x, wi, wo, stretch) * lobes;
  } else if (shape_ == Base::kPlane) {
    const Rgb lobes = f.eval(wi, wo);
    if ((lobes == 0).all()) return lobes;
    f_low = square(x, wi, wo) * lobes;
  } else {
    const Rgb projected = f.projected(wi, wo);
    if ((projected == 0).all()) return projected;
    f_low = square(x, wi, wo) * (projected / MultiLobeBrdf::limitedCosine(wi.z()));
  }
  if (shape_ == Base::kCurved && wo.z() < 0) f_low *= viewBelowHorizonFactor(f, wi, wo, stretch);
  return f_low;
}

// On a plane, the lobes' draws folded above the horizon (foldedPdf): Eq. (4.5) is zero below it.
// On a curved base, above the horizon the lobes' own draws; below it, with probability
// kBelowHorizonShare, those draws mirrored in the base plane. f'_low's lobes reach below the horizon
// only as far as their facets tilt (a height field's micro-normals, so every mu_k, face up), and
// wherever a lobe's <mu_k, wi> > 0 below the horizon it is also > 0 at wi's mirror image, which the
// mirrored draws cover. There, draws of a lobe that land below the horizon are not kept: pdf()
// leaves them out.
BrdfSample PrefilteredBrdf::sample(const Point2& x, const Vec3& wo, double u_lobe, const Point2& u,
                                    const TileStretch& stretch, const Vec3& coarse_normal) const {
  if (shape_ == Base::kPlane) {
    const MultiLobeBrdf& cell = cellAt(x);
    if (!(wo.z() > 0)) return {};
    BrdfSample s = cell.sampleLobes(wo, u_lobe, u);
    if (!(s.pdf > 0)) return {};
    s.pdf += cell.lobePdf(wo, Vec3(s.wi.x(), s.wi.y(), -s.wi.z()));  // foldedPdf at the folded wi
    s.wi.z() = std::abs(s.wi.z());
    if (!(s.wi.z() > 0)) return {};
    s.weight = (stretch.isIdentity() ? Rgb(cell.eval(s.wi, wo) * square(x, s.wi, wo))
                                     : eval(x, s.wi, wo, stretch, coarse_normal)) * (s.wi.z() / s.pdf);
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
  if (shape_ == Base::kPlane) return foldedPdf(f, wo, wi);
  if (wi.z() < 0) return kBelowHorizonShare * f.lobePdf(wo, Vec3(wi.x(), wi.y(), -wi.z()));
  return wi.z() > 0 ? (1 - kBelowHorizonShare) * f.lobePdf(wo, wi) : 0.0;
}

}  // namespace vdbappear
