#pragma once
// Straight fiber segments (velvet pile, fur strands) in a uniform grid of buckets, so that the
// fiber through a point is found by testing only the few segments of the point's bucket.

#include "libvdbappear/math/vector.h"

#include <cstdint>
#include <vector>

namespace vdbappear {

// A solid cylinder of `radius` around the segment a -> b, flat-ended.
struct FiberSegment {
  Vec3 a, b;
  double radius;
  int material = 0;  // caller's index: colour, density, roughness
};

class SegmentIndex {
 public:
  // `cell_size`: bucket edge; a few fiber radii is a good choice.
  SegmentIndex(std::vector<FiberSegment> segments, double cell_size);

  // The lowest-numbered segment whose cylinder holds p, or -1.
  int find(const Vec3& p) const;
  const FiberSegment& segment(int id) const { return segments_[std::size_t(id)]; }
  std::size_t size() const { return segments_.size(); }
  // World box holding every cylinder.
  const Vec3& lower() const { return lower_; }
  const Vec3& upper() const { return upper_; }

 private:
  std::int64_t bucketOf(const Eigen::Vector3i& cell) const;
  Eigen::Vector3i cellOf(const Vec3& p) const;

  std::vector<FiberSegment> segments_;
  double cell_size_;
  Vec3 lower_, upper_;
  Eigen::Vector3i dims_;
  std::vector<std::uint32_t> first_;  // CSR: segments of bucket b are ids_[first_[b] .. first_[b+1])
  std::vector<std::int32_t> ids_;
};

// Is p inside the flat-ended cylinder of `s`?
bool insideSegment(const FiberSegment& s, const Vec3& p);

}  // namespace vdbappear
