#include "medium_testing.h"

#include "libvdbappear/procedural/random_medium.h"

namespace vdbappear::test {

void writeRawVdb(const std::string& path, const openvdb::GridPtrVec& grids, const openvdb::MetaMap& metadata) {
  openvdb::initialize();
  openvdb::io::File file(path);
  file.write(grids, metadata);
  file.close();
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

}  // namespace vdbappear::test
