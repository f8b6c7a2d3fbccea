#include "libvdbappear/io/medium.h"

#include <algorithm>
#include <regex>

namespace vdbappear {

openvdb::GridCPtrVec Medium::grids() const {
  openvdb::GridCPtrVec all;
  for (openvdb::GridBase::ConstPtr grid :
       {openvdb::GridBase::ConstPtr(density), openvdb::GridBase::ConstPtr(albedo),
        openvdb::GridBase::ConstPtr(sggx_diag), openvdb::GridBase::ConstPtr(sggx_offdiag),
        openvdb::GridBase::ConstPtr(hg_g)}) {
    if (grid) all.push_back(grid);
  }
  all.insert(all.end(), other_grids.begin(), other_grids.end());
  return all;
}

bool isLobeGridName(const std::string& name) {
  static const std::regex lobe("lobe[0-9]+_(diag|offdiag|fraction|weight)");
  return std::regex_match(name, lobe);
}

openvdb::BBoxd worldBoxOfCells(const openvdb::math::Transform& transform, const openvdb::CoordBBox& voxels) {
  openvdb::BBoxd box;
  for (int corner = 0; corner < 8; ++corner) {
    const openvdb::Vec3d index(corner & 1 ? voxels.max().x() + 0.5 : voxels.min().x() - 0.5,
                               corner & 2 ? voxels.max().y() + 0.5 : voxels.min().y() - 0.5,
                               corner & 4 ? voxels.max().z() + 0.5 : voxels.min().z() - 0.5);
    box.expand(transform.indexToWorld(index));
  }
  return box;
}

openvdb::CoordBBox framedVoxels(const Medium& medium) {
  openvdb::CoordBBox box = medium.density->evalActiveVoxelBoundingBox();
  if (const auto emission = findOtherGrid<openvdb::Vec3SGrid>(medium, grid_names::kEmission))
    box.expand(emission->evalActiveVoxelBoundingBox());  // an empty box leaves it as it is
  if (const auto temperature = findOtherGrid<openvdb::FloatGrid>(medium, grid_names::kBlackbodyTemperature))
    box.expand(temperature->evalActiveVoxelBoundingBox());
  return box;
}

void removeOtherGrid(Medium& medium, const std::string& name) {
  auto& grids = medium.other_grids;
  grids.erase(std::remove_if(grids.begin(), grids.end(), [&](const auto& g) { return g->getName() == name; }),
              grids.end());
}

bool isBlockIndexedGridName(const std::string& name) {
  return name == grid_names::kExemplarLayout || name == grid_names::kExemplarStacking;
}

std::optional<double> hgGMetadata(const openvdb::MetaMap& metadata) {
  if (auto f = metadata.getMetadata<openvdb::FloatMetadata>(metadata_names::kHgG)) return f->value();
  if (auto d = metadata.getMetadata<openvdb::DoubleMetadata>(metadata_names::kHgG)) return d->value();
  return std::nullopt;
}

std::optional<double> blackbodyIntensityMetadata(const openvdb::MetaMap& grid) {
  if (auto f = grid.getMetadata<openvdb::FloatMetadata>(metadata_names::kBlackbodyIntensity)) return f->value();
  if (auto d = grid.getMetadata<openvdb::DoubleMetadata>(metadata_names::kBlackbodyIntensity)) return d->value();
  return std::nullopt;
}

}  // namespace vdbappear
