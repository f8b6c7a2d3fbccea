#include "libvdbappear/procedural/random_medium.h"

#include "libvdbappear/math/random_spd.h"
#include "libvdbappear/procedural/voxel_filler.h"
#include "libvdbappear/util/hash_random.h"

namespace vdbappear {

MediumPtr makeRandomMedium(const RandomMediumParams& p) {
  ProceduralLayout layout;
  const int lo = -p.extent / 2;
  layout.bounds = openvdb::CoordBBox(openvdb::Coord(lo), openvdb::Coord(lo + p.extent - 1));
  layout.voxel_size = p.voxel_size;
  layout.albedo = p.albedo;
  layout.sggx = p.sggx;
  layout.hg_g = p.hg_g;

  enum Stream : std::int64_t { kBlock, kActive, kZero, kDensity, kAlbedo, kSggx, kHg };
  auto block_test = [&p](const openvdb::CoordBBox& block) {
    const openvdb::Coord b = block.min() >> 3;
    return hashUniform(p.seed, {kBlock, b.x(), b.y(), b.z()}) < p.block_fill;
  };
  auto sample = [&p](const openvdb::Coord& c, const Vec3&) -> std::optional<VoxelSample> {
    auto u = [&](std::int64_t stream, std::int64_t k = 0) { return hashUniform(p.seed, {stream, k, c.x(), c.y(), c.z()}); };
    if (u(kActive) >= p.voxel_fill) return std::nullopt;
    VoxelSample v;
    v.density = u(kZero) < p.zero_density ? 0.0f : float(p.max_density * (1 - u(kDensity)));
    v.albedo = Vec3(u(kAlbedo, 0), u(kAlbedo, 1), u(kAlbedo, 2));
    v.S = randomSpdMatrix(u(kSggx, 0), u(kSggx, 1), u(kSggx, 2), Vec3(u(kSggx, 3), u(kSggx, 4), u(kSggx, 5)),
                          p.min_eigenvalue);
    v.hg_g = float(1.8 * u(kHg) - 0.9);
    return v;
  };
  return fillMedium(layout, block_test, sample);
}

}  // namespace vdbappear
