#include "libvdbappear/optimize/training_error.h"

#include <stdexcept>

namespace vdbappear {

void addTrainingImage(const TrainingImage& image, const RenderResult& a, const RenderResult& b, TrainingError* error) {
  const int K = image.masks.clusters();
  const std::vector<Rgb> mean_a = restrictedMeans(a.mean, image.masks), mean_b = restrictedMeans(b.mean, image.masks);
  const bool gradients = !a.weight_gradients.empty() && !b.weight_gradients.empty();
  const int P = a.gradient_clusters * a.gradient_lobes;
  std::vector<Rgb> grad_a, grad_b;
  if (gradients) {
    grad_a = restrictedGradientMeans(a.weight_gradients, P, image.masks);
    grad_b = restrictedGradientMeans(b.weight_gradients, P, image.masks);
    if (error->dE_de.empty()) error->dE_de.assign(P, Rgb::Zero());
    if (int(error->dE_de.size()) != P) throw std::invalid_argument("addTrainingImage: parameter counts differ");
  }
  const Rgb c2 = image.normalisation * image.normalisation;
  double E = 0;
  error->relative_errors.emplace_back(K, Rgb::Zero());
  for (int k = 0; k < K; ++k) {
    if (image.masks.count(k) == 0) continue;
    error->relative_errors.back()[k] = ((mean_a[k] + mean_b[k]) / 2) / image.reference[k].max(1e-12) - 1;
    const Rgb da = mean_a[k] - image.reference[k], db = mean_b[k] - image.reference[k];
    E += (c2 * da * db).sum();
    if (!gradients) continue;
    for (int p = 0; p < P; ++p)
      error->dE_de[p] += c2 * (da * grad_b[std::size_t(k) * P + p] + db * grad_a[std::size_t(k) * P + p]);
    for (int c = 0; c < 3; ++c) {
      Residual r;
      r.channel = c;
      r.value = image.normalisation[c] * ((da[c] + db[c]) / 2);
      r.derivative.assign(P, Rgb::Zero());
      for (int p = 0; p < P; ++p)
        r.derivative[p][c] = image.normalisation[c] * (grad_a[std::size_t(k) * P + p][c] + grad_b[std::size_t(k) * P + p][c]) / 2;
      error->residuals.push_back(std::move(r));
    }
  }
  error->E += E;
  error->per_image.push_back(E);
}

}  // namespace vdbappear
