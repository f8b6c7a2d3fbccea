#include "libvdbappear/medium/blackbody.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/vector.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

namespace {

constexpr double kMinKelvin = 800, kMaxKelvin = 12000, kTableStep = 5;

// One lobe of the fit: a Gaussian of mean mu with widths below and above it.
double lobe(double lambda, double mu, double below, double above) {
  const double t = (lambda - mu) / (lambda < mu ? below : above);
  return std::exp(-0.5 * t * t);
}

// The CIE 1931 colour-matching functions at `lambda` nanometres (Wyman, Sloan and Shirley 2013,
// the multi-lobe fit, their Eq. 2).
Vec3 colourMatching(double lambda) {
  const double x = 1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7) -
                   0.065 * lobe(lambda, 501.1, 20.4, 26.2);
  const double y = 0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1);
  const double z = 1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8);
  return {x, y, z};
}

// Planck's spectral radiance up to a constant factor: 1 / (lambda^5 (exp(hc / (lambda k T)) - 1)).
double planck(double lambda_nm, double kelvin) {
  constexpr double hc_over_k = 1.438776877e-2;  // m K (second radiation constant)
  const double lambda = lambda_nm * 1e-9;
  return 1 / (std::pow(lambda, 5) * std::expm1(hc_over_k / (lambda * kelvin)));
}

}  // namespace

Rgb blackbodyColour(double kelvin) {
  const double T = std::clamp(kelvin, kMinKelvin, kMaxKelvin);
  Vec3 xyz = Vec3::Zero();
  for (int lambda = 360; lambda <= 830; ++lambda) xyz += planck(lambda, T) * colourMatching(lambda);
  xyz /= xyz.y();  // luminance 1
  Mat3 to_rec709;  // XYZ to linear Rec.709 primaries, D65 white
  to_rec709 << 3.2404542, -1.5371385, -0.4985314, -0.9692660, 1.8760108, 0.0415560, 0.0556434, -0.2040259, 1.0572252;
  return (to_rec709 * xyz).array();
}

BlackbodyTable::BlackbodyTable() {
  const int n = int(std::lround((kMaxKelvin - kMinKelvin) / kTableStep)) + 1;
  colours_.reserve(std::size_t(n));
  for (int i = 0; i < n; ++i) colours_.push_back(blackbodyColour(kMinKelvin + kTableStep * i));
}

Rgb BlackbodyTable::operator()(double kelvin) const {
  const double x = (std::clamp(kelvin, kMinKelvin, kMaxKelvin) - kMinKelvin) / kTableStep;
  const std::size_t i = std::min(std::size_t(x), colours_.size() - 2);
  const double f = x - double(i);
  return (1 - f) * colours_[i] + f * colours_[i + 1];
}

Rgb principledBlackbodyEmission(double attribute, const PrincipledBlackbody& settings, const BlackbodyTable& table) {
  constexpr double kCutoff = 1e-5;  // Cycles' CLOSURE_WEIGHT_CUTOFF: no light at or below it
  if (!(settings.intensity > kCutoff)) return Rgb::Zero();
  const double T = settings.kelvin * std::max(attribute, 0.0);
  const double T4 = (T * T) * (T * T);
  const double sigma = 5.670373e-8 * 1e-6 / kPi;
  const double intensity = sigma * ((1 - settings.intensity) + settings.intensity * T4);
  if (!(intensity > kCutoff)) return Rgb::Zero();
  return (settings.tint * intensity * table(T)).max(0.0);
}

}  // namespace vdbappear
