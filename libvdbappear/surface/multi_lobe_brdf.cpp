#include "libvdbappear/surface/multi_lobe_brdf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

namespace {
constexpr int kMaxLobes = 16;
// Eq. (4.5)'s 1 / cos theta_i, limited at 84 degrees: the prefiltered model is shaded with the
// coarse surface's cosine, which does not vanish where the base's does, and unlimited the ratio
// lit pixels a thousand times their mean under a sky.
constexpr double kMinCosTheta = 0.1;
}

double MultiLobeBrdf::widenedRoughness(double alpha, double kappa) {
  return std::min(1.0, std::sqrt(alpha * alpha + (kappa > 0 ? 2 / kappa : 1e30)));
}

MultiLobeBrdf::MultiLobeBrdf(const VmfMixture& ndf, const MicrofacetBrdf& base) {
  if (ndf.lobes.size() > std::size_t(kMaxLobes)) throw std::invalid_argument("MultiLobeBrdf: at most 16 lobes");
  const MicrofacetDistribution& d = base.distribution();
  for (const VmfLobe& lobe : ndf.lobes) {
    if (!(lobe.amplitude > 0)) continue;
    const MicrofacetDistribution widened(d.kind(), widenedRoughness(d.alpha(), lobe.kappa));
    lobes_.push_back({Frame::fromNormal(lobe.mu.normalized()), lobe.amplitude,
                      MicrofacetBrdf(widened, base.specular(), base.diffuse())});
  }
}

double MultiLobeBrdf::limitedCosine(double cos_theta_i) { return std::max(cos_theta_i, kMinCosTheta); }

// The square tile's sum, which every shading point of a planar model evaluates: a lobe facing away
// from wi is left before its terms are formed, and each lobe's own frame serves (onSurface() would
// copy it). The same arithmetic as projected(wi, wo, TileStretch()), bit for bit.
Rgb MultiLobeBrdf::projected(const Vec3& wi, const Vec3& wo) const {
  Rgb sum = Rgb::Zero();
  for (const Lobe& l : lobes_) {
    const double cos_i = l.frame.n.dot(wi);  // <mu_k, wi>
    if (cos_i <= 0) continue;
    sum += l.brdf.eval(l.frame.toLocal(wo), l.frame.toLocal(wi)) * (l.amplitude * cos_i);
  }
  return sum;
}

MultiLobeBrdf::OnSurface MultiLobeBrdf::onSurface(const Lobe& l, const Vec3& vi, const TileStretch& stretch) {
  const double cos_i = l.frame.n.dot(vi);  // <mu_k, vi>, of the sign of <A^-T mu_k, wi>
  if (stretch.isIdentity()) return {l.frame, 1.0, cos_i};
  const Vec3 axis = stretch.normalOnSurfaceUnnormalised(l.frame.n);  // |A^-T mu_k| = 1 / its weight
  const double length = axis.norm();
  return {Frame::fromNormal(axis / length), length, cos_i};
}

Rgb MultiLobeBrdf::projected(const Vec3& wi, const Vec3& wo, const TileStretch& stretch) const {
  if (stretch.isIdentity()) return projected(wi, wo);
  const Vec3 vi = stretch.toMap(wi);
  Rgb sum = Rgb::Zero();
  for (const Lobe& l : lobes_) {
    if (l.frame.n.dot(vi) <= 0) continue;  // onSurface()'s cos_i, before its frame is built
    const OnSurface s = onSurface(l, vi, stretch);
    sum += l.brdf.eval(s.frame.toLocal(wo), s.frame.toLocal(wi)) * (l.amplitude * s.cos_i / s.length);
  }
  return sum;
}

Rgb MultiLobeBrdf::visibleMean(const Vec3& wi, const Vec3& wo, const TileStretch& stretch) const {
  const Vec3 vi = stretch.isIdentity() ? wi : stretch.toMap(wi);
  Rgb seen = Rgb::Zero();
  double seen_area = 0;
  for (const Lobe& l : lobes_) {
    const OnSurface s = onSurface(l, vi, stretch);
    const double shown = l.amplitude / s.length * std::max(0.0, s.frame.n.dot(wo));  // alpha_k' <a_k, wo>+
    if (shown <= 0) continue;
    seen_area += shown;
    if (s.cos_i > 0) seen += l.brdf.eval(s.frame.toLocal(wo), s.frame.toLocal(wi)) * (shown * s.cos_i);
  }
  return seen_area > 0 ? Rgb(seen / seen_area) : Rgb(Rgb::Zero());
}

Rgb MultiLobeBrdf::onStretchedTile(const Vec3& wi, const Vec3& wo, const TileStretch& stretch,
                                   const Vec3& coarse_normal) const {
  const Rgb sum = projected(wi, wo, stretch);
  if ((sum == 0).all()) return sum;
  // |A^-1 wi| / cos theta_i = 1 / cos theta(vi), limited where the surface's own wi grazes, not
  // where the mapped vi does (toward a sphere's poles most vi graze).
  const Vec3 vi = stretch.toMap(wi);
  const double mapped_length = std::abs(wi.z()) / std::max(std::abs(vi.z()), 1e-300);
  const double coarse_weight = stretch.facetWeightOnSurface(coarse_normal.normalized());
  return sum * (mapped_length / (limitedCosine(wi.z()) * coarse_weight));
}

Rgb MultiLobeBrdf::eval(const Vec3& wi, const Vec3& wo) const {
  if (wi.z() <= 0 || wo.z() <= 0) return Rgb::Zero();
  return projected(wi, wo) / limitedCosine(wi.z());
}

bool MultiLobeBrdf::lobeProbabilities(const Vec3& wo, double* probability) const {
  double total = 0;
  for (std::size_t k = 0; k < lobes_.size(); ++k) {
    // alpha_k alone: lobe k's term of Eq. (4.5) carries alpha_k and <mu_k, wi>, which its own
    // sampling draws, but no <mu_k, wo>; weighing the lobes by <mu_k, wo> besides left their
    // sampling weights unequal (the woven map's 32x model under a glossy base: 37% more variance).
    probability[k] = lobes_[k].frame.n.dot(wo) > 0 ? lobes_[k].amplitude : 0.0;
    total += probability[k];
  }
  if (!(total > 0)) return false;
  for (std::size_t k = 0; k < lobes_.size(); ++k) probability[k] /= total;
  return true;
}

double MultiLobeBrdf::lobePdf(const Vec3& wo, const Vec3& wi) const {
  double probability[kMaxLobes];
  if (!lobeProbabilities(wo, probability)) return 0;
  double density = 0;
  for (std::size_t k = 0; k < lobes_.size(); ++k)
    if (probability[k] > 0) density += probability[k] * lobes_[k].brdf.pdf(lobes_[k].frame.toLocal(wo), lobes_[k].frame.toLocal(wi));
  return density;
}

double MultiLobeBrdf::pdf(const Vec3& wo, const Vec3& wi) const {
  return wo.z() <= 0 || wi.z() <= 0 ? 0 : lobePdf(wo, wi);
}

BrdfSample MultiLobeBrdf::sampleLobes(const Vec3& wo, double u_lobe, const Point2& u) const {
  double probability[kMaxLobes];
  if (!lobeProbabilities(wo, probability)) return {};
  std::size_t k = 0;
  while (k + 1 < lobes_.size() && u_lobe >= probability[k]) u_lobe -= probability[k++];
  u_lobe = std::min(u_lobe / probability[k], 1 - 1e-16);  // reused for the base BRDF's lobe choice
  const Lobe& l = lobes_[k];
  const Vec3 wo_local = l.frame.toLocal(wo);
  BrdfSample s;
  // lobeProbabilities() gives no weight to a lobe whose axis wo does not face; toLocal() may round.
  if (!(wo_local.z() > 0)) return s;
  // The lobe's direction alone: its own pdf and weight are not the mixture's, which follow.
  const Vec3 wi_local = l.brdf.sampleDirection(wo_local, u_lobe, u);
  if (!(wi_local.z() > 0)) return s;
  s.wi = l.frame.toWorld(wi_local);
  s.pdf = lobePdf(wo, s.wi);
  return s;
}

BrdfSample MultiLobeBrdf::sample(const Vec3& wo, double u_lobe, const Point2& u) const {
  if (wo.z() <= 0) return {};
  BrdfSample s = sampleLobes(wo, u_lobe, u);
  if (!(s.pdf > 0) || s.wi.z() <= 0) return {};  // below the macro-surface: absorbed
  s.weight = eval(s.wi, wo) * (s.wi.z() / s.pdf);
  return s;
}

}  // namespace vdbappear
