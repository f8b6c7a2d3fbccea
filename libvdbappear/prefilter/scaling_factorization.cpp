#include "libvdbappear/prefilter/scaling_factorization.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/math/sampling.h"
#include "libvdbappear/util/progress.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace vdbappear {
namespace {

// The coarse cell under base position x in [0,1]^2.
std::pair<int, int> cellAt(const Point2& x, int cells_x, int cells_y) {
  return {std::clamp(int(x.x() * cells_x), 0, cells_x - 1), std::clamp(int(x.y() * cells_y), 0, cells_y - 1)};
}

// The strata of S's n positions: nx columns by ny rows with nx ny = n, nx the largest divisor of n
// not above sqrt(n) (1024: 32 x 32; 8192: 64 x 128; a prime: one row of strips), so that every
// stratum holds exactly one position whether or not n is a square.
struct Strata {
  int nx, ny;
  explicit Strata(int n) : nx(std::max(1, int(std::sqrt(double(n))))), ny(0) {
    while (n % nx != 0) --nx;
    ny = n / nx;
  }
  // Position k of the bin (k < nx ny), u uniform in its stratum.
  Point2 position(int k, const Point2& u) const { return {(k % nx + u.x()) / nx, (k / nx + u.y()) / ny}; }
};

void add(ScalingSample* sum, const ScalingSample& sample) {
  sum->original += sample.original;
  sum->prefiltered += sample.prefiltered;
}

// A bin's R: the samples' weighted mean, sum(original) / sum(prefiltered).
Rgb ratio(const ScalingSample& sum, double epsilon) { return (sum.original + epsilon) / (sum.prefiltered + epsilon); }

// T's bin (a, b) before normalisation: R over uniform positions in the bin and cosine-weighted
// direction pairs (§4.7.1).
Rgb spatialBin(const ScalingSampler& R, int a, int b, int cells_x, int cells_y, const FactorizationSettings& s) {
  const int M = s.spatial_resolution;
  const double max_theta = s.max_theta_degrees * kPi / 180;
  RandomStream rng(s.seed, {0, a, b});
  ScalingSample sum;
  for (int k = 0; k < s.pairs_per_spatial_bin; ++k) {
    const Point2 u = rng.uniform2();
    const auto [cu, cv] = cellAt(Point2((a + u.x()) / M, (b + u.y()) / M), cells_x, cells_y);
    const Vec3 wi = limitPolarAngle(sampleCosineHemisphere(rng.uniform2()), max_theta);
    const Vec3 wo = limitPolarAngle(sampleCosineHemisphere(rng.uniform2()), max_theta);
    add(&sum, R(cu, cv, std::uint64_t(k), wi, wo));
  }
  return ratio(sum, s.epsilon);
}

// The ratio of sums with its first-order bias removed (Quenouille's jackknife): a ratio over n
// samples is biased by O(1/n), and n R - (n - 1) mean_i R_-i, with R_-i the ratio without sample i,
// cancels that term. Where it is not a finite non-negative number (one sample holds nearly all of a
// sum), the plain ratio.
Rgb jackknifedRatio(const std::vector<ScalingSample>& samples, const ScalingSample& sum, double epsilon) {
  const Rgb plain = ratio(sum, epsilon);
  if (samples.size() < 2) return plain;
  const double n = double(samples.size());
  Rgb leave_one_out = Rgb::Zero();
  for (const ScalingSample& sample : samples)
    leave_one_out += ((sum.original - sample.original).max(0.0) + epsilon) /
                     ((sum.prefiltered - sample.prefiltered).max(0.0) + epsilon);
  const Rgb jackknifed = n * plain - (n - 1) / n * leave_one_out;
  return (jackknifed.isFinite() && jackknifed >= 0).select(jackknifed, plain);
}

// An S bin's samples: their sums, those of o^2, m^2 and o m for the bin's standard error, and for
// the relief term those of m z, m z^2 and o z (o, m the original's and the prefiltered model's
// light, z the sample cell's relief).
struct AngularBinSums {
  ScalingSample sum;
  Rgb oo = Rgb::Zero(), mm = Rgb::Zero(), om = Rgb::Zero();
  Rgb mz = Rgb::Zero(), mzz = Rgb::Zero(), oz = Rgb::Zero();
  int count = 0;
  std::vector<ScalingSample> samples;  // kept for the jackknife only
  void add(const ScalingSample& sample, double z, bool keep) {
    vdbappear::add(&sum, sample);
    const Rgb& o = sample.original;
    const Rgb& m = sample.prefiltered;
    oo += o * o;
    mm += m * m;
    om += o * m;
    mz += m * z;
    mzz += m * (z * z);
    oz += o * z;
    ++count;
    if (keep) samples.push_back(sample);
  }
};

// The relative standard error of a bin's ratio r = sum o / sum m over its n samples, by the delta
// method: Var(r) ~ n / (n - 1) sum (o_k - r m_k)^2 / (sum m)^2, relative to r that is
// sqrt(n / (n - 1) sum (o_k - r m_k)^2) / sum o, with sum (o - r m)^2 = sum o^2 - 2 r sum o m +
// r^2 sum m^2. Averaged over the channels; 0 where the bin has one sample or no light.
double relativeStandardError(const AngularBinSums& b) {
  if (b.count < 2) return 0;
  const Rgb O = b.sum.original, M = b.sum.prefiltered;
  const Rgb r = O / M.max(1e-300);
  const Rgb residual = (b.oo - 2 * r * b.om + r * r * b.mm).max(0.0);
  const double n = b.count;
  const Rgb relative = (n / (n - 1) * residual).sqrt() / O.max(1e-300);
  return average((O > 0 && M > 0).select(relative, 0.0));
}

// The relief term's slope B of a bin: the weighted least squares of the samples' ratios
// r = o / m on their cells' z, weights m (the light each sends, as the ratio of sums weighs it):
//   B = cov_m(r, z) / var_m(z) = [sum o z - sum o sum m z / sum m] / [sum m z^2 - (sum m z)^2 / sum m],
// 0 where z barely varies over the bin's light (a flat map, a bin of one sample).
Rgb reliefSlope(const AngularBinSums& b) {
  const Rgb m = b.sum.prefiltered.max(1e-300);
  const Rgb variance = b.mzz - b.mz * b.mz / m, covariance = b.oz - b.sum.original * b.mz / m;
  return (variance > 1e-9 * m).select(covariance / variance.max(1e-300), Rgb::Zero());
}

struct AngularBinValue {
  Rgb intercept, slope;  // S, and B with the relief term (0 without): R = S + B z
  double relative_error = 0;  // of the bin's ratio (relativeStandardError)
};

// A bin's S, R's ratio of sums (jackknifed or plain) capped at max_scaling; with the relief term
// the fit's intercept S - B z_m, z_m = sum m z / sum m the bin's mean z as its light weighs it, so
// that S + B z_m, what the bin's own cells reflect together, is that ratio. A capped bin keeps
// B = 0: the model carries none of its cells' light as it should, whatever their relief.
AngularBinValue angularBinValue(const AngularBinSums& b, bool relief, const FactorizationSettings& s) {
  const Rgb plain = s.jackknife ? jackknifedRatio(b.samples, b.sum, s.epsilon) : ratio(b.sum, s.epsilon);
  const Rgb S = plain.min(s.max_scaling);
  const double error = relativeStandardError(b);
  if (!relief) return {S, Rgb::Zero(), error};
  const Rgb B = (plain > s.max_scaling).select(Rgb::Zero(), reliefSlope(b));
  return {S - B * b.mz / b.sum.prefiltered.max(1e-300), B, error};
}

// The visit of an S bin's k-th position: unique to the bin (`key`) and the position, and apart from
// T's visits (below 2^32). Keyed by k alone, every bin's k-th position drew the same estimate
// wherever the strata are the coarse cells (1024 positions over the 32^2 cells of a map at 32x): the
// bins' errors moved together, and an image, which reads many bins, kept them whole instead of
// averaging them (docs/displacement.md §6, "The tables' own error").
std::uint64_t angularVisit(std::int64_t key, int k) { return (std::uint64_t(key + 1) << 32) | std::uint64_t(k); }

// S's bin: R at the bins' directions over positions stratified over the whole map, one per stratum.
// `key` keys its random numbers.
AngularBinValue angularBin(const ScalingSampler& R, const Vec3& wi, const Vec3& wo, std::int64_t key, int cells_x,
                           int cells_y, const CellRelief* relief, const FactorizationSettings& s) {
  const int count = s.positions_per_angular_bin;
  const Strata strata(count);
  RandomStream rng(s.seed, {1, key});
  AngularBinSums sums;
  if (s.jackknife) sums.samples.reserve(std::size_t(count));
  for (int k = 0; k < count; ++k) {
    const Point2 x = strata.position(k, rng.uniform2());
    const auto [cu, cv] = cellAt(x, cells_x, cells_y);
    sums.add(R(cu, cv, angularVisit(key, k), wi, wo), relief ? relief->at(cu, cv) : 0.0, s.jackknife);
  }
  return angularBinValue(sums, relief != nullptr, s);
}

// With shared_positions, S's bins of one wo (bin wo_bin): R at every wi bin's direction over the same positions, stratified
// over the whole map, drawn from a stream keyed by the wo bin; out[k] for wis[k].
void angularBinsOfView(const ViewScalingSampler& R, const std::vector<Vec3>& wis, const Vec3& wo, std::int64_t wo_key,
                       int cells_x, int cells_y, const CellRelief* relief, const FactorizationSettings& s,
                       AngularBinValue* out) {
  const int count = s.positions_per_angular_bin;
  const Strata strata(count);
  RandomStream rng(s.seed, {2, wo_key});
  std::vector<AngularBinSums> sums(wis.size());
  std::vector<ScalingSample> batch(wis.size());
  for (auto& bin : sums)
    if (s.jackknife) bin.samples.reserve(std::size_t(count));
  for (int k = 0; k < count; ++k) {
    const Point2 x = strata.position(k, rng.uniform2());
    const auto [cu, cv] = cellAt(x, cells_x, cells_y);
    R(cu, cv, angularVisit(wo_key, k), wis, wo, batch.data());
    const double z = relief ? relief->at(cu, cv) : 0.0;
    for (std::size_t w = 0; w < wis.size(); ++w) sums[w].add(batch[w], z, s.jackknife);
  }
  for (std::size_t w = 0; w < wis.size(); ++w) out[w] = angularBinValue(sums[w], relief != nullptr, s);
}

// wo at S's node (oa, ob) (a bin centre, or with view_horizon one on the horizon), its polar angle
// limited (horizon nodes to view_horizon_degrees).
Vec3 viewAtNode(const AngularScaling& S, int oa, int ob, const FactorizationSettings& s) {
  const double limit = S.onHorizon(oa, ob) ? s.view_horizon_degrees : s.max_theta_degrees;
  return limitPolarAngle(S.viewNodeDirection(oa, ob), limit * kPi / 180);
}

// The key of S's entry (ia, ib, oa, ob)'s random numbers: a bin's index without horizon nodes, so
// that the bins read the same with or without them; a horizon node's its index past all of those.
std::int64_t angularKey(const AngularScaling& S, int ia, int ib, int oa, int ob) {
  const std::int64_t N = S.resolution, shift = S.view_horizon ? 1 : 0;
  if (S.onHorizon(oa, ob)) return N * N * N * N + std::int64_t(S.index(ia, ib, oa, ob));
  return ((ib * N + ia) * N + (ob - shift)) * N + (oa - shift);
}

}  // namespace

Vec3 limitPolarAngle(const Vec3& w, double max_theta) {
  const double theta = std::acos(std::clamp(w.z(), -1.0, 1.0));
  if (theta <= max_theta) return w;
  const double r = std::hypot(w.x(), w.y());
  if (r == 0) return w;
  return {w.x() / r * std::sin(max_theta), w.y() / r * std::sin(max_theta), std::cos(max_theta)};
}

std::uint64_t tableBins(const FactorizationSettings& s) {
  const std::uint64_t M = std::uint64_t(s.spatial_resolution), N = std::uint64_t(s.angular_resolution);
  const std::uint64_t V = s.view_horizon_degrees > 0 ? N + 2 : N;
  return M * M + N * N * V * V;
}

ViewScalingSampler sampledPerLight(ScalingSampler R) {
  return [R = std::move(R)](int u, int v, std::uint64_t visit, const std::vector<Vec3>& wis, const Vec3& wo,
                            ScalingSample* out) {
    for (std::size_t k = 0; k < wis.size(); ++k) out[k] = R(u, v, visit, wis[k], wo);
  };
}

FactorizedScaling factorizeScaling(const ScalingSampler& R, int cells_x, int cells_y,
                                   const FactorizationSettings& s, ProgressBar* progress,
                                   const ViewScalingSampler& R_view, const CellRelief* relief) {
  if (cells_x < 1 || cells_y < 1 || s.spatial_resolution < 1 || s.angular_resolution < 1 ||
      s.pairs_per_spatial_bin < 1 || s.positions_per_angular_bin < 1)
    throw std::invalid_argument("factorizeScaling: empty map, table or sample count");
  if (!(s.view_horizon_degrees >= 0 && s.view_horizon_degrees < 90))
    throw std::invalid_argument("factorizeScaling: the view's horizon nodes at 0 (none) or below 90 degrees");
  if (relief && (relief->empty() || relief->cells_x != cells_x || relief->cells_y != cells_y))
    throw std::invalid_argument("factorizeScaling: the relief is not of the map's coarse cells");
  const int M = s.spatial_resolution, N = s.angular_resolution;
  FactorizedScaling result;
  result.T.resolution = M;
  result.T.values.assign(std::size_t(M) * M, Rgb::Zero());
  result.S.resolution = N;
  result.S.view_horizon = s.view_horizon_degrees > 0;
  const int V = result.S.viewNodes();
  result.S.values.assign(std::size_t(N) * N * V * V, Rgb::Zero());
  if (relief) {
    result.S.relief_slopes.assign(result.S.values.size(), Rgb::Zero());
    result.relief = *relief;
  }
  result.S_relative_errors.assign(result.S.values.size(), 0.0);
  const auto store = [&](std::size_t index, const AngularBinValue& value) {
    result.S.values[index] = value.intercept;
    result.S_relative_errors[index] = value.relative_error;
    if (relief) result.S.relief_slopes[index] = value.slope;
  };

  tbb::parallel_for(std::size_t(0), result.T.values.size(), [&](std::size_t bin) {
    result.T.values[bin] = spatialBin(R, int(bin % M), int(bin / M), cells_x, cells_y, s);
    if (progress) progress->advance();
  });
  // Eq. (4.23): C makes T average one, so that S carries R's overall level.
  Rgb mean = Rgb::Zero();
  for (const Rgb& t : result.T.values) mean += t;
  mean /= double(result.T.values.size());
  for (Rgb& t : result.T.values) t = (mean > 0).select(t / mean, Rgb::Ones());

  const double max_theta = s.max_theta_degrees * kPi / 180;
  if (!s.shared_positions) {
    tbb::parallel_for(std::size_t(0), result.S.values.size(), [&](std::size_t bin) {
      const int oa = int(bin % V), ob = int(bin / V % V), ia = int(bin / (V * V) % N), ib = int(bin / (std::size_t(V) * V * N));
      const Vec3 wi = limitPolarAngle(result.S.binDirection(ia, ib), max_theta);
      const Vec3 wo = viewAtNode(result.S, oa, ob, s);
      const std::int64_t key = angularKey(result.S, ia, ib, oa, ob);
      store(result.S.index(ia, ib, oa, ob), angularBin(R, wi, wo, key, cells_x, cells_y, relief, s));
      if (progress) progress->advance();
    });
    return result;
  }
  std::vector<Vec3> wis;  // wi bin (ia, ib) at ia + N ib
  for (int ib = 0; ib < N; ++ib)
    for (int ia = 0; ia < N; ++ia) wis.push_back(limitPolarAngle(result.S.binDirection(ia, ib), max_theta));
  const ViewScalingSampler per_view = R_view ? R_view : sampledPerLight(R);
  tbb::parallel_for(std::size_t(0), std::size_t(V) * V, [&](std::size_t wo_node) {
    const int oa = int(wo_node % V), ob = int(wo_node / V);
    const Vec3 wo = viewAtNode(result.S, oa, ob, s);
    // wo's key: as angularKey() keys a bin of wi bin 0 (its bin without horizon nodes, or past them).
    const std::int64_t key = angularKey(result.S, 0, 0, oa, ob);
    std::vector<AngularBinValue> values(wis.size());
    angularBinsOfView(per_view, wis, wo, key, cells_x, cells_y, relief, s, values.data());
    for (int ib = 0; ib < N; ++ib)
      for (int ia = 0; ia < N; ++ia) store(result.S.index(ia, ib, oa, ob), values[std::size_t(ia + N * ib)]);
    if (progress) progress->advance(wis.size());
  });
  return result;
}

}  // namespace vdbappear
