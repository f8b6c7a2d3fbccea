#include "libvdbappear/procedural/weave_medium.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/sggx.h"
#include "libvdbappear/procedural/voxel_filler.h"
#include "libvdbappear/util/hash_random.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace vdbappear {

namespace {

// Yarn geometry in world units (yarn spacing 1).
constexpr double kHalfWidth = 0.42;    // cross-section semi-axis across the fabric
constexpr double kHalfHeight = 0.14;   // cross-section semi-axis through the fabric
constexpr double kAmplitude = 0.16;    // crimp: over/under excursion of the centreline (> kHalfHeight)
constexpr double kTwistPitch = 2.0;    // world units per full turn of the fibers
constexpr double kFiberSpacing = 0.05; // fiber centres on a jittered grid in the twisted cross-section
constexpr double kFiberRadius = 0.019;

// A point inside a yarn: where the yarn runs, and the point's offset in its cross-section.
struct YarnPoint {
  bool warp;
  int yarn;         // index across the fabric
  Vec3 axis;        // unit tangent of the yarn centreline
  Vec3 across;      // unit vector across the fabric, in the cross-section
  Vec3 through;     // unit vector completing the cross-section frame
  double u, v;      // offsets along `across` and `through`
  double s;         // position along the yarn
};

// Centreline height of yarn `index` at position s along it; warp and weft have opposite phase, so
// they alternate over and under at every crossing.
double crimpHeight(bool warp, int index, double s) {
  const double h = kAmplitude * std::sin(kPi * s + kPi * index);
  return warp ? h : -h;
}
double crimpSlope(bool warp, int index, double s) {
  const double d = kAmplitude * kPi * std::cos(kPi * s + kPi * index);
  return warp ? d : -d;
}

std::optional<YarnPoint> locateYarn(const Vec3& p, bool warp) {
  const double along = warp ? p.x() : p.y(), across = warp ? p.y() : p.x();
  const int index = int(std::floor(across));
  const double layer_centre = std::floor(p.z()) + 0.5;
  const double u = across - (index + 0.5);
  const double dz = p.z() - layer_centre - crimpHeight(warp, index, along);
  if ((u / kHalfWidth) * (u / kHalfWidth) + (dz / kHalfHeight) * (dz / kHalfHeight) > 1) return std::nullopt;
  const double slope = crimpSlope(warp, index, along);
  const Vec3 axis = (warp ? Vec3(1, 0, slope) : Vec3(0, 1, slope)).normalized();
  const Vec3 across_dir = warp ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  const Vec3 through = axis.cross(across_dir).normalized() * (warp ? 1.0 : -1.0);  // about +z
  return YarnPoint{warp, index, axis, across_dir, through, u, dz, along};
}

class PlainWeave {
 public:
  explicit PlainWeave(const WeaveParams& p) : p_(p), voxel_size_(double(std::max(p.yarns, p.layers)) / p.resolution) {}

  double voxelSize() const { return voxel_size_; }

  openvdb::CoordBBox bounds() const {
    auto last = [&](int extent) { return int(std::ceil(extent / voxel_size_)) - 1; };
    return {openvdb::Coord(0), openvdb::Coord(last(p_.yarns), last(p_.yarns), last(p_.layers))};
  }

  // A block can hold fibers only where it meets the slab of some layer.
  bool mayBeOccupied(const openvdb::CoordBBox& block) const {
    const double z0 = (block.min().z() - 0.5) * voxel_size_, z1 = (block.max().z() + 0.5) * voxel_size_;
    const double half = kAmplitude + kHalfHeight;
    for (int layer = 0; layer < p_.layers; ++layer)
      if (z1 >= layer + 0.5 - half && z0 <= layer + 0.5 + half) return true;
    return false;
  }

  std::optional<VoxelSample> sample(const openvdb::Coord& ijk) const {
    const Vec3 centre = Vec3(ijk.x(), ijk.y(), ijk.z()) * voxel_size_;
    int inside = 0;
    for (int k = 0; k < 8; ++k) {
      const Vec3 offset = (Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1) - Vec3::Constant(0.5)) * (0.5 * voxel_size_);
      inside += fiberAt(centre + offset).has_value();
    }
    if (inside == 0) return std::nullopt;
    auto yarn = locateYarn(centre, true);
    if (!yarn) yarn = locateYarn(centre, false);
    if (!yarn) return std::nullopt;  // fibers only at subsamples off the centre's yarn: skip the sliver
    VoxelSample voxel;
    voxel.density = float(p_.fiber_density * inside / 8.0);
    voxel.S = Sggx::fiberMatrix(fiberTangent(*yarn), p_.roughness);
    const auto fiber = fiberCell(*yarn);
    const double jitter = 1 + 0.08 * (2 * hashUniform(p_.seed, {7, yarn->warp, yarn->yarn, fiber.x(), fiber.y()}) - 1);
    voxel.albedo = ((yarn->warp ? p_.warp_albedo : p_.weft_albedo) * jitter).cwiseMin(1.0).cwiseMax(0.0);
    return voxel;
  }

 private:
  // Cross-section offset in the frame that turns with the fibers (untwisted).
  Eigen::Vector2d untwisted(const YarnPoint& y) const {
    const double angle = -2 * kPi * y.s / kTwistPitch;
    return Eigen::Rotation2Dd(angle) * Eigen::Vector2d(y.u, y.v);
  }

  Eigen::Vector2i fiberCell(const YarnPoint& y) const {
    const Eigen::Vector2d q = untwisted(y) / kFiberSpacing;
    return Eigen::Vector2i(int(std::floor(q.x())), int(std::floor(q.y())));
  }

  // Is p inside a fiber? Fibers are discs around jittered cell centres of the untwisted section.
  std::optional<YarnPoint> fiberAt(const Vec3& p) const {
    for (bool warp : {true, false}) {
      auto y = locateYarn(p, warp);
      if (!y) continue;
      const Eigen::Vector2d q = untwisted(*y);
      const Eigen::Vector2i cell = fiberCell(*y);
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) {
          const int cx = cell.x() + dx, cy = cell.y() + dy;
          const double jx = 0.5 * hashUniform(p_.seed, {1, warp, y->yarn, cx, cy}) - 0.25;
          const double jy = 0.5 * hashUniform(p_.seed, {2, warp, y->yarn, cx, cy}) - 0.25;
          const Eigen::Vector2d c = (Eigen::Vector2d(cx + 0.5 + jx, cy + 0.5 + jy)) * kFiberSpacing;
          if ((q - c).squaredNorm() < kFiberRadius * kFiberRadius) return y;
        }
    }
    return std::nullopt;
  }

  // A helix around the yarn axis: tangent = axis + (2 pi / pitch) * (azimuthal offset).
  static Vec3 fiberTangent(const YarnPoint& y) {
    const double twist = 2 * kPi / kTwistPitch;
    return (y.axis + twist * (y.u * y.through - y.v * y.across)).normalized();
  }

  WeaveParams p_;
  double voxel_size_;
};

}  // namespace

MediumPtr makePlainWeave(const WeaveParams& params) {
  const PlainWeave weave(params);
  ProceduralLayout layout;
  layout.bounds = weave.bounds();
  layout.voxel_size = weave.voxelSize();
  return fillMedium(
      layout, [&](const openvdb::CoordBBox& block) { return weave.mayBeOccupied(block); },
      [&](const openvdb::Coord& ijk) { return weave.sample(ijk); });
}

}  // namespace vdbappear
