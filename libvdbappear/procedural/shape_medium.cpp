#include "libvdbappear/procedural/shape_medium.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/sggx.h"
#include "libvdbappear/procedural/voxel_filler.h"
#include "libvdbappear/util/hash_random.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace vdbappear {

namespace {

const std::vector<std::pair<std::string, PhaseChoice>>& phaseTable() {
  static const std::vector<std::pair<std::string, PhaseChoice>> table{{"isotropic", PhaseChoice::Isotropic},
                                                                      {"hg", PhaseChoice::Hg},
                                                                      {"sggx-fiber", PhaseChoice::SggxFiber},
                                                                      {"sggx-surface", PhaseChoice::SggxSurface}};
  return table;
}

// A smooth field in [-1,1]: a product of one full sine period per axis of the cube of edge `size`,
// with random phases. Its mean over the cube (and over any whole-period box of voxels) is 0.
class SmoothVariation {
 public:
  SmoothVariation(std::uint64_t seed, double size) : size_(size) {
    for (int k = 0; k < 3; ++k) phase_[k] = 2 * kPi * hashUniform(seed, {31, k});
  }
  double operator()(const Vec3& p) const {
    double v = 1;
    for (int k = 0; k < 3; ++k) v *= std::sin(2 * kPi * p[k] / size_ + phase_[k]);
    return v;
  }

 private:
  double size_;
  double phase_[3];
};

}  // namespace

const std::vector<std::string>& phaseChoiceNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& [name, choice] : phaseTable()) n.push_back(name);
    return n;
  }();
  return names;
}

PhaseChoice phaseChoiceByName(const std::string& name) {
  for (const auto& [n, choice] : phaseTable())
    if (n == name) return choice;
  throw std::invalid_argument(fmt::format("unknown phase '{}' (isotropic, hg, sggx-fiber or sggx-surface)", name));
}

MediumPtr makeShape(const ShapeParams& p) {
  const int res = p.resolution;
  const double voxel_size = p.size / res;
  const int depth = p.shape == Shape::Slab ? std::max(1, int(std::lround(p.thickness / voxel_size))) : res;
  ProceduralLayout layout = centredLayout(openvdb::Coord(res, res, depth), voxel_size);
  layout.sggx = p.phase == PhaseChoice::SggxFiber || p.phase == PhaseChoice::SggxSurface;
  Mat3 S = Mat3::Identity();
  if (p.phase == PhaseChoice::SggxFiber) S = Sggx::fiberMatrix(p.axis, p.roughness);
  if (p.phase == PhaseChoice::SggxSurface) S = Sggx::surfaceMatrix(p.axis, p.roughness);
  const SmoothVariation variation(p.seed, p.size);
  const double radius2 = 0.25 * p.size * p.size;
  MediumPtr medium = fillMedium(
      layout, [](const openvdb::CoordBBox&) { return true; },
      [&](const openvdb::Coord&, const Vec3& centre) -> std::optional<VoxelSample> {
        if (p.shape == Shape::Sphere && centre.squaredNorm() > radius2) return std::nullopt;
        VoxelSample voxel;
        voxel.density = float(p.density * (1 + p.variation * variation(centre)));
        voxel.albedo = p.albedo;
        voxel.S = S;
        return voxel;
      });
  if (p.phase == PhaseChoice::Hg) medium->metadata.insertMeta(metadata_names::kHgG, openvdb::FloatMetadata(float(p.g)));
  return medium;
}

}  // namespace vdbappear
