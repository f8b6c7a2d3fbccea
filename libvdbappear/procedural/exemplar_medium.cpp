#include "libvdbappear/procedural/exemplar_medium.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/procedural/voxel_filler.h"
#include "libvdbappear/procedural/weave_medium.h"
#include "libvdbappear/util/hash_random.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace vdbappear {

namespace {

struct PatternVariant {
  const char* name;
  WeavePattern (*make)();
};
const PatternVariant kPatterns[] = {
    {"plain", [] { return WeavePattern::plain(); }},
    {"twill 4", [] { return WeavePattern::twill(4); }},
    {"twill 4 mirrored", [] { return WeavePattern::twill(4).mirrored(); }},
    {"twill 4 weft-faced", [] { return WeavePattern::twill(4).transposed(); }},
};
struct Palette {
  const char* name;
  Vec3 warp, weft;
};
const Palette kPalettes[] = {
    {"pink/yellow", Vec3(0.85, 0.30, 0.45), Vec3(0.85, 0.75, 0.25)},
    {"navy/cream", Vec3(0.10, 0.15, 0.45), Vec3(0.90, 0.85, 0.70)},
    {"green/grey", Vec3(0.20, 0.55, 0.25), Vec3(0.55, 0.55, 0.55)},
};
constexpr int kPatternCount = int(std::size(kPatterns));
constexpr int kPaletteCount = int(std::size(kPalettes));

WeaveGeometry exemplarGeometry(const ExemplarParams& p, int e) {
  WeaveParams w;
  w.seed = p.seed + std::uint64_t(e);
  w.yarns = p.block_yarns;
  w.fiber_density = p.fiber_density;
  w.roughness = p.roughness;
  w.warp_albedo = kPalettes[e % kPaletteCount].warp;
  w.weft_albedo = kPalettes[e % kPaletteCount].weft;
  return WeaveGeometry(w, kPatterns[e % kPatternCount].make());
}

openvdb::Int32Grid::Ptr layoutGrid(const ExemplarParams& p, const openvdb::math::Transform::Ptr& transform) {
  auto grid = openvdb::Int32Grid::create(0);
  grid->setName(grid_names::kExemplarLayout);
  grid->setTransform(transform);
  auto accessor = grid->getAccessor();
  for (int i = 0; i < p.layout_width; ++i)
    for (int j = 0; j < p.layout_height; ++j)
      accessor.setValueOn(openvdb::Coord(i, j, 0), int(hashKeys(p.seed, {41, i, j}) % std::uint64_t(p.count)));
  return grid;
}

}  // namespace

MediumPtr makeExemplars(const ExemplarParams& p) {
  if (p.block_yarns % 4 != 0)
    throw std::invalid_argument(fmt::format("exemplar blocks of {} yarns: need a multiple of 4 (whole repeats of every pattern)", p.block_yarns));
  std::vector<WeaveGeometry> exemplars;
  for (int e = 0; e < p.count; ++e) exemplars.push_back(exemplarGeometry(p, e));
  const double voxel_size = double(p.block_yarns) / p.resolution;
  const int depth = voxelsToCover(1, voxel_size);  // one fabric layer
  const ProceduralLayout layout = cornerLayout(openvdb::Coord(p.count * p.resolution, p.resolution, depth), voxel_size);
  MediumPtr medium = fillMedium(
      layout, [](const openvdb::CoordBBox&) { return true; },
      [&](const openvdb::Coord& ijk, const Vec3& centre) {
        const int e = ijk.x() / p.resolution;
        return exemplars[std::size_t(e)].sampleVoxel(centre - Vec3(e * p.block_yarns, 0, 0), voxel_size);
      });
  medium->other_grids.push_back(layoutGrid(p, medium->density->transformPtr()));
  medium->metadata.insertMeta(metadata_names::kExemplarCount, openvdb::Int32Metadata(p.count));
  medium->metadata.insertMeta(metadata_names::kExemplarBlock,
                              openvdb::Vec3IMetadata(openvdb::Vec3i(p.resolution, p.resolution, depth)));
  return medium;
}

}  // namespace vdbappear
