#pragma once
// A medium file read slab by slab along x, in memory bounded by a budget (docs/scaling.md §5): the
// file is mapped and each grid's topology walked once, a node at a time (io/slab_tree_index.h), so
// that what stays in memory is a few hundred bytes per 128^3 node; each slab's leaves are then read
// from the file into a medium of their own, validated and handed over, then freed with it. For reductions whose output
// voxel needs only its own children (naive downsampling): slabs are aligned to whole coarse leaves.
// Internal header: includes OpenVDB.

#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace vdbappear {

class MappedVdbFile;
class SlabTreeIndex;

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

// Slabs of at most this much where the budget allows more: smaller slabs cost no time (a 512^3
// twill downsampled: 4.0 s in 6 slabs of 0.49 GB, 4.4 s in 32 of 0.1 GB, 5.3 s in one of 2.7 GB).
inline constexpr std::uint64_t kSlabTargetBytes = 500'000'000;

// The pieces are slabs of whole bands along x; a band larger than the piece's target is cut along y
// and z into cells of cellSize(band) voxels (a multiple of the band, at least a 128^3 node), so that
// a piece's size does not grow with the medium's cross-section.
int cellSize(int band);

// "x = 0..31", with the y and z ranges where the piece is cut along them: for messages.
std::string pieceName(const openvdb::CoordBBox& piece);

class MediumSlabs {
 public:
  // Opens `path` (MediumError for a missing or unreadable file, as readMedium gives).
  MediumSlabs(const std::string& path, const GridMapping& mapping);
  ~MediumSlabs();

  // Why the file must be read whole instead (a grid mapping applies to it, a grid is of a type a slab
  // does not take, or the file's format is older than the parts reader takes), or nullopt. plan and slab need a file read in slabs.
  const std::optional<std::string>& whyNotStreamed() const { return why_not_; }

  // Pieces covering every active value: slabs of whole bands `band` voxels wide (band = 8 F for
  // factor F, aligned to x = 0), in increasing x, each as wide as fits in `memory_bytes` less what
  // stays in memory throughout: the input's index (io/slab_tree_index.h) and the output's topology (a
  // leaf per band-wide block that holds a leaf, per voxel grid, its values spilled to disk:
  // io/spilled_medium.h); a band that does not fit is cut into runs of cells along y, then z. No
  // pieces if one cell alone does not fit.
  struct Plan {
    std::vector<openvdb::CoordBBox> slabs;  // the pieces: whole bands, or cells of one band
    std::uint64_t largest_cell_bytes = 0;   // a cell's leaves and its output's, every voxel grid
    std::uint64_t resident_bytes = 0;       // the input's index and the output's topology
  };
  // Slabs hold at most `slab_target_bytes` where the budget allows more: small slabs cost no time.
  // An output with `extra_output_grids` voxel grids more than the input (lobe grids), each with the
  // density's output topology, is counted as such.
  Plan plan(int band, std::uint64_t memory_bytes, std::uint64_t slab_target_bytes = ~std::uint64_t(0),
            int extra_output_grids = 0) const;
  // The same plan; MediumError naming the budget one cell needs where it does not fit.
  Plan planWithin(int band, std::uint64_t memory_bytes, std::uint64_t slab_target_bytes, int extra_output_grids = 0) const;

  // The piece's medium: its leaves read from the file (any box, in any order), active tiles cut to it, the grids that are not indexed by voxel copied whole; each grid
  // validated as readMedium validates a grid (an empty density excepted), then across grids.
  MediumPtr slab(const openvdb::CoordBBox& piece);

  // The whole-medium checks that no slab can make: some voxel had density > 0. Call after the last slab.
  void finish() const;

  const std::vector<std::string>& notes() const { return notes_; }

 private:
  std::string path_;
  std::unique_ptr<MappedVdbFile> file_;
  openvdb::MetaMap::Ptr metadata_;
  // Per grid: a voxel-indexed grid's name, metadata, transform and background (no voxels) and its
  // index; any other grid read whole (and a null index).
  openvdb::GridPtrVec grids_;
  std::vector<std::unique_ptr<SlabTreeIndex>> indices_;
  std::optional<std::string> why_not_;
  std::vector<std::string> notes_;
  bool saw_density_ = false;
};

}  // namespace vdbappear
