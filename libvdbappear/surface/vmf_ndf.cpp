#include "libvdbappear/surface/vmf_ndf.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/frame.h"
#include "libvdbappear/math/kmeans.h"
#include "libvdbappear/math/random_stream.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

namespace {

// vmf() = vmfNormalization(kappa) * vmfShape(w, kappa, mu), split so that a fit evaluating one lobe
// at many directions computes the normalisation once.
double vmfNormalization(double kappa) { return kappa < 1e-8 ? 1 / (4 * kPi) : kappa / (2 * kPi * -std::expm1(-2 * kappa)); }
double vmfShape(const Vec3& w, double kappa, const Vec3& mu) {
  return kappa < 1e-8 ? 1.0 : std::exp(kappa * (w.dot(mu) - 1));
}

}  // namespace

double vmf(const Vec3& w, double kappa, const Vec3& mu) { return vmfNormalization(kappa) * vmfShape(w, kappa, mu); }

Vec3 sampleVmf(double kappa, const Vec3& mu, const Point2& u) {
  const double w = kappa < 1e-8 ? 1 - 2 * u.x()
                                : 1 + std::log(u.x() + (1 - u.x()) * std::exp(-2 * kappa)) / kappa;
  const double r = std::sqrt(std::max(0.0, 1 - w * w)), phi = 2 * kPi * u.y();
  return Frame::fromNormal(mu).toWorld(Vec3(r * std::cos(phi), r * std::sin(phi), std::clamp(w, -1.0, 1.0)));
}

double VmfMixture::operator()(const Vec3& w) const {
  double sum = 0;
  for (const VmfLobe& lobe : lobes) sum += lobe.amplitude * vmf(w, lobe.kappa, lobe.mu);
  return sum;
}

namespace {

// Banerjee et al. 2005's approximation of kappa from the mean resultant length R, in 3-D.
double kappaOf(double R, double max_kappa) {
  if (R >= 1 - 1e-12) return max_kappa;
  return std::min(max_kappa, R * (3 - R * R) / (1 - R * R));
}

// One M-step from responsibilities: amplitudes, directions and bandwidths. A lobe that lost all its
// weight is dropped.
std::vector<VmfLobe> maximise(const std::vector<Vec3>& d, const std::vector<double>& w,
                              const std::vector<std::vector<double>>& responsibility, double total, double max_kappa) {
  std::vector<VmfLobe> lobes;
  for (const std::vector<double>& r : responsibility) {
    double mass = 0;
    Vec3 sum = Vec3::Zero();
    for (std::size_t n = 0; n < d.size(); ++n) {
      mass += w[n] * r[n];
      sum += w[n] * r[n] * d[n];
    }
    if (!(mass > 1e-12 * total)) continue;
    const double length = sum.norm();
    VmfLobe lobe;
    lobe.amplitude = mass / total;
    lobe.mu = length > 0 ? Vec3(sum / length) : Vec3(0, 0, 1);
    lobe.kappa = kappaOf(length / mass, max_kappa);
    lobes.push_back(lobe);
  }
  double amplitudes = 0;
  for (const VmfLobe& lobe : lobes) amplitudes += lobe.amplitude;
  for (VmfLobe& lobe : lobes) lobe.amplitude /= amplitudes;
  return lobes;
}

// E-step; returns the weighted log-likelihood.
double expect(const std::vector<Vec3>& d, const std::vector<double>& w, const std::vector<VmfLobe>& lobes,
              std::vector<std::vector<double>>* responsibility) {
  responsibility->assign(lobes.size(), std::vector<double>(d.size(), 0.0));
  std::vector<double> normalization(lobes.size());
  for (std::size_t k = 0; k < lobes.size(); ++k) normalization[k] = vmfNormalization(lobes[k].kappa);
  double log_likelihood = 0;
  for (std::size_t n = 0; n < d.size(); ++n) {
    double sum = 0;
    for (std::size_t k = 0; k < lobes.size(); ++k) {
      const double p = lobes[k].amplitude * (normalization[k] * vmfShape(d[n], lobes[k].kappa, lobes[k].mu));
      (*responsibility)[k][n] = p;
      sum += p;
    }
    if (!(sum > 0)) {  // beyond every lobe's reach in double precision: give it to the nearest
      std::size_t nearest = 0;
      for (std::size_t k = 1; k < lobes.size(); ++k)
        if (d[n].dot(lobes[k].mu) > d[n].dot(lobes[nearest].mu)) nearest = k;
      (*responsibility)[nearest][n] = 1;
      log_likelihood += w[n] * -700;
      continue;
    }
    for (std::size_t k = 0; k < lobes.size(); ++k) (*responsibility)[k][n] /= sum;
    log_likelihood += w[n] * std::log(sum);
  }
  return log_likelihood;
}

}  // namespace

VmfMixture fitVmfMixture(const std::vector<Vec3>& directions, const std::vector<double>& weights,
                         const VmfFitSettings& settings) {
  if (directions.empty() || directions.size() != weights.size() || settings.lobes < 1)
    throw std::invalid_argument("fitVmfMixture: no directions, a weight missing, or no lobe asked for");
  double total = 0;
  for (double w : weights) {
    if (!(w > 0) || !std::isfinite(w)) throw std::invalid_argument("fitVmfMixture: weights must be positive");
    total += w;
  }
  // k-means on the unit vectors seeds one responsibility-one lobe per cluster.
  RandomStream rng(settings.seed, {0x766d66});
  const KMeansResult<Vec3> clusters = kMeans(directions, weights, settings.lobes, rng);
  std::vector<std::vector<double>> responsibility(clusters.centres.size(), std::vector<double>(directions.size(), 0.0));
  for (std::size_t n = 0; n < directions.size(); ++n) responsibility[std::size_t(clusters.cluster[n])][n] = 1;
  std::vector<VmfLobe> lobes = maximise(directions, weights, responsibility, total, settings.max_kappa);
  double previous = -1e300;
  for (int iteration = 0; iteration < settings.max_iterations; ++iteration) {
    const double log_likelihood = expect(directions, weights, lobes, &responsibility);
    lobes = maximise(directions, weights, responsibility, total, settings.max_kappa);
    if (std::abs(log_likelihood - previous) <= 1e-9 * std::abs(log_likelihood) + 1e-12 * total) break;
    previous = log_likelihood;
  }
  return {lobes};
}

}  // namespace vdbappear
