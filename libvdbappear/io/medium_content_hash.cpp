#include "libvdbappear/io/medium_content_hash.h"

#include "libvdbappear/io/medium.h"

#include <fmt/format.h>
#include <xxhash.h>

namespace vdbappear {

namespace {

template <typename GridT>
void hashValues(const openvdb::GridBase& base, XXH3_state_t* state) {
  const auto& grid = static_cast<const GridT&>(base);
  for (auto v = grid.cbeginValueOn(); v; ++v) {
    const openvdb::Coord ijk = v.getCoord();
    const typename GridT::ValueType value = *v;
    const openvdb::Index64 count = v.getVoxelCount();
    XXH3_128bits_update(state, &ijk, sizeof(ijk));
    XXH3_128bits_update(state, &value, sizeof(value));
    XXH3_128bits_update(state, &count, sizeof(count));
  }
}

}  // namespace

std::string mediumContentHash(const Medium& medium) {
  XXH3_state_t* state = XXH3_createState();
  XXH3_128bits_reset(state);
  for (const auto& grid : medium.grids()) {
    const std::string name = grid->getName() + ":" + grid->valueType();
    XXH3_128bits_update(state, name.data(), name.size());
    const openvdb::Mat4d map = grid->transform().baseMap()->getAffineMap()->getMat4();
    XXH3_128bits_update(state, map.asPointer(), 16 * sizeof(double));
    if (grid->isType<openvdb::FloatGrid>()) hashValues<openvdb::FloatGrid>(*grid, state);
    else if (grid->isType<openvdb::Vec3SGrid>()) hashValues<openvdb::Vec3SGrid>(*grid, state);
    else if (grid->isType<openvdb::Int32Grid>()) hashValues<openvdb::Int32Grid>(*grid, state);
  }
  const XXH128_hash_t h = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  return fmt::format("{:016x}{:016x}", h.high64, h.low64);
}

}  // namespace vdbappear
