#include "libvdbappear/medium/scattering_function.h"

#include "libvdbappear/math/henyey_greenstein.h"
#include "libvdbappear/math/sampling.h"

#include <cmath>
#include <stdexcept>

namespace vdbappear {

double PhaseLobe::eval(const Vec3& wi, const Vec3& wo) const {
  switch (kind) {
    case PhaseKind::kIsotropic: return uniformSpherePdf();
    case PhaseKind::kHenyeyGreenstein: return henyeyGreensteinPhase(wi, wo, g);
    case PhaseKind::kSggx: return sggx.phase(wi, wo);
    case PhaseKind::kTabulated: return table->phase(wi, wo);
  }
  return 0;
}

PhaseSample PhaseLobe::sample(const Vec3& wi, const Point2& u) const {
  switch (kind) {
    case PhaseKind::kIsotropic: return {sampleUniformSphere(u), uniformSpherePdf(), 1.0};
    case PhaseKind::kHenyeyGreenstein: return sampleHenyeyGreenstein(wi, g, u);
    case PhaseKind::kSggx: return sggx.samplePhase(wi, u);
    case PhaseKind::kTabulated: return table->sample(wi, u);
  }
  return {};
}

double PhaseLobe::legendreMoment(int l) const {
  if (kind == PhaseKind::kIsotropic) return l == 0 ? 1.0 : 0.0;
  if (kind == PhaseKind::kHenyeyGreenstein) return std::pow(g, l);
  throw std::logic_error("PhaseLobe::legendreMoment: no closed form for SGGX lobes and tables");
}

void ScatteringFunction::addLobe(const PhaseLobe& lobe, const Rgb& weight, int slot) {
  appendLobe(weight, slot) = lobe;
}

PhaseLobe& ScatteringFunction::appendLobe(const Rgb& weight, int slot) {
  if (lobe_count_ == kMaxLobes) throw std::length_error("ScatteringFunction: too many lobes");
  weights_[lobe_count_] = weight;
  slots_[lobe_count_] = slot;
  PhaseLobe& lobe = lobes_[lobe_count_++];
  lobe.kind = PhaseKind::kIsotropic;
  lobe.g = 0;
  lobe.table = nullptr;
  return lobe;
}

void ScatteringFunction::scaleWeight(int j, const Rgb& factor) { weights_[j] *= factor; }

// P(j), proportional to the mean of W_j (uniform when every weight is 0).
std::array<double, ScatteringFunction::kMaxLobes> ScatteringFunction::pickProbabilities() const {
  std::array<double, kMaxLobes> p;
  double total = 0;
  for (int j = 0; j < lobe_count_; ++j) total += average(weights_[j]);
  for (int j = 0; j < lobe_count_; ++j) p[j] = total > 0 ? average(weights_[j]) / total : 1.0 / lobe_count_;
  return p;
}

Rgb ScatteringFunction::albedo() const {
  Rgb sum = Rgb::Zero();
  for (int j = 0; j < lobe_count_; ++j) sum += weights_[j];
  return sum;
}

Rgb ScatteringFunction::eval(const Vec3& wi, const Vec3& wo) const {
  Rgb f = Rgb::Zero();
  for (int j = 0; j < lobe_count_; ++j)
    if ((weights_[j] > 0).any()) f += weights_[j] * lobes_[j].eval(wi, wo);
  return f;
}

Rgb ScatteringFunction::evalLobes(const Vec3& wi, const Vec3& wo, Rgb* per_lobe) const {
  Rgb f = Rgb::Zero();
  for (int j = 0; j < lobe_count_; ++j) {
    per_lobe[j] = (weights_[j] > 0).any() ? Rgb(weights_[j] * lobes_[j].eval(wi, wo)) : Rgb(Rgb::Zero());
    f += per_lobe[j];
  }
  return f;
}

double ScatteringFunction::pdf(const Vec3& wi, const Vec3& wo) const {
  const std::array<double, kMaxLobes> pick = pickProbabilities();
  double p = 0;
  for (int j = 0; j < lobe_count_; ++j)
    if (pick[j] > 0) p += pick[j] * lobes_[j].pdf(wi, wo);
  return p;
}

ScatterSample ScatteringFunction::sample(const Vec3& wi, double u_lobe, const Point2& u, Rgb* per_lobe) const {
  if (lobe_count_ == 0) return {};
  if (lobe_count_ == 1) {
    const PhaseSample s = lobes_[0].sample(wi, u);
    if (per_lobe) evalLobes(wi, s.wo, per_lobe);
    return {s.wo, s.pdf, s.pdf > 0 ? Rgb(weights_[0] * s.weight) : Rgb(Rgb::Zero())};
  }
  const std::array<double, kMaxLobes> pick = pickProbabilities();
  int j = 0;
  for (double cdf = pick[0]; j + 1 < lobe_count_ && u_lobe >= cdf; cdf += pick[++j]) {
  }
  const PhaseSample s = lobes_[j].sample(wi, u);
  if (!(s.pdf > 0)) return {};
  // pdf and eval over all lobes from one evaluation of each lobe (the sums of pdf() and evalLobes());
  // the sampled lobe's comes with its sample: pdf s.pdf, phase value s.weight * s.pdf.
  double pdf_all = 0;
  Rgb f = Rgb::Zero();
  for (int k = 0; k < lobe_count_; ++k) {
    const bool weighted = (weights_[k] > 0).any();
    double phase = 0, pdf = 0;
    if (k == j) {
      phase = s.weight * s.pdf;
      pdf = s.pdf;
    } else if (weighted || pick[k] > 0) {
      phase = lobes_[k].eval(wi, s.wo);
      pdf = lobes_[k].samplesItsPhase() ? phase : lobes_[k].pdf(wi, s.wo);
    }
    if (pick[k] > 0) pdf_all += pick[k] * pdf;
    const Rgb term = weighted ? Rgb(weights_[k] * phase) : Rgb(Rgb::Zero());
    if (per_lobe) per_lobe[k] = term;
    f += term;
  }
  return {s.wo, pdf_all, pdf_all > 0 ? Rgb(f / pdf_all) : Rgb(Rgb::Zero())};
}

}  // namespace vdbappear
