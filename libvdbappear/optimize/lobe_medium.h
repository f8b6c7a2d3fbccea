#pragma once
// The multi-lobe medium the weight optimisation works on (docs/medium.md §5): what it needs to know
// of it, the checks that it is vdb_lobe_cluster's output on the full-resolution medium, and the
// optimised medium it writes (Eq. 12 and 19 applied to the lobe weights). Light header: no OpenVDB.

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/optimize/weight_factors.h"

#include <nlohmann/json.hpp>

#include <vector>

namespace vdbappear {

struct LobeMediumLayout {
  int clusters = 0;  // K: 1 + the largest id of `cluster`
  int lobes = 0;     // m: the lobe slots lobe0 .. lobe{m-1}
  // Per cluster k, the naive weights of its voxels: voxel v's lobe j, channel c at
  // [(v * lobes + j) * 3 + c] (inactive slots 0): what the effective-albedo limit needs.
  std::vector<std::vector<float>> naive_weights;
  bool coloured = false;  // some voxel's weights differ between channels (semi-coloured media, §6.4)
};

// Throws MediumError naming the file and the grid when the medium has no lobe or cluster grids, or
// already holds optimised weights (metadata `weight_factors`).
LobeMediumLayout inspectLobeMedium(const Medium& lobes);

// The factor F by which `lobes` was downsampled from `full`: its transform is full's coarsened by
// F (2..64) and its density holds full's mass (Eq. 6: sum of the children / F^3) to 1e-4. Throws
// MediumError naming LOBES otherwise.
int downsamplingFactor(const Medium& full, const Medium& lobes);

// LOBES with every lobe{j}_weight multiplied by s_c(i) w_c(i)j (Eq. 12, 19) and the file metadata
// `weight_factors` set to `record` (a JSON object holding at least factors.toJson()). The other grids
// are shared with `lobes`.
MediumPtr applyWeightFactors(const Medium& lobes, const WeightFactors& factors, const nlohmann::json& record);

// Keeps factors where the estimator and the medium stay physical: every factor at least kMinFactor,
// and every voxel's effective albedo sum_j W_ij^c <= 1 per channel (a cluster whose largest
// effective albedo exceeds 1 in channel c is scaled down by it: s_k^c with colour scales, w_k^c per
// channel, all of w_k in grey mode); colour scales normalised (WeightFactors::normaliseColourScales).
// Returns true when the albedo limit changed something.
inline constexpr double kMinFactor = 0.01;
bool constrainFactors(const LobeMediumLayout& layout, WeightFactors& factors);
// Is every voxel's effective albedo at most 1 per channel?
bool isFeasible(const LobeMediumLayout& layout, const WeightFactors& factors);

}  // namespace vdbappear
