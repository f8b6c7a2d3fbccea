#include "libvdbappear/io/sh_light_grid_file.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/vdb_writer.h"
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
constexpr const char* kBasis = "sh_basis";
constexpr const char* kBasisText =
    "real SH of Eq. (2.16), dissertation (Wu 2020), Condon-Shortley phase, index l(l+1)+m; coefficients are "
    "integrals of the incident radiance against Y_lm over directions pointing toward the lights";
constexpr const char* kChannels = "rgb";

std::string coefficientName(int n) { return fmt::format("sh_{}", n); }
std::string gradientName(int channel, int n) { return fmt::format("sh_grad_{}_{}", kChannels[channel], n); }

openvdb::math::Transform::Ptr nodeTransform(const ShGridLayout& layout) {
  auto transform = openvdb::math::Transform::createLinearTransform(layout.spacing);
  transform->postTranslate(openvdb::Vec3d(layout.origin.x(), layout.origin.y(), layout.origin.z()));
  return transform;
}

template <typename Value>
openvdb::Vec3SGrid::Ptr nodeGrid(const ShLightGrid& grid, const std::string& name, const Value& value) {
  auto out = openvdb::Vec3SGrid::create(openvdb::Vec3s(0));
  out->setName(name);
  out->setTransform(nodeTransform(grid.layout()));
  out->setGridClass(openvdb::GRID_UNKNOWN);
  auto accessor = out->getAccessor();
  const Eigen::Vector3i n = grid.layout().nodes;
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const Vec3 v = value(grid.node(i, j, k));
        accessor.setValue(openvdb::Coord(i, j, k), openvdb::Vec3s(float(v.x()), float(v.y()), float(v.z())));
      }
  return out;
}

}  // namespace

void writeShLightGrid(const ShLightGrid& grid, const std::string& path, const std::string& history_line) {
  openvdb::initialize();
  checkWritable(path);
  openvdb::GridCPtrVec grids;
  for (int n = 0; n < shCount(grid.lmax()); ++n) {
    grids.push_back(nodeGrid(grid, coefficientName(n), [n](const ShLighting& s) { return s.coeffs[n]; }));
    for (int c = 0; c < 3; ++c)
      grids.push_back(nodeGrid(grid, gradientName(c, n), [n, c](const ShLighting& s) { return Vec3(s.gradients[n].row(c)); }));
  }
  openvdb::MetaMap metadata;
  metadata.insertMeta(kLmax, openvdb::Int32Metadata(grid.lmax()));
  metadata.insertMeta(kBasis, openvdb::StringMetadata(kBasisText));
  metadata.insertMeta(metadata_names::kHistory, openvdb::StringMetadata(history_line));
  metadata.insertMeta(metadata_names::kSchema, openvdb::Int32Metadata(metadata_names::kSchemaVersion));
  writeVdb(path, grids, metadata);
}

ShLightGrid readShLightGrid(const std::string& path) {
  openvdb::initialize();
  openvdb::GridPtrVecPtr grids;
  openvdb::MetaMap::Ptr metadata;
  try {
    openvdb::io::File file(path);
    file.open(false);
    grids = file.getGrids();
    metadata = file.getMetadata();
  } catch (const std::exception& e) {
    throw MediumError(fmt::format("{}: not a readable VDB file ({})", path, e.what()));
  }
  const auto lmax_meta = metadata->getMetadata<openvdb::Int32Metadata>(kLmax);
  if (!lmax_meta) throw MediumError(fmt::format("{}: no '{}' metadata: not an SH light grid (vdb_sh_lightgrid writes them)", path, kLmax));
  const int lmax = lmax_meta->value();
  if (lmax < 0 || lmax > 20) throw MediumError(fmt::format("{}: '{}' is {}, expected 0..20", path, kLmax, lmax));
  std::map<std::string, openvdb::Vec3SGrid::Ptr> by_name;
  for (const auto& g : *grids) {
    auto typed = openvdb::gridPtrCast<openvdb::Vec3SGrid>(g);
    if (!typed) throw MediumError(fmt::format("{}: grid '{}': holds {} values, expected vec3s", path, g->getName(), g->valueType()));
    by_name[g->getName()] = typed;
  }
  const auto find = [&](const std::string& name) {
    const auto it = by_name.find(name);
    if (it == by_name.end()) throw MediumError(fmt::format("{}: grid '{}' is missing (lmax {})", path, name, lmax));
    return it->second;
  };
  const auto first = find(coefficientName(0));
  const openvdb::CoordBBox box = first->evalActiveVoxelBoundingBox();
  if (first->empty() || box.min() != openvdb::Coord(0))
    throw MediumError(fmt::format("{}: grid '{}': expected nodes from (0,0,0)", path, coefficientName(0)));
  const auto& map = *first->transform().baseMap();
  const openvdb::Vec3d origin = first->transform().indexToWorld(openvdb::Vec3d(0)), step = first->voxelSize();
  if (!map.isLinear() || std::abs(step.x() - step.y()) > 1e-9 * step.x() || std::abs(step.x() - step.z()) > 1e-9 * step.x())
    throw MediumError(fmt::format("{}: grid '{}': expected a uniform scale-and-translate transform", path, coefficientName(0)));
  ShGridLayout layout;
  layout.origin = Vec3(origin.x(), origin.y(), origin.z());
  layout.spacing = step.x();
  layout.nodes = Eigen::Vector3i(box.max().x() + 1, box.max().y() + 1, box.max().z() + 1);
  if (layout.nodes.minCoeff() < 2) throw MediumError(fmt::format("{}: grid '{}': needs at least 2 nodes per axis", path, coefficientName(0)));
  ShLightGrid grid(lmax, layout);
  const auto read = [&](const std::string& name, const auto& store) {
    const auto g = find(name);
    if (g->activeVoxelCount() != layout.count() || g->evalActiveVoxelBoundingBox() != box)
      throw MediumError(fmt::format("{}: grid '{}': its nodes differ from '{}'", path, name, coefficientName(0)));
    auto accessor = g->getConstAccessor();
    for (int k = 0; k < layout.nodes.z(); ++k)
      for (int j = 0; j < layout.nodes.y(); ++j)
        for (int i = 0; i < layout.nodes.x(); ++i) {
          const openvdb::Vec3s v = accessor.getValue(openvdb::Coord(i, j, k));
          if (!std::isfinite(v.x()) || !std::isfinite(v.y()) || !std::isfinite(v.z()))
            throw MediumError(fmt::format("{}: grid '{}': non-finite value at node ({}, {}, {})", path, name, i, j, k));
          store(grid.node(i, j, k), Vec3(v.x(), v.y(), v.z()));
        }
  };
  for (int n = 0; n < shCount(lmax); ++n) {
    read(coefficientName(n), [n](ShLighting& s, const Vec3& v) { s.coeffs[n] = v; });
    for (int c = 0; c < 3; ++c) read(gradientName(c, n), [n, c](ShLighting& s, const Vec3& v) { s.gradients[n].row(c) = v.transpose(); });
  }
  return grid;
}

}  // namespace vdbappear
