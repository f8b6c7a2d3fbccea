#include "libvdbappear/procedural/cloud_medium.h"

#include "libvdbappear/io/medium.h"
#include "libvdbappear/procedural/gradient_noise.h"
#include "libvdbappear/math/smoothstep.h"
#include "libvdbappear/procedural/voxel_filler.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace vdbappear {

namespace {

class CloudField {
 public:
  explicit CloudField(const CloudParams& p) : p_(p), radius_(0.5 * p.size) {}

  // Noise plus a centre bump (1 at the centre, 0 at the sphere); -inf outside the sphere.
  double operator()(const Vec3& q) const {
    const double r2 = q.squaredNorm() / (radius_ * radius_);
    if (r2 > 1) return -HUGE_VAL;
    return fractalNoise(q / p_.feature_size, p_.seed, p_.octaves) + 0.6 * (1 - r2);
  }

  // The field value above which a voxel holds smoke: the (1 - coverage) quantile of the field over
  // a 48^3 lattice of points in the sphere.
  double threshold() const {
    constexpr int kLattice = 48;
    std::vector<double> values;
    for (int i = 0; i < kLattice; ++i)
      for (int j = 0; j < kLattice; ++j)
        for (int k = 0; k < kLattice; ++k) {
          const Vec3 q = (Vec3(i, j, k) + Vec3::Constant(0.5)) * (p_.size / kLattice) - Vec3::Constant(radius_);
          if (q.squaredNorm() <= radius_ * radius_) values.push_back((*this)(q));
        }
    const auto nth = values.begin() + std::ptrdiff_t(std::clamp(1 - p_.coverage, 0.0, 1.0) * double(values.size() - 1));
    std::nth_element(values.begin(), nth, values.end());
    return *nth;
  }

 private:
  CloudParams p_;
  double radius_;
};

}  // namespace

MediumPtr makeCloud(const CloudParams& p) {
  const CloudField field(p);
  const double threshold = field.threshold();
  const int res = p.resolution;
  const double voxel_size = p.size / res;
  ProceduralLayout layout = centredLayout(openvdb::Coord(res), voxel_size);
  layout.sggx = false;
  layout.hg_g = p.g_edge.has_value();
  MediumPtr medium = fillMedium(
      layout, [](const openvdb::CoordBBox&) { return true; },
      [&](const openvdb::Coord&, const Vec3& centre) -> std::optional<VoxelSample> {
        const double excess = field(centre) - threshold;
        if (!(excess > 0)) return std::nullopt;
        VoxelSample voxel;
        voxel.density = float(p.density * smoothstep(excess / p.edge_softness));
        voxel.albedo = p.albedo;
        if (p.g_edge) voxel.hg_g = float(*p.g_edge + (p.g - *p.g_edge) * voxel.density / p.density);
        return voxel;
      });
  if (!p.g_edge) medium->metadata.insertMeta(metadata_names::kHgG, openvdb::FloatMetadata(float(p.g)));
  return medium;
}

}  // namespace vdbappear
