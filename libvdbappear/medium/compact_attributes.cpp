#include "libvdbappear/medium/compact_attributes.h"

#include "libvdbappear/io/leaf_values.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/math/sggx.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

namespace vdbappear {

namespace {

using openvdb::math::half;

}  // namespace

// S = R diag(lambda) R^T in double precision from the float channels (Eigen's closed form, accurate
// to a few ulps of |S|), R turned proper (det +1) so that a quaternion holds it.
CompactVoxel compactVoxel(const openvdb::Vec3s& albedo, const openvdb::Vec3s& diag, const openvdb::Vec3s& offdiag) {
  const Mat3 S = sggxMatrix(Vec3(diag[0], diag[1], diag[2]), Vec3(offdiag[0], offdiag[1], offdiag[2]));
  Eigen::SelfAdjointEigenSolver<Mat3> solver;
  solver.computeDirect(S);
  Mat3 R = solver.eigenvectors();
  if (R.determinant() < 0) R.col(2) = -R.col(2);
  const Eigen::Quaterniond q(R);
  CompactVoxel v;
  for (int c = 0; c < 3; ++c) v.albedo[c] = half(albedo[c]);
  const double rotation[4] = {q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 4; ++i) v.rotation[i] = std::int16_t(std::lround(32767 * rotation[i]));
  for (int i = 0; i < 3; ++i) v.sigma[i] = half(float(std::sqrt(std::max(0.0, solver.eigenvalues()[i]))));
  return v;
}

Mat3 sggxOf(const CompactVoxel& v) {
  const Vec3 lambda(double(float(v.sigma[0])) * float(v.sigma[0]), double(float(v.sigma[1])) * float(v.sigma[1]),
                    double(float(v.sigma[2])) * float(v.sigma[2]));
  const Mat3 R = rotationOf(v);
  return R * lambda.asDiagonal() * R.transpose();
}

LeafRecords::LeafRecords(const CompactVoxel* first_record, const openvdb::util::NodeMask<3>& mask) : first(first_record) {
  std::uint16_t count = 0;
  for (openvdb::Index n = 0; n < 8; ++n) {
    before_word[n] = count;
    count = std::uint16_t(count + openvdb::util::CountOn(mask.getWord<openvdb::Index64>(n)));
  }
}

void CompactAttributes::add(const Medium& piece) {
  const openvdb::FloatTree& density = piece.density->tree();
  if (density.activeTileCount() > 0)
    throw std::invalid_argument(piece.source + ": the compact form takes a density of leaves only (it has active tiles)");
  if (piece.albedo) has_albedo_ = true;
  if (piece.hasSggx()) has_sggx_ = true;
  std::vector<const DensityLeaf*> leaves;
  leaves.reserve(density.leafCount());
  for (auto leaf = density.cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf.getLeaf());
  Piece added;
  added.leaves.resize(leaves.size());
  std::vector<std::uint64_t> first(leaves.size() + 1, 0);  // each leaf's first record in the piece
  for (std::size_t i = 0; i < leaves.size(); ++i) first[i + 1] = first[i] + leaves[i]->onVoxelCount();
  added.records.reset(new CompactVoxel[first.back()]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 16), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const DensityLeaf& leaf = *leaves[i];
      const openvdb::Coord& origin = leaf.origin();
      const auto albedo = piece.albedo ? LeafValues<openvdb::Vec3STree>(piece.albedo->tree(), origin)
                                       : LeafValues<openvdb::Vec3STree>(defaults::kAlbedo);
      const auto diag = piece.sggx_diag ? LeafValues<openvdb::Vec3STree>(piece.sggx_diag->tree(), origin)
                                        : LeafValues<openvdb::Vec3STree>(defaults::kSggxDiag);
      const auto offdiag = piece.sggx_offdiag ? LeafValues<openvdb::Vec3STree>(piece.sggx_offdiag->tree(), origin)
                                              : LeafValues<openvdb::Vec3STree>(defaults::kSggxOffdiag);
      CompactVoxel* record = added.records.get() + first[i];
      openvdb::Index previous = 0;
      for (auto v = leaf.cbeginValueOn(); v; ++v) {
        const openvdb::Index n = v.pos();
        // Neighbours often share S and albedo (a tile, a constant grid, a uniform fibre): one
        // eigen-decomposition for a run of them.
        if (record > added.records.get() + first[i] && albedo[n] == albedo[previous] && diag[n] == diag[previous] &&
            offdiag[n] == offdiag[previous]) {
          *record = record[-1];
          ++record;
        } else {
          *record++ = compactVoxel(albedo[n], diag[n], offdiag[n]);
        }
        previous = n;
      }
      added.leaves[i] = LeafRecords(added.records.get() + first[i], leaf.getValueMask());
    }
  });
  openvdb::tree::ValueAccessor<openvdb::Int64Tree> index(leaves_);
  for (std::size_t i = 0; i < leaves.size(); ++i)
    index.setValue(leafKey(leaves[i]->origin()), std::int64_t(reinterpret_cast<std::intptr_t>(&added.leaves[i])));
  voxel_count_ += first.back();
  pieces_.push_back(std::move(added));
}

std::uint64_t CompactAttributes::memoryBytes() const {
  std::uint64_t bytes = leaves_.memUsage();
  for (const Piece& piece : pieces_) bytes += piece.leaves.capacity() * sizeof(LeafRecords);
  return bytes + voxel_count_ * sizeof(CompactVoxel);
}

}  // namespace vdbappear
