#pragma once
// The error metric of the weight optimisation and its gradient (Eq. 14 and 16, downsampling paper)
// from renders of the training images:
//   E = sum_r sum_c sum_k (c_r^c)^2 (mean_k(I~_r^c) - mean_k(I_r^c))^2
//   dE/de = 2 sum_r sum_c sum_k (c_r^c)^2 (mean_k(I~_r^c) - mean_k(I_r^c)) mean_k(dI~_r^c / de)
// summed over the RGB channels c (each channel is an image of its own, so colour scales see their
// channel's error). Eq. 16 as printed has c_r, not c_r^2: the derivative of Eq. 14 has the square.
//
// Each training image is rendered twice per iteration with independent seeds (A and B, half the
// samples each) and the products take one factor from each:
//   E ~ sum c^2 (mean_k(A) - ref)(mean_k(B) - ref)
//   dE/de ~ sum c^2 [(mean_k(A) - ref) mean_k(dB) + (mean_k(B) - ref) mean_k(dA)]
// so that both are unbiased; a product of two estimates from the same paths carries their
// covariance as a bias (about the noise variance of a restricted mean, the size of the error
// itself once the factors are close). Light header.

#include "libvdbappear/optimize/training_images.h"

#include <vector>

namespace vdbappear {

// One term of Eq. 14 before squaring, with its derivatives: c_r^c (mean_k(I~_r^c) - mean_k(I_r^c))
// and, per (cluster, lobe) parameter, c_r^c mean_k(dI~_r^c / de_kj) (channel c of a vector of RGB).
struct Residual {
  double value = 0;
  int channel = 0;
  std::vector<Rgb> derivative;  // [k * lobes + j]; only `channel` is non-zero
};

struct TrainingError {
  double E = 0;                     // Eq. 14 (unbiased estimate: may come out slightly negative)
  std::vector<double> per_image;    // E of each training image
  std::vector<Rgb> dE_de;           // Eq. 16: dE / de_kj^c, [k * lobes + j]
  std::vector<Residual> residuals;  // every (image, cluster, channel), from the mean of A and B
  // Per image and cluster, mean_k(I~) / mean_k(I) - 1 per channel (A and B averaged; 0 where the
  // cluster is not visible): what E is made of, for reports.
  std::vector<std::vector<Rgb>> relative_errors;
};

// Adds training image `image`'s share from its two half renders (with weight_gradients unless only
// E is wanted: then dE_de and residuals stay empty).
void addTrainingImage(const TrainingImage& image, const RenderResult& a, const RenderResult& b, TrainingError* error);

}  // namespace vdbappear
