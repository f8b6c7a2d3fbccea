#include "libvdbappear/procedural/hairy_ball_medium.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/frame.h"
#include "libvdbappear/procedural/fiber_field.h"
#include "libvdbappear/procedural/fiber_segments.h"
#include "libvdbappear/math/smoothstep.h"
#include "libvdbappear/procedural/voxel_filler.h"
#include "libvdbappear/util/hash_random.h"

#include <cmath>

namespace vdbappear {

namespace {

// Root k of n on the Fibonacci lattice: near-uniform points on the unit sphere.
Vec3 fibonacciPoint(int k, int n) {
  const double golden_angle = kPi * (3 - std::sqrt(5.0));
  const double z = 1 - (2 * k + 1) / double(n);
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  return Vec3(r * std::cos(golden_angle * k), r * std::sin(golden_angle * k), z);
}

class HairyBall : public FiberField {
 public:
  explicit HairyBall(const HairyBallParams& p) : p_(p), strands_(makeStrands(p), 4 * p.strand_radius) {}

  std::optional<FiberPoint> fiberAt(const Vec3& q) const override {
    if (q.squaredNorm() < p_.radius * p_.radius)
      return FiberPoint{Vec3::UnitZ(), colour(q.normalized()), p_.core_density, 1.0};  // roughness 1: S = I
    const int id = strands_.find(q);
    if (id < 0) return std::nullopt;
    const FiberSegment& s = strands_.segment(id);
    return FiberPoint{(s.b - s.a).normalized(), colour(s.a.normalized()), p_.strand_density, roughness(s.a)};
  }

  double extent() const { return p_.radius + p_.hair_length + p_.strand_radius; }

 private:
  // Strands start just inside the core (which takes precedence there), so none floats free.
  static std::vector<FiberSegment> makeStrands(const HairyBallParams& p) {
    const int n = hairyBallStrandCount(p);
    const double tan_max = std::tan(p.tilt_degrees * kPi / 180);
    std::vector<FiberSegment> strands;
    strands.reserve(std::size_t(n));
    for (int k = 0; k < n; ++k) {
      const Vec3 normal = fibonacciPoint(k, n);
      const Frame frame = Frame::fromNormal(normal);
      const double tilt = tan_max * hashUniform(p.seed, {21, k}), phi = 2 * kPi * hashUniform(p.seed, {22, k});
      const Vec3 dir = frame.toWorld(Vec3(tilt * std::cos(phi), tilt * std::sin(phi), 1)).normalized();
      const Vec3 root = normal * (p.radius - p.strand_radius);
      strands.push_back({root, root + dir * p.hair_length, p.strand_radius, k});
    }
    return strands;
  }

  Vec3 colour(const Vec3& direction) const {
    if (p_.two_materials) return direction.x() >= 0 ? p_.material_a : p_.material_b;
    return p_.colour_a + (p_.colour_b - p_.colour_a) * smoothstep(0.5 * (1 + direction.z()));
  }
  double roughness(const Vec3& root) const {
    if (p_.two_materials) return root.x() >= 0 ? 0.1 : 0.4;
    return p_.roughness;
  }

  HairyBallParams p_;
  SegmentIndex strands_;
};

}  // namespace

int hairyBallStrandCount(const HairyBallParams& p) {
  return std::max(1, int(std::lround(4 * kPi * p.radius * p.radius / (p.strand_spacing * p.strand_spacing))));
}

MediumPtr makeHairyBall(const HairyBallParams& params) {
  const HairyBall ball(params);
  const double voxel_size = 2 * ball.extent() / params.resolution;
  // Non-negative index coordinates keep the tree under one root child (smaller files).
  ProceduralLayout layout = centredLayout(openvdb::Coord(params.resolution), voxel_size);
  layout.memory = params.memory;
  return fillMedium(
      layout, [](const openvdb::CoordBBox&) { return true; },
      [&](const openvdb::Coord&, const Vec3& centre) { return sampleFiberVoxel(ball, centre, voxel_size); });
}

}  // namespace vdbappear
