#pragma once
// Multi-lobe SGGX fit of one downsampled voxel (§5 of the downsampling paper): the children's S
// (the input voxels with density > 0) are clustered by K-means as 9-D vectors, and each cluster
// becomes one lobe with the mean S of its members (Eq. 10) and the fraction |V(i,j)| / |V(i)| of the
// children it holds (the factor of Eq. 11). The number of lobes follows §8.1: start at m = 1 and add
// a lobe while the fit error with m + 1 lobes is at most half the error with m lobes, up to a cap.
// Light header: Eigen only.

#include "libvdbappear/math/vector.h"

#include <cstdint>
#include <vector>

namespace vdbappear {

struct LobeFitOptions {
  int max_lobes = 3;      // the cap on m (§8.1: 3)
  int forced_lobes = 0;   // > 0: exactly this m (fewer where the children hold fewer distinct S)
  double keep_ratio = 0.5;  // add lobe m+1 while error(m+1) <= keep_ratio * error(m) (§8.1: 50%)
};

struct SggxLobe {
  Mat3 S;                // Eq. (10): the mean S of the lobe's children
  double fraction = 0;   // |V(i,j)| / |V(i)|
};

struct LobeFit {
  std::vector<SggxLobe> lobes;  // ordered by decreasing fraction (ties: K-means order)
  // error_by_lobes[m - 1]: the fit error with m lobes, for every m tried (lobeFitError).
  std::vector<double> error_by_lobes;
  // The L2 norm over the sphere of the children's mean D, the scale of the errors.
  double target_norm = 0;
};

// The L2 distance over the sphere between the lobes' mixture sum_j fraction_j D(S_j) and the mean
// of the children's D: sqrt(integral (mixture - mean)^2 dm), over the quadrature of
// lobes/ndf_quadrature.h.
double lobeFitError(const std::vector<SggxLobe>& lobes, const std::vector<Mat3>& children);

// The fit of §5: for each m, K-means with m clusters on the children's S as 9-D vectors (Frobenius
// distance; math/kmeans.h, seeded from `seed` and m), one lobe per non-empty cluster; the lobes
// returned are those of the m chosen by §8.1 (or options.forced_lobes). children must not be empty.
LobeFit fitLobes(const std::vector<Mat3>& children, const LobeFitOptions& options, std::uint64_t seed);

}  // namespace vdbappear
