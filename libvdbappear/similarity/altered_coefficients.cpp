#include "libvdbappear/similarity/altered_coefficients.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

double referenceAlbedo(const Rgb& albedo, double f1, double alpha) {
  const Rgb weight = 1 / (1 - albedo * f1);  // 1 / sigma_tr,1 per unit density
  auto worst = [&](double x) { return ((albedo - x).abs() * weight).maxCoeff(); };
  // The objective is convex and piecewise linear: its minimum is where a rising branch
  // (x - a_i) w_i meets a falling one (a_j - x) w_j, or at a channel's own albedo.
  double best = albedo[0], best_value = worst(albedo[0]);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double x = i == j ? albedo[i] : (albedo[i] * weight[i] + albedo[j] * weight[j]) / (weight[i] + weight[j]);
      const double value = worst(x);
      if (value < best_value) best = x, best_value = value;
    }
  // No channel may need negative scattering: a_ref (1 - alpha) <= min_c a_c. The objective is
  // convex, so its minimum over the allowed interval is the clamped one.
  return alpha < 1 ? std::min(best, albedo.minCoeff() / (1 - alpha)) : best;
}

AlteredCoefficients alterCoefficients(double density, const Rgb& albedo, double alpha, double f1) {
  AlteredCoefficients altered;
  const double a_ref = referenceAlbedo(albedo, f1, alpha);
  const double r = 1 - a_ref * (1 - alpha);
  altered.density = density * r;
  altered.albedo = (1 - (1 - albedo) / r).max(0.0);  // max: rounding only
  // Eq. (11) at n = 1, per unit of the original density: sigma_tr,1 = sigma_t - sigma_s f_1.
  const double f1_altered = 1 - (1 - f1) / alpha;  // Eq. (23)
  const Rgb original = 1 - albedo * f1;
  const Rgb altered_term = r * (1 - altered.albedo * f1_altered);
  altered.reduced_attenuation_error = ((altered_term - original).abs() / original).maxCoeff();
  return altered;
}

}  // namespace vdbappear
