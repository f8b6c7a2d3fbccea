#pragma once
// Naive downsampling of a medium (Eq. 5-6 of the downsampling paper): the baseline that every
// other reduction is compared with. Light header: no OpenVDB.

#include "libvdbappear/io/medium_file.h"

#include <string>
#include <vector>

namespace vdbappear {

class ProgressBar;

// How the children's SGGX matrices are averaged into a coarse voxel.
enum class SggxWeighting {
  Count,    // Eq. (5): plain mean over the children with density > 0 (the paper's baseline)
  Density,  // mean weighted by the children's density (commutes with chaining F = a then b)
};

inline constexpr int kMaxDownsampleFactor = 64;

struct DownsampleOptions {
  int factor = 2;  // 2 <= F <= kMaxDownsampleFactor: output voxel I holds input voxels F*I .. F*I+F-1 per axis
  SggxWeighting s_weighting = SggxWeighting::Count;
};

struct DownsampleResult {
  MediumPtr medium;
  std::vector<std::string> warnings;  // grids dropped, with the reason
};

// density: mean over all F^3 children, empty children counting as 0 (Eq. 6);
// albedo: density-weighted mean per channel (Eq. 6); S: see SggxWeighting (Eq. 5);
// hg_g: mean weighted by the scattering coefficient rho * mean(albedo) (preserves the mixture's
// first Legendre moment), or by density where nothing scatters; emission: see
// downsample/emission_downsample.h (docs/medium.md §3b).
// A coarse voxel is active when one of its children has density > 0. The world region is
// preserved (docs/medium.md, Placement). Works leaf by leaf in parallel and never densifies.
// Throws MediumError for grids it cannot downsample (multi-lobe, cluster, phase_id) and for
// non-linear transforms.
DownsampleResult downsampleNaive(const Medium& fine, const DownsampleOptions& options,
                                 ProgressBar* progress = nullptr);

}  // namespace vdbappear
