#include "libvdbappear/procedural/weave_medium.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/procedural/voxel_filler.h"
#include "libvdbappear/util/hash_random.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace vdbappear {

namespace {

// Three uniforms in [0,1) from one 64-bit hash, 21 bits each.
struct HashTriple {
  explicit HashTriple(std::uint64_t h) : bits(h) {}
  double operator[](int k) const { return double((bits >> (21 * k)) & 0x1fffff) * 0x1.0p-21; }
  std::uint64_t bits;
};

}  // namespace

WeaveGeometry::WeaveGeometry(const WeaveParams& params)
    : WeaveGeometry(params, WeavePattern::byName(params.pattern, params.harness)) {}

WeaveGeometry::WeaveGeometry(const WeaveParams& params, WeavePattern pattern)
    : params_(params), pattern_(std::move(pattern)) {}

bool WeaveGeometry::onTop(bool warp, int yarn, int crossing) const {
  return warp ? pattern_.warpOver(yarn, crossing) : !pattern_.warpOver(crossing, yarn);
}

std::optional<YarnPoint> WeaveGeometry::locateYarn(const Vec3& p, bool warp) const {
  const double along = warp ? p.x() : p.y(), across = warp ? p.y() : p.x();
  const int yarn = int(std::floor(across));
  const int layer = int(std::floor(p.z()));
  // u runs along +y for warp, -x for weft: both cross-section frames (across, through, axis) are
  // right-handed, so warp and weft fibers twist the same way (Z twist).
  const double u = (across - (yarn + 0.5)) * (warp ? 1.0 : -1.0);
  if (std::abs(u) > kHalfWidth) return std::nullopt;
  // Crimp: the centreline sits +-kAmplitude above the layer's mid-plane at the crossing centres
  // (up where this yarn is on top) and follows a half cosine in between.
  const double c = along - 0.5;
  const int crossing = int(std::floor(c));
  const double t = c - crossing;
  const double h0 = onTop(warp, yarn, crossing) ? kAmplitude : -kAmplitude;
  const double h1 = onTop(warp, yarn, crossing + 1) ? kAmplitude : -kAmplitude;
  const double height = h0 == h1 ? h0 : h0 + (h1 - h0) * 0.5 * (1 - std::cos(kPi * t));
  const double v = p.z() - (layer + 0.5) - height;
  if ((u / kHalfWidth) * (u / kHalfWidth) + (v / kHalfHeight) * (v / kHalfHeight) > 1) return std::nullopt;
  const double slope = h0 == h1 ? 0.0 : (h1 - h0) * 0.5 * kPi * std::sin(kPi * t);
  return YarnPoint{warp, layer, yarn, u, v, along, slope};
}

YarnFrame yarnFrame(const YarnPoint& y) {
  const Vec3 axis = (y.warp ? Vec3(1, 0, y.slope) : Vec3(0, 1, y.slope)).normalized();
  const Vec3 across = y.warp ? Vec3(0, 1, 0) : Vec3(-1, 0, 0);
  const Vec3 through = axis.cross(across).normalized();  // about +z; across x through = axis
  return {axis, across, through};
}

double WeaveGeometry::fiberAngle(double along) const { return 2 * kPi * along / params_.twist_pitch; }

std::optional<FiberPoint> WeaveGeometry::fiberAt(const Vec3& p) const {
  for (bool warp : {true, false}) {
    const std::optional<YarnPoint> y = locateYarn(p, warp);
    if (!y) continue;
    // Untwist the cross-section: fibers sit at fixed places of the frame that turns with them.
    const Eigen::Vector2d q = Eigen::Rotation2Dd(-fiberAngle(y->along)) * Eigen::Vector2d(y->u, y->v);
    const Eigen::Vector2d cell_f = (q / kFiberSpacing).array().floor();
    const int cx = int(cell_f.x()), cy = int(cell_f.y());
    const HashTriple h(hashKeys(params_.seed, {warp, y->layer, y->yarn, cx, cy}));
    const Eigen::Vector2d centre = (cell_f + Eigen::Vector2d::Constant(0.5)) * kFiberSpacing +
                                   kFiberJitter * Eigen::Vector2d(2 * h[0] - 1, 2 * h[1] - 1);
    if ((q - centre).squaredNorm() >= kFiberRadius * kFiberRadius) continue;
    // A helix about the yarn axis. Per unit of `along`, the centreline advances by (1, slope)
    // (unnormalised) and the fiber turns by 2 pi / pitch about it: tangent = centreline
    // derivative + (2 pi / pitch) * (azimuthal offset).
    const double twist = 2 * kPi / params_.twist_pitch;
    const YarnFrame f = yarnFrame(*y);
    const Vec3 centreline = f.axis * std::sqrt(1 + y->slope * y->slope);
    const Vec3 tangent = (centreline + twist * (y->u * f.through - y->v * f.across)).normalized();
    const double jitter = 1 + 0.08 * (2 * h[2] - 1);  // per-fiber colour variation
    const Vec3 albedo = ((warp ? params_.warp_albedo : params_.weft_albedo) * jitter).cwiseMin(1.0).cwiseMax(0.0);
    return FiberPoint{tangent, albedo, params_.fiber_density, params_.roughness};
  }
  return std::nullopt;
}

std::optional<VoxelSample> WeaveGeometry::sampleVoxel(const Vec3& centre, double voxel_size) const {
  // Reject voxels whose circumscribed sphere misses both yarn ellipses, widened by the radius
  // (vertically also by the steepest crimp slope, kAmplitude * pi / 2, over that radius).
  const double r = 0.87 * voxel_size;
  auto near = [&](bool warp) {
    const double across = warp ? centre.y() : centre.x();
    const double u = across - (std::floor(across) + 0.5);
    if (std::abs(u) > kHalfWidth + r) return false;
    const double dz = centre.z() - (std::floor(centre.z()) + 0.5);
    return std::abs(dz) <= kAmplitude + kHalfHeight + r * (1 + 0.5 * kPi * kAmplitude);
  };
  if (!near(true) && !near(false)) return std::nullopt;
  return sampleFiberVoxel(*this, centre, voxel_size);
}

bool WeaveGeometry::slabMayHoldYarns(double z0, double z1) const {
  const double half = kAmplitude + kHalfHeight;
  for (int layer = 0; layer < params_.layers; ++layer)
    if (z1 >= layer + 0.5 - half && z0 <= layer + 0.5 + half) return true;
  return false;
}

MediumPtr makeWeave(const WeaveParams& params) {
  const WeaveGeometry weave(params);
  const double voxel_size = double(std::max(params.yarns, params.layers)) / params.resolution;
  const int across = voxelsToCover(params.yarns, voxel_size);
  ProceduralLayout layout =
      cornerLayout(openvdb::Coord(across, across, voxelsToCover(params.layers, voxel_size)), voxel_size);
  layout.memory = params.memory;
  return fillMedium(
      layout,
      [&](const openvdb::CoordBBox& block) {
        return weave.slabMayHoldYarns(block.min().z() * voxel_size, (block.max().z() + 1) * voxel_size);
      },
      [&](const openvdb::Coord&, const Vec3& centre) { return weave.sampleVoxel(centre, voxel_size); });
}

}  // namespace vdbappear
