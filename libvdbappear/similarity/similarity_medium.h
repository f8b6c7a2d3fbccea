#pragma once
// A medium altered by the similarity relations (similarity paper, Algorithm 1), as vdb_similarity
// writes it: density* and albedo* per voxel (similarity/altered_coefficients.h), one altered table
// per distinct phase function in `phase_table`, and `phase_id` where voxels differ (docs/medium.md
// §6). Light header: no OpenVDB.
//
// Phase functions in: `phase_table` (+ `phase_id`): each table once; an `hg_g` grid: g quantised
// (similarity/g_quantiser.h), one table per level in use, ids in ascending g; constant g
// (metadata `hg_g`, else 0): one table. The paper computes one altered version per homogeneous
// region and notes that many are costly; the quantisation bounds the moment error instead.

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/similarity/similarity_relation.h"

#include <cstdint>
#include <string>
#include <vector>

namespace vdbappear {

class ProgressBar;

struct MediumSimilarityOptions {
  SimilarityOptions phase;         // alpha 0: defaultAlpha per phase function (§7.2)
  double moment_tolerance = 1e-3;  // epsilon of the g quantisation (per-voxel hg_g only)
};

struct AlteredTable {
  std::string source;         // "hg g=0.9", "phase_table 2"
  double f1 = 0;              // the original mean cosine
  AlteredPhase phase;
  std::uint64_t voxels = 0;   // voxels with density > 0 that use it
};

struct MediumSimilarityResult {
  MediumPtr medium;
  std::vector<AlteredTable> tables;  // by phase_id
  std::uint64_t voxels = 0;          // voxels with density > 0
  int g_levels = 0;                  // quantisation levels M (0: g was not quantised)
  double moment_tolerance = 0;       // epsilon when quantised
  // max over voxels and n = 0..N0 of |f_n(g) - f_n(g_q)|: the measured quantisation error.
  double max_moment_error = 0;
  // max over voxels of AlteredCoefficients::reduced_attenuation_error (colour; 0 when grey).
  double max_reduced_attenuation_error = 0;
  std::vector<std::string> notes;    // grids or metadata replaced
};

// Throws MediumError for media with SGGX or lobe grids (their phase functions depend on the incident
// direction, which the 1-D theory does not cover), std::invalid_argument for options out of range
// or an alpha below a phase function's minimumAlpha().
MediumSimilarityResult alterMedium(const Medium& medium, const MediumSimilarityOptions& options,
                                   ProgressBar* progress = nullptr);

}  // namespace vdbappear
