#include "libvdbappear/downsample/emission_downsample.h"

#include "libvdbappear/io/emission_convention.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/math/block_index.h"
#include "libvdbappear/math/rgb.h"
#include "libvdbappear/medium/emission_light.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <optional>
#include <vector>

namespace vdbappear {

namespace {

using openvdb::Coord;

// The coarse voxels that hold an active voxel of `emission`, sorted.
std::vector<Coord> coarseVoxels(const openvdb::Vec3SGrid& emission, int factor) {
  openvdb::MaskGrid coarse;
  auto mask = coarse.getAccessor();
  for (auto v = emission.cbeginValueOn(); v; ++v) {
    for (auto c = blocksOf(v.getBoundingBox(), Coord(factor)).begin(); c; ++c) mask.setValueOn(*c);
  }
  std::vector<Coord> voxels;
  for (auto c = coarse.cbeginValueOn(); c; ++c) voxels.push_back(c.getCoord());  // leaves only: no tiles were made
  return voxels;
}

// Sums over the children of one coarse voxel.
struct ChildSums {
  Rgb emission = Rgb::Zero();         // sum E (cycles)
  Rgb absorbed = Rgb::Zero();         // sum rho (1 - a) Le (pbrt)
  Rgb absorption = Rgb::Zero();       // sum rho (1 - a), over every child with density
  Rgb dense_emission = Rgb::Zero();   // sum rho Le
  double rho = 0;                     // sum rho
};

struct FineAccessors {
  openvdb::Vec3SGrid::ConstAccessor emission;
  openvdb::FloatGrid::ConstAccessor density;
  std::optional<openvdb::Vec3SGrid::ConstAccessor> albedo;
};

ChildSums sumChildren(FineAccessors& fine, const Coord& coarse, int factor, EmissionConvention convention) {
  ChildSums sums;
  const Coord first(coarse.x() * factor, coarse.y() * factor, coarse.z() * factor);
  for (auto v = openvdb::CoordBBox::createCube(first, factor).begin(); v; ++v) {
    openvdb::Vec3s e(0.0f);
    const bool emits = fine.emission.probeValue(*v, e);  // inactive voxels emit nothing
    if (convention == EmissionConvention::kCycles) {
      if (emits) sums.emission += toVec3(e).array();
      continue;
    }
    float rho = 0;
    if (!fine.density.probeValue(*v, rho) || !(rho > 0)) continue;  // inactive density: empty space
    const Rgb a = fine.albedo ? Rgb(toVec3(fine.albedo->getValue(*v)).array()) : Rgb(Rgb::Ones());
    const Rgb Le = emits ? Rgb(toVec3(e).array()) : Rgb(Rgb::Zero());
    sums.absorbed += rho * (1 - a) * Le;
    sums.absorption += rho * (1 - a);
    sums.dense_emission += rho * Le;
    sums.rho += rho;
  }
  return sums;
}

openvdb::Vec3s coarseValue(const ChildSums& sums, int factor, EmissionConvention convention) {
  if (convention == EmissionConvention::kCycles) return toVec3s(Vec3((sums.emission / double(factor * factor * factor)).matrix()));
  Rgb Le = Rgb::Zero();
  for (int c = 0; c < 3; ++c) {
    if (sums.absorption[c] > 0) Le[c] = sums.absorbed[c] / sums.absorption[c];
    else if (sums.rho > 0) Le[c] = sums.dense_emission[c] / sums.rho;
  }
  return toVec3s(Vec3(Le.matrix()));
}

}  // namespace

openvdb::Vec3SGrid::Ptr downsampleEmission(const Medium& fine, int factor, const openvdb::math::Transform::Ptr& coarse) {
  const auto emission = voxelEmission(fine);  // emission plus blackbody light, per fine voxel
  if (!emission) return nullptr;
  const EmissionConvention convention = emissionConvention(fine);
  const std::vector<Coord> voxels = coarseVoxels(*emission, factor);
  std::vector<openvdb::Vec3s> values(voxels.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, voxels.size(), 64), [&](const auto& range) {
    FineAccessors accessors{emission->getConstAccessor(), fine.density->getConstAccessor(), std::nullopt};
    if (fine.albedo) accessors.albedo.emplace(fine.albedo->getConstAccessor());
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      values[i] = coarseValue(sumChildren(accessors, voxels[i], factor, convention), factor, convention);
  });
  auto out = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  out->setName(grid_names::kEmission);
  out->setTransform(coarse);
  auto accessor = out->getAccessor();
  for (std::size_t i = 0; i < voxels.size(); ++i) accessor.setValueOn(voxels[i], values[i]);
  return out;
}

}  // namespace vdbappear
