#pragma once
// An instanced model (§7; docs/modularity.md): the block set and a layout, rendered without building
// the model's grids. Every voxel lookup goes through the layout: model voxel v in block b is voxel
// v - b*B of exemplar layout(b), at index (e*Bx, 0, 0) + (v - b*B) of the block set. Memory grows
// with the block set and the layout, not with the model (its majorant included:
// instanced_majorant_traversal.h). Includes OpenVDB (library code only).

#include "libvdbappear/io/medium.h"
#include "libvdbappear/modularity/block_moves.h"
#include "libvdbappear/modularity/exemplar_layout.h"

#include <map>
#include <optional>

namespace vdbappear {

class InstanceMapping {
 public:
  // The mapping of a medium whose exemplar_kind is `instanced`; nullopt for any other medium. Throws
  // MediumError when its metadata or layout are broken, or when a block side is not a multiple of
  // `block_multiple` (the majorant's block, so that majorant blocks do not straddle model blocks).
  static std::optional<InstanceMapping> of(const Medium& medium, int block_multiple);

  // The block-set voxel that model voxel `v` reads; a voxel far from every grid's data where the
  // layout has no exemplar.
  openvdb::Coord operator()(const openvdb::Coord& v) const {
    const openvdb::Coord b = blockOf(v, block_);
    if (b.x() < 0 || b.y() < 0 || b.z() < 0 || b.x() >= layout_.width || b.y() >= layout_.height ||
        b.z() >= layout_.depth)
      return kNowhere;
    const int e = layout_.at(b.x(), b.y(), b.z());
    if (e == ExemplarLayout::kEmpty) return kNowhere;
    return openvdb::Coord(v.x() + (e - b.x()) * block_.x(), v.y() - b.y() * block_.y(), v.z() - b.z() * block_.z());
  }

  const openvdb::Coord& block() const { return block_; }
  const ExemplarLayout& layout() const { return layout_; }

  // The bounding box of the model's active voxels: each placed exemplar's own box, shifted.
  openvdb::CoordBBox modelBounds(const openvdb::FloatGrid& density) const;

  // How many voxels the model's majorant would have if built (forEachInstancedMajorantSegment,
  // instanced_majorant_traversal.h, walks it without building it): the block set's majorant grid,
  // whose voxels are `unit` of its voxels on a side, counted as the layout places it.
  std::uint64_t modelMajorantVoxelCount(const openvdb::FloatGrid& set_majorant, int unit) const;

  // Voxels of the model if it were built: the sum over placed blocks of their exemplar's active voxels.
  std::uint64_t modelVoxelCount(const openvdb::FloatGrid& density) const;

 private:
  static inline const openvdb::Coord kNowhere{-(1 << 29)};

  // The sum over the layout's placed blocks of their exemplar's count (keyed by its block (e, 0, 0)).
  std::uint64_t placedTotal(std::map<openvdb::Coord, std::uint64_t> per_exemplar) const;

  openvdb::Coord block_;
  int count_ = 0;
  ExemplarLayout layout_;
};

}  // namespace vdbappear
