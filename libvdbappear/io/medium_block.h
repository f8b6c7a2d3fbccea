#pragma once
// Building media leaf by leaf: the leaf nodes of one 8^3 block of every base grid, made off-tree
// (so blocks can be built in parallel) and then adopted into the trees (serially: inserting into a
// tree is not thread-safe). Includes OpenVDB (library code only).

#include "libvdbappear/io/medium.h"

#include <memory>

namespace vdbappear {

// Which base grids a medium has besides density.
struct BaseGrids {
  bool albedo = true;
  bool sggx = true;  // sggx_diag and sggx_offdiag
  bool hg_g = false;
};

// A medium with empty base grids named per the contract, sharing `transform`; backgrounds are the
// contract's defaults (density 0, albedo 1, S = I, g = 0).
MediumPtr makeEmptyMedium(const BaseGrids& grids, const openvdb::math::Transform::Ptr& transform);

class MediumBlock {
 public:
  using FloatLeaf = openvdb::FloatTree::LeafNodeType;
  using Vec3sLeaf = openvdb::Vec3STree::LeafNodeType;

  bool empty() const { return !density_; }

  // Creates the leaves at `origin` (a multiple of 8) for the base grids that `medium` has.
  void allocate(const Medium& medium, const openvdb::Coord& origin);

  // Sets voxel n (leaf offset) active in every grid of the block; values of absent grids are ignored.
  void setVoxel(openvdb::Index n, float density, const openvdb::Vec3s& albedo, const openvdb::Vec3s& sggx_diag,
                const openvdb::Vec3s& sggx_offdiag, float hg_g);

  // Moves the leaves into `medium`'s trees; the block is empty afterwards.
  void adoptInto(Medium& medium);

 private:
  std::unique_ptr<FloatLeaf> density_, hg_g_;
  std::unique_ptr<Vec3sLeaf> albedo_, sggx_diag_, sggx_offdiag_;
};

}  // namespace vdbappear
