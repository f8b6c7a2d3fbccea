#pragma once
// A medium file read slab by slab along x, in memory bounded by a budget (docs/scaling.md §5): the
// file is opened with OpenVDB's delayed loading (the trees' topology in memory, leaf values read
// from the file when first used), and each slab's leaves are moved out of the file's trees into a
// medium of their own, validated and handed over, then freed with it. For reductions whose output
// voxel needs only its own children (naive downsampling): slabs are aligned to whole coarse leaves.
// Internal header: includes OpenVDB.

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace vdbappear {

// The grid types a slab, or any part of a medium, can hold (the contract's, and the usual foreign
// ones); a file with a grid of another type is read whole. GridBase::apply calls an operation on the
// grid as its own type.
using SlabGridTypes = openvdb::TypeList<openvdb::FloatGrid, openvdb::Vec3SGrid, openvdb::Int32Grid, openvdb::DoubleGrid,
                                        openvdb::Vec3DGrid, openvdb::Int64Grid>;

// Grids indexed by voxel are cut into parts; the others (the phase table, the exemplar grids indexed
// by block) are the same in every part.
inline bool isVoxelIndexed(const std::string& name) {
  return name != grid_names::kPhaseTable && !isBlockIndexedGridName(name);
}

// [x0, x1): a slab's fine voxel columns.
using SlabRange = std::pair<int, int>;

class MediumSlabs {
 public:
  // Opens `path` (MediumError for a missing or unreadable file, as readMedium gives).
  MediumSlabs(const std::string& path, const GridMapping& mapping);

  // Why the file must be read whole instead (a grid mapping applies to it, or a grid is of a type a
  // slab does not take), or nullopt. plan and slab need a file read in slabs.
  const std::optional<std::string>& whyNotStreamed() const { return why_not_; }

  // Slabs of whole bands `band` voxels wide (band = 8 F for factor F, aligned to x = 0), covering
  // every active value in increasing x, each as wide as fits in `memory_bytes` less what stays in
  // memory throughout: the trees' topology on the input file's side and on the output's (a leaf per
  // band-wide block that holds a leaf, per voxel grid, its values spilled to disk:
  // io/spilled_medium.h). No slabs if one band alone does not fit.
  struct Plan {
    std::vector<SlabRange> slabs;
    std::uint64_t largest_band_bytes = 0;  // a band's leaves and its output's, every voxel grid
    std::uint64_t resident_bytes = 0;      // the topology of input and output
  };
  // Slabs hold at most `slab_target_bytes` where the budget allows more: small slabs cost no time.
  Plan plan(int band, std::uint64_t memory_bytes, std::uint64_t slab_target_bytes = ~std::uint64_t(0)) const;

  // The slab's medium: its leaves taken from the file's trees (so call each range once, in any
  // order), active tiles cut to it, the grids that are not indexed by voxel copied whole; each grid
  // validated as readMedium validates a grid (an empty density excepted), then across grids.
  MediumPtr slab(const SlabRange& range);

  // The whole-medium checks that no slab can make: some voxel had density > 0. Call after the last slab.
  void finish() const;

  const std::vector<std::string>& notes() const { return notes_; }

 private:
  std::string path_;
  openvdb::MetaMap::Ptr metadata_;
  openvdb::GridPtrVec grids_;  // topology, values on the file (delayed loading)
  // Per voxel-indexed grid (null tiles otherwise), found once: its leaves' origins sorted by x, and
  // its tiles (active, or inactive with another value than the background) as a grid of their own,
  // so that a slab visits its own leaves and the few tiles, not every node slot of the file's trees.
  struct Pieces {
    std::vector<openvdb::Coord> leaves;
    openvdb::GridBase::Ptr tiles;
  };
  std::vector<Pieces> pieces_;
  std::optional<std::string> why_not_;
  std::vector<std::string> notes_;
  bool saw_density_ = false;
};

}  // namespace vdbappear
