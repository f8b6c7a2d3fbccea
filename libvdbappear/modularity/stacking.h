#pragma once
// §7 of the downsampling paper, "Downsampling exemplars": the N exemplar blocks are stacked
// (randomly) into one exemplar volume (sheets in one layer), which the whole pipeline (naive, lobes,
// clusters, weight optimisation) reduces once; `splitStacked` cuts the result back into reduced blocks, whose
// cluster ids and scaled phase functions then agree across blocks by construction.
// Light header: no OpenVDB.

#include "libvdbappear/io/medium_file.h"

#include <array>
#include <cstdint>
#include <vector>

namespace vdbappear {

struct StackOptions {
  enum class Order { Random, Sorted, Given };
  Order order = Order::Random;
  std::vector<int> permutation;  // Given: slot s holds exemplar permutation[s], each of 0..N-1 once
  std::uint64_t seed = 1;        // Random: the shuffle's seed
  std::array<int, 3> shape{0, 0, 0};  // slots along x, y, z; zeros: stackShape's
};

using BlockCounts = std::array<int, 3>;  // along x, y, z

// Slots of the exemplar volume along x, y, z for `count` blocks of `block` voxels: the box of least
// surface for its volume among those with at most one incomplete layer of slots; for sheets (blocks
// thinner than half their width and length, like fabric) among the single layers (nz = 1), so that
// the training views from above see every exemplar as they see a model. Measured (make modularity,
// docs/modularity.md §4): six 64x64x16 sheets stacked in a 1x1x6 column moved the held-out mean of a
// model by 1.5-1.7% from one random stacking to another; in a 2x3x1 layer it spreads by 0.3% over
// four stackings (the noise of the comparison: 0.1%).
BlockCounts stackShape(int count, const BlockCounts& block);

// The slots stackExemplars uses for this block set: options.shape, or stackShape's. Throws like it.
BlockCounts stackShapeFor(const Medium& blocks, const StackOptions& options);

// Slot s (x fastest) -> exemplar, for the first `count` slots; throws std::invalid_argument for a
// given permutation that is not one of 0..count-1.
std::vector<int> stackOrder(int count, const StackOptions& options);

// The block set (docs/medium.md, section 6b) rearranged into an exemplar volume: every grid travels
// with its voxels, the placement is the grid exemplar_stacking, exemplar_kind = stacked and
// exemplar_set names the block set. Throws MediumError for a medium that is not a block set.
MediumPtr stackExemplars(const Medium& blocks, const StackOptions& options);

// Any output of the pipeline run on a stacked medium -> a block set in the side-by-side format at
// the medium's resolution (exemplar_block divided by the reduction factor), every grid and the
// metadata (weight_factors included) carried. Throws MediumError for a medium without the placement
// or whose reduction factor does not divide the block side.
MediumPtr splitStacked(const Medium& stacked);

}  // namespace vdbappear
