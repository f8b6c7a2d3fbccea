#pragma once
// The per-voxel values a render reads beside the density, held compactly for rendering
// (docs/rendering.md, "The render's medium in memory"): one 20-byte record per active density voxel,
// the albedo as three half floats and the SGGX matrix S by its eigen-decomposition, S = R diag(s^2)
// R^T: the rotation R as a unit quaternion in 16-bit fixed point and the square roots s of the
// eigenvalues as half floats. The float grids hold 36 bytes per voxel of every leaf, active or not.
//
// Why not S's six entries in half floats: rounding them moves S's eigenvalues by about 2^-12 |S|,
// which makes a thin fibre's S (eigenvalue roughness^2 = 0.0001 along the fibre at roughness 0.01)
// indefinite, and errs by almost 1% in sigma(w) = sqrt(w^T S w) near a fibre of roughness 0.1.
// Stored as eigenvalues and a rotation, S stays positive definite and each eigenvalue keeps its own
// relative precision (2^-11). Near a thin fibre's direction sigma varies over an angle of about the
// roughness, so what counts there is the fibre's direction: a quaternion in half floats tilts it by up
// to 8e-4 radians (4% in sigma at roughness 0.01), in 16-bit fixed point by about 5e-5. sigma(w) then
// errs by at most 2^-10 relative in every direction down to roughness 0.03, 0.19% at 0.01
// (tests/unit/compact_medium_test.cpp). Storing s = sqrt(eigenvalue) widens the range half floats
// take: eigenvalues from 4e-9 to 4e9.
//
// A record is found from the density leaf holding its voxel: the leaf's first record plus the
// voxel's rank among the leaf's active voxels, from the active voxels before each 64-voxel word of
// its value mask and a popcount within the word. Both are kept per leaf (LeafRecords), found through
// a tree with one value per leaf. The density tree's leaves must keep the masks they had when added.
// Internal header: includes OpenVDB.

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/vector.h"

#include <Eigen/Geometry>

#include <openvdb/math/Half.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace vdbappear {

struct Medium;

struct CompactVoxel {
  openvdb::math::half albedo[3];
  std::int16_t rotation[4];         // R as a unit quaternion (w, x, y, z) times 32767; its columns are S's eigenvectors
  openvdb::math::half sigma[3];     // the square roots of S's eigenvalues
};
static_assert(sizeof(CompactVoxel) == 20, "a record is 20 bytes");

// The record of a voxel's albedo and S = sggxMatrix(diag, offdiag) (S positive definite, as the
// medium's readers check; a negative eigenvalue is taken as 0).
CompactVoxel compactVoxel(const openvdb::Vec3s& albedo, const openvdb::Vec3s& diag, const openvdb::Vec3s& offdiag);
inline Rgb albedoOf(const CompactVoxel& v) { return {float(v.albedo[0]), float(v.albedo[1]), float(v.albedo[2])}; }
// R from the quaternion q; with s = 2 / |q|^2 it is orthonormal whatever q's rounding (no square root).
inline Mat3 rotationOf(const CompactVoxel& v) {
  const double w = v.rotation[0], x = v.rotation[1], y = v.rotation[2], z = v.rotation[3];
  const double s = 2 / (w * w + x * x + y * y + z * z);  // the scale 32767 cancels
  Mat3 R;
  R << 1 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y),  //
      s * (x * y + w * z), 1 - s * (x * x + z * z), s * (y * z - w * x),  //
      s * (x * z - w * y), s * (y * z + w * x), 1 - s * (x * x + y * y);
  return R;
}
Mat3 sggxOf(const CompactVoxel& v);      // R diag(sigma^2) R^T
// The largest eigenvalue of sggxOf(v): the largest sigma^2 (R is orthonormal to double rounding).
inline double largestEigenvalueOf(const CompactVoxel& v) {
  const double s = std::max({float(v.sigma[0]), float(v.sigma[1]), float(v.sigma[2])});
  return s * s;
}
// w^T S w = sum_i (sigma_i r_i . w)^2, r_i the columns of R. R^T w is w turned by the conjugate
// quaternion (a, -u): w + (2 / |q|^2) (-a (u x w) + u x (u x w)), without forming R.
inline double wSwOf(const CompactVoxel& v, const Vec3& w) {
  const Vec3 u(v.rotation[1], v.rotation[2], v.rotation[3]);
  const double a = v.rotation[0];
  const Vec3 uw = u.cross(w);
  const Vec3 local = w + (2 / (a * a + u.squaredNorm())) * (u.cross(uw) - a * uw);
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    const double projected = double(float(v.sigma[i])) * local[i];
    sum += projected * projected;
  }
  return sum;
}

// Where a density leaf's records are: the first, and the leaf's active voxels before each word of
// its value mask.
struct LeafRecords {
  const CompactVoxel* first = nullptr;
  std::uint16_t before_word[8] = {};
  LeafRecords() = default;
  LeafRecords(const CompactVoxel* first_record, const openvdb::util::NodeMask<3>& mask);
  // The record of active voxel `offset` of the leaf whose value mask is `mask`.
  const CompactVoxel& at(const openvdb::util::NodeMask<3>& mask, openvdb::Index offset) const {
    const openvdb::Index64 below = (openvdb::Index64(1) << (offset & 63)) - 1;
    return first[before_word[offset >> 6] + openvdb::util::CountOn(mask.getWord<openvdb::Index64>(offset >> 6) & below)];
  }
};

class CompactAttributes {
 public:
  using DensityLeaf = openvdb::FloatTree::LeafNodeType;

  // Records for every active voxel of the density leaves of `piece` (a medium or a slab of one),
  // from its albedo and SGGX grids (absent: the defaults). The piece's density must hold no active
  // tiles (std::invalid_argument) and its leaves must not overlap those of pieces added before.
  void add(const Medium& piece);

  bool hasAlbedo() const { return has_albedo_; }
  bool hasSggx() const { return has_sggx_; }
  std::uint64_t voxelCount() const { return voxel_count_; }
  std::uint64_t memoryBytes() const;  // the records and their leaf index

  // Per thread, as an OpenVDB accessor.
  class Accessor {
   public:
    explicit Accessor(const CompactAttributes& attributes) : leaves_(attributes.leaves_) {}
    // The record of active voxel `offset` of `leaf`, a density leaf that was added.
    const CompactVoxel& at(const DensityLeaf& leaf, openvdb::Index offset) { return recordsOf(leaf).at(leaf.getValueMask(), offset); }
    // Where the records of `leaf`, a density leaf that was added, are.
    const LeafRecords& recordsOf(const DensityLeaf& leaf) {
      return *reinterpret_cast<const LeafRecords*>(leaves_.getValue(leafKey(leaf.origin())));
    }

   private:
    openvdb::tree::ValueAccessor<const openvdb::Int64Tree> leaves_;
  };

 private:
  static openvdb::Coord leafKey(const openvdb::Coord& origin) { return {origin.x() >> 3, origin.y() >> 3, origin.z() >> 3}; }

  struct Piece {
    std::unique_ptr<CompactVoxel[]> records;
    std::vector<LeafRecords> leaves;
  };
  std::vector<Piece> pieces_;     // one per piece added
  openvdb::Int64Tree leaves_{0};  // at leafKey(origin): the address of the leaf's LeafRecords
  std::uint64_t voxel_count_ = 0;
  bool has_albedo_ = false, has_sggx_ = false;
};

}  // namespace vdbappear
