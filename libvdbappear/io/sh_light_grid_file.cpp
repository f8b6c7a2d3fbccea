#include "libvdbappear/io/sh_light_grid_file.h"
#include "libvdbappear/io/vdb_read_error.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/vdb_writer.h"
#include "libvdbappear/lightgrid/adaptive_sh_grid.h"
#include "libvdbappear/lightgrid/sh_light_grid.h"
#include "libvdbappear/math/spherical_harmonics.h"
#include "libvdbappear/util/error.h"

#include <openvdb/io/File.h>

#include <fmt/format.h>

#include <cmath>
#include <map>

namespace vdbappear {

namespace {

constexpr const char* kLmax = "sh_lmax";
constexpr const char* kLevels = "sh_levels";
constexpr const char* kBasis = "sh_basis";
constexpr const char* kBasisText =
    "real SH of Eq. (2.16), dissertation (Wu 2020), Condon-Shortley phase, index l(l+1)+m; coefficients are "
    "integrals of the incident radiance against Y_lm over directions pointing toward the lights";
constexpr const char* kChannels = "rgb";

std::string coefficientName(int n) { return fmt::format("sh_{}", n); }
std::string gradientName(int channel, int n) { return fmt::format("sh_grad_{}_{}", kChannels[channel], n); }

openvdb::Vec3s vec3s(const Vec3& v) { return openvdb::Vec3s(float(v.x()), float(v.y()), float(v.z())); }

// The 4 grids of each coefficient, in file order: sh_n, then the gradients of r, g and b.
std::vector<std::string> gridNames(int lmax) {
  std::vector<std::string> names;
  for (int n = 0; n < shCount(lmax); ++n) {
    names.push_back(coefficientName(n));
    for (int c = 0; c < 3; ++c) names.push_back(gradientName(c, n));
  }
  return names;
}

}  // namespace

void writeShLightGrid(const ShGridLookup& grid, const std::string& path, const std::string& history_line) {
  openvdb::initialize();
  checkWritable(path);
  const ShLattice lattice = grid.lattice();
  auto transform = openvdb::math::Transform::createLinearTransform(lattice.spacing);
  transform->postTranslate(openvdb::Vec3d(lattice.origin.x(), lattice.origin.y(), lattice.origin.z()));
  const int count = shCount(grid.lmax());
  std::vector<openvdb::Vec3SGrid::Ptr> grids;
  for (const std::string& name : gridNames(grid.lmax())) {
    grids.push_back(openvdb::Vec3SGrid::create(openvdb::Vec3s(0)));
    grids.back()->setName(name);
    grids.back()->setTransform(transform);
  }
  std::vector<openvdb::Vec3SGrid::Accessor> accessors;
  for (const auto& g : grids) accessors.push_back(g->getAccessor());
  grid.forEachNode([&](const LatticeIndex& at, const ShLighting& node) {
    const openvdb::Coord ijk{int(at[0]), int(at[1]), int(at[2])};
    for (int n = 0; n < count; ++n) {
      accessors[4 * n].setValue(ijk, vec3s(node.coeffs[n]));
      for (int c = 0; c < 3; ++c) accessors[4 * n + 1 + c].setValue(ijk, vec3s(node.gradients[n].row(c).transpose()));
    }
  });
  openvdb::MetaMap metadata;
  metadata.insertMeta(kLmax, openvdb::Int32Metadata(grid.lmax()));
  metadata.insertMeta(kLevels, openvdb::Int32Metadata(lattice.levels));
  metadata.insertMeta(kBasis, openvdb::StringMetadata(kBasisText));
  metadata.insertMeta(metadata_names::kHistory, openvdb::StringMetadata(history_line));
  metadata.insertMeta(metadata_names::kSchema, openvdb::Int32Metadata(metadata_names::kSchemaVersion));
  writeVdb(path, openvdb::GridCPtrVec(grids.begin(), grids.end()), metadata);
}

std::shared_ptr<const ShGridLookup> readShLightGrid(const std::string& path) {
  openvdb::initialize();
  openvdb::GridPtrVecPtr grids;
  openvdb::MetaMap::Ptr metadata;
  try {
    openvdb::io::File file(path);
    file.open(false);
    grids = file.getGrids();
    metadata = file.getMetadata();
  } catch (const std::exception& e) {
    throw MediumError(fmt::format("{}: not a readable VDB file ({})", path, vdbReadError(e)));
  }
  const auto int_meta = [&](const char* name, std::optional<int> fallback) {
    const auto meta = metadata->getMetadata<openvdb::Int32Metadata>(name);
    if (!meta && (*metadata)[name])
      throw MediumError(fmt::format("{}: '{}' metadata is {}, expected int32", path, name, (*metadata)[name]->typeName()));
    if (!meta && !fallback) throw MediumError(fmt::format("{}: no '{}' metadata: not an SH light grid (vdb_sh_lightgrid writes them)", path, name));
    return meta ? meta->value() : *fallback;
  };
  const int lmax = int_meta(kLmax, std::nullopt), levels = int_meta(kLevels, 0);
  if (lmax < 0 || lmax > 20) throw MediumError(fmt::format("{}: '{}' is {}, expected 0..20", path, kLmax, lmax));
  if (levels < 0 || levels > 12) throw MediumError(fmt::format("{}: '{}' is {}, expected 0..12", path, kLevels, levels));
  std::map<std::string, openvdb::Vec3SGrid::Ptr> by_name;
  for (const auto& g : *grids) {
    auto typed = openvdb::gridPtrCast<openvdb::Vec3SGrid>(g);
    if (!typed) throw MediumError(fmt::format("{}: grid '{}': holds {} values, expected vec3s", path, g->getName(), g->valueType()));
    by_name[g->getName()] = typed;
  }
  const std::vector<std::string> names = gridNames(lmax);
  std::vector<openvdb::Vec3SGrid::Ptr> ordered;
  for (const std::string& name : names) {
    const auto it = by_name.find(name);
    if (it == by_name.end()) throw MediumError(fmt::format("{}: grid '{}' is missing (lmax {})", path, name, lmax));
    ordered.push_back(it->second);
  }
  const openvdb::Vec3SGrid& first = *ordered[0];
  const openvdb::Vec3d origin = first.transform().indexToWorld(openvdb::Vec3d(0)), step = first.voxelSize();
  const auto map = first.transform().baseMap();
  if (!map->isLinear() || !map->getAffineMap()->isScaleTranslate() || std::abs(step.x() - step.y()) > 1e-9 * step.x() ||
      std::abs(step.x() - step.z()) > 1e-9 * step.x())
    throw MediumError(fmt::format("{}: grid '{}': expected a uniform scale-and-translate transform", path, names[0]));
  for (std::size_t g = 1; g < ordered.size(); ++g)
    if (ordered[g]->transform() != first.transform())
      throw MediumError(fmt::format("{}: grid '{}': its transform differs from '{}'", path, names[g], names[0]));
  if (first.empty()) throw MediumError(fmt::format("{}: grid '{}' has no nodes", path, names[0]));
  // The nodes: the active voxels of sh_0; every other grid has the same.
  std::vector<std::pair<LatticeIndex, ShLighting>> nodes;
  for (auto voxel = first.cbeginValueOn(); voxel; ++voxel) {
    if (!voxel.isVoxelValue()) throw MediumError(fmt::format("{}: grid '{}': active tiles are not nodes", path, names[0]));
    const openvdb::Coord c = voxel.getCoord();
    if (c.x() < 0 || c.y() < 0 || c.z() < 0) throw MediumError(fmt::format("{}: grid '{}': a node below (0,0,0)", path, names[0]));
    nodes.push_back({{c.x(), c.y(), c.z()}, ShLighting(shCount(lmax))});
  }
  for (std::size_t g = 0; g < ordered.size(); ++g) {
    if (ordered[g]->activeVoxelCount() != first.activeVoxelCount())
      throw MediumError(fmt::format("{}: grid '{}': its nodes differ from '{}'", path, names[g], names[0]));
    auto accessor = ordered[g]->getConstAccessor();
    const int n = int(g / 4), part = int(g % 4);
    for (auto& [at, node] : nodes) {
      const openvdb::Coord ijk{int(at[0]), int(at[1]), int(at[2])};
      if (!accessor.isValueOn(ijk)) throw MediumError(fmt::format("{}: grid '{}': its nodes differ from '{}'", path, names[g], names[0]));
      const openvdb::Vec3s v = accessor.getValue(ijk);
      if (!std::isfinite(v.x()) || !std::isfinite(v.y()) || !std::isfinite(v.z()))
        throw MediumError(fmt::format("{}: grid '{}': non-finite value at node ({}, {}, {})", path, names[g], at[0], at[1], at[2]));
      const Vec3 value(v.x(), v.y(), v.z());
      if (part == 0) node.coeffs[n] = value;
      else node.gradients[n].row(part - 1) = value.transpose();
    }
  }
  const ShLattice lattice{Vec3(origin.x(), origin.y(), origin.z()), step.x(), levels};
  if (levels == 0) {
    const openvdb::CoordBBox box = first.evalActiveVoxelBoundingBox();
    ShGridLayout layout;
    layout.origin = lattice.origin;
    layout.spacing = lattice.spacing;
    layout.nodes = Eigen::Vector3i(box.max().x() + 1, box.max().y() + 1, box.max().z() + 1);
    if (box.min() != openvdb::Coord(0) || layout.nodes.minCoeff() < 2 || layout.count() != nodes.size())
      throw MediumError(fmt::format("{}: grid '{}': a uniform grid needs every node of a box from (0,0,0), at least 2 per axis", path, names[0]));
    auto grid = std::make_shared<ShLightGrid>(lmax, layout);
    for (auto& [at, node] : nodes) grid->node(int(at[0]), int(at[1]), int(at[2])) = std::move(node);
    return grid;
  }
  try {
    return std::make_shared<AdaptiveShGrid>(AdaptiveShGrid::fromNodes(lmax, lattice, std::move(nodes)));
  } catch (const std::invalid_argument& e) {
    throw MediumError(fmt::format("{}: {}", path, e.what()));
  }
}

}  // namespace vdbappear
