#pragma once
// §7 of the downsampling paper: a model synthesised from exemplar blocks is built by placing, at
// each of its blocks, the exemplar its layout names; from full-resolution blocks this gives the
// reference, from blocks cut out of one stacked, reduced and optimised volume the fast model.
// Light header: no OpenVDB.

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/modularity/exemplar_layout.h"

namespace vdbappear {

// A layout taken from another medium (assemble --layout MEDIUM) must describe blocks of this set: the
// same exemplar count and the same block size in world units (the resolutions may differ: a reduced
// block set assembled with the full one's layout). Throws MediumError naming both files otherwise.
void checkLayoutMedium(const Medium& layout_medium, const Medium& blocks);

// The model whose block (i, j, k) holds, bit for bit, the voxels of exemplar layout.at(i, j, k)
// (index x in [i*Bx, (i+1)*Bx), ...; the block set's transform). Every grid and the metadata
// (weight_factors included) are carried; exemplar_layout becomes `layout`, exemplar_kind = model and
// exemplar_set names the exemplars. Throws MediumError for a medium that is not a block set and for
// a layout naming an exemplar the set lacks.
MediumPtr assembleModel(const Medium& blocks, const ExemplarLayout& layout);

// The same model, instanced: the block set's grids as they are plus `layout` as exemplar_layout and
// exemplar_kind = instanced (a file that grows with the block set, not the model). vdb_render looks
// its voxels up through the layout (modularity/instance_mapping.h).
MediumPtr instancedModel(const Medium& blocks, const ExemplarLayout& layout);

}  // namespace vdbappear
