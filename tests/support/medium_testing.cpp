#include "medium_testing.h"

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/lobes/multi_lobe_downsample.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/procedural/weave_medium.h"

namespace vdbappear::test {

void writeRawVdb(const std::string& path, const openvdb::GridPtrVec& grids, const openvdb::MetaMap& metadata) {
  openvdb::initialize();
  openvdb::io::File file(path);
  file.write(grids, metadata);
  file.close();
}

std::string readMediumError(const std::string& path, const GridMapping& mapping) {
  try {
    readMedium(path, mapping);
  } catch (const MediumError& e) {
    return e.what();
  }
  return "";
}

MediumPtr randomMedium(int extent, std::uint64_t seed) {
  RandomMediumParams params;
  params.extent = extent;
  params.seed = seed;
  return makeRandomMedium(params);
}

openvdb::GridPtrVec copyGrids(const Medium& medium) {
  openvdb::GridPtrVec grids;
  for (const auto& grid : medium.grids()) grids.push_back(grid->deepCopyGrid());
  return grids;
}

MediumPtr multiLobeTwill(int resolution, int yarns, int factor, int lobes, int clusters) {
  WeaveParams weave;
  weave.resolution = resolution;
  weave.yarns = yarns;
  MultiLobeOptions options;
  options.factor = factor;
  options.fit.forced_lobes = lobes;
  options.clustering.clusters = clusters;
  return downsampleMultiLobe(*makeWeave(weave), options).medium;
}

MediumPtr spreadCopies(const Medium& medium, const std::vector<openvdb::Coord>& offsets) {
  auto copy = std::make_shared<Medium>(medium);
  const auto spread = [&](auto& grid) {
    if (!grid) return;
    using GridT = typename std::decay_t<decltype(grid)>::element_type;
    auto out = GridT::create(grid->background());
    out->setName(grid->getName());
    out->setTransform(grid->transform().copy());
    for (const openvdb::Coord& offset : offsets)
      for (auto v = grid->cbeginValueOn(); v; ++v) out->tree().setValueOn(v.getCoord() + offset, *v);
    grid = out;
  };
  spread(copy->density);
  spread(copy->albedo);
  spread(copy->sggx_diag);
  spread(copy->sggx_offdiag);
  return copy;
}

}  // namespace vdbappear::test
