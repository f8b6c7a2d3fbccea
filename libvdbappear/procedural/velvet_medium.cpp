#include "libvdbappear/procedural/velvet_medium.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/procedural/fiber_field.h"
#include "libvdbappear/procedural/fiber_segments.h"
#include "libvdbappear/procedural/voxel_filler.h"
#include "libvdbappear/procedural/weave_medium.h"
#include "libvdbappear/util/hash_random.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

namespace {

constexpr double kBaseMidPlane = 0.5;

WeaveParams baseWeave(const VelvetParams& p) {
  WeaveParams w;
  w.seed = p.seed;
  w.pattern = "plain";
  w.yarns = p.yarns;
  w.layers = 1;
  w.fiber_density = p.base_density;
  w.roughness = p.roughness;
  w.warp_albedo = w.weft_albedo = p.base_albedo;
  return w;
}

// Pile fibers rooted on a jittered grid of the base's mid-plane (a fiber never leaves its cell at
// the root), each leaning toward +x by the common angle plus a random tilt in a cone. The grid
// spacing is adjusted so that whole cells fill the patch, and the roots repeat with the patch's
// period beyond its edges, so fibers leaning in from outside fill the pile up to every edge and
// the patch tiles like the base weave.
std::vector<FiberSegment> pileFibers(const VelvetParams& p) {
  const int cells = std::max(1, int(std::lround(p.yarns / p.pile_spacing)));
  const double spacing = double(p.yarns) / cells;
  const double jitter = std::max(0.0, 0.5 * spacing - p.pile_radius);
  const double lean = std::tan(p.lean_degrees * kPi / 180);
  const double cos_max = std::cos(p.tilt_degrees * kPi / 180);
  const double reach = p.pile_height * std::tan((p.lean_degrees + p.tilt_degrees) * kPi / 180);
  const int margin = int(std::ceil(reach / spacing)) + 1;
  std::vector<FiberSegment> fibers;
  fibers.reserve(std::size_t(cells + 2 * margin) * std::size_t(cells + 2 * margin));
  auto wrap = [cells](int k) { return ((k % cells) + cells) % cells; };
  for (int i = -margin; i < cells + margin; ++i)
    for (int j = -margin; j < cells + margin; ++j) {
      const int wi = wrap(i), wj = wrap(j);
      auto u = [&](int k) { return hashUniform(p.seed, {11, wi, wj, k}); };
      const Vec3 root((i + 0.5) * spacing + jitter * (2 * u(0) - 1),
                      (j + 0.5) * spacing + jitter * (2 * u(1) - 1), kBaseMidPlane);
      // Uniform direction in the cone of half-angle tilt about +z, then the common lean.
      const double cos_t = 1 - u(2) * (1 - cos_max), sin_t = std::sqrt(1 - cos_t * cos_t), phi = 2 * kPi * u(3);
      Vec3 dir(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
      dir = (dir / dir.z() + Vec3(lean, 0, 0)).normalized();
      fibers.push_back({root, root + dir * (p.pile_height / dir.z()), p.pile_radius, wi * cells + wj});
    }
  return fibers;
}

class Velvet : public FiberField {
 public:
  explicit Velvet(const VelvetParams& p) : p_(p), base_(baseWeave(p)), pile_(pileFibers(p), 4 * p.pile_radius) {}

  std::optional<FiberPoint> fiberAt(const Vec3& q) const override {
    if (q.z() < 1) {
      if (auto base = base_.fiberAt(q)) return base;  // the base weave holds the pile's roots
    }
    const int id = pile_.find(q);
    if (id < 0) return std::nullopt;
    const FiberSegment& s = pile_.segment(id);
    const double jitter = 1 + 0.1 * (2 * hashUniform(p_.seed, {12, s.material}) - 1);
    return FiberPoint{(s.b - s.a).normalized(), (p_.pile_albedo * jitter).cwiseMin(1.0), p_.pile_density,
                      p_.roughness};
  }

  double top() const { return kBaseMidPlane + p_.pile_height + p_.pile_radius; }

 private:
  VelvetParams p_;
  WeaveGeometry base_;
  SegmentIndex pile_;
};

}  // namespace

MediumPtr makeVelvet(const VelvetParams& params) {
  const Velvet velvet(params);
  const double extent = std::max(double(params.yarns), velvet.top());
  const double voxel_size = extent / params.resolution;
  const int across = voxelsToCover(params.yarns, voxel_size);
  ProceduralLayout layout =
      cornerLayout(openvdb::Coord(across, across, voxelsToCover(velvet.top(), voxel_size)), voxel_size);
  layout.memory = params.memory;
  return fillMedium(
      layout, [](const openvdb::CoordBBox&) { return true; },
      [&](const openvdb::Coord&, const Vec3& centre) { return sampleFiberVoxel(velvet, centre, voxel_size); });
}

}  // namespace vdbappear
