#include "libvdbappear/io/medium_block.h"

namespace vdbappear {

namespace {

template <typename GridT>
typename GridT::Ptr makeGrid(const char* name, typename GridT::ValueType background,
                             const openvdb::math::Transform::Ptr& transform) {
  auto grid = GridT::create(background);
  grid->setName(name);
  grid->setTransform(transform);
  return grid;
}

template <typename GridPtrT, typename LeafT>
std::unique_ptr<LeafT> leafFor(const GridPtrT& grid, const openvdb::Coord& origin) {
  return grid ? std::make_unique<LeafT>(origin, grid->background()) : nullptr;
}

template <typename GridPtrT, typename LeafT>
void adopt(const GridPtrT& grid, std::unique_ptr<LeafT>& leaf) {
  if (grid && leaf) grid->tree().addLeaf(leaf.release());
  leaf.reset();
}

}  // namespace

MediumPtr makeEmptyMedium(const BaseGrids& grids, const openvdb::math::Transform::Ptr& transform) {
  auto medium = std::make_shared<Medium>();
  medium->density = makeGrid<openvdb::FloatGrid>(grid_names::kDensity, 0.0f, transform);
  medium->density->setGridClass(openvdb::GRID_FOG_VOLUME);
  if (grids.albedo) medium->albedo = makeGrid<openvdb::Vec3SGrid>(grid_names::kAlbedo, defaults::kAlbedo, transform);
  if (grids.sggx) {
    medium->sggx_diag = makeGrid<openvdb::Vec3SGrid>(grid_names::kSggxDiag, defaults::kSggxDiag, transform);
    medium->sggx_offdiag = makeGrid<openvdb::Vec3SGrid>(grid_names::kSggxOffdiag, defaults::kSggxOffdiag, transform);
  }
  if (grids.hg_g) medium->hg_g = makeGrid<openvdb::FloatGrid>(grid_names::kHgG, defaults::kHgG, transform);
  medium->metadata.insertMeta(metadata_names::kSchema, openvdb::Int32Metadata(metadata_names::kSchemaVersion));
  return medium;
}

void MediumBlock::allocate(const Medium& medium, const openvdb::Coord& origin) {
  density_ = leafFor<openvdb::FloatGrid::Ptr, FloatLeaf>(medium.density, origin);
  albedo_ = leafFor<openvdb::Vec3SGrid::Ptr, Vec3sLeaf>(medium.albedo, origin);
  sggx_diag_ = leafFor<openvdb::Vec3SGrid::Ptr, Vec3sLeaf>(medium.sggx_diag, origin);
  sggx_offdiag_ = leafFor<openvdb::Vec3SGrid::Ptr, Vec3sLeaf>(medium.sggx_offdiag, origin);
  hg_g_ = leafFor<openvdb::FloatGrid::Ptr, FloatLeaf>(medium.hg_g, origin);
}

void MediumBlock::setVoxel(openvdb::Index n, float density, const openvdb::Vec3s& albedo,
                           const openvdb::Vec3s& sggx_diag, const openvdb::Vec3s& sggx_offdiag, float hg_g) {
  density_->setValueOn(n, density);
  if (albedo_) albedo_->setValueOn(n, albedo);
  if (sggx_diag_) sggx_diag_->setValueOn(n, sggx_diag);
  if (sggx_offdiag_) sggx_offdiag_->setValueOn(n, sggx_offdiag);
  if (hg_g_) hg_g_->setValueOn(n, hg_g);
}

void MediumBlock::adoptInto(Medium& medium) {
  adopt(medium.density, density_);
  adopt(medium.albedo, albedo_);
  adopt(medium.sggx_diag, sggx_diag_);
  adopt(medium.sggx_offdiag, sggx_offdiag_);
  adopt(medium.hg_g, hg_g_);
}

}  // namespace vdbappear
