#include "libvdbappear/procedural/fiber_segments.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace vdbappear {

bool insideSegment(const FiberSegment& s, const Vec3& p) {
  const Vec3 d = s.b - s.a;
  const double t = (p - s.a).dot(d) / d.squaredNorm();
  if (t < 0 || t > 1) return false;
  return (p - (s.a + t * d)).squaredNorm() < s.radius * s.radius;
}

SegmentIndex::SegmentIndex(std::vector<FiberSegment> segments, double cell_size)
    : segments_(std::move(segments)), cell_size_(cell_size) {
  if (segments_.empty()) throw std::invalid_argument("SegmentIndex: no segments");
  lower_ = Vec3::Constant(std::numeric_limits<double>::infinity());
  upper_ = -lower_;
  for (const FiberSegment& s : segments_) {
    lower_ = lower_.cwiseMin(s.a.cwiseMin(s.b) - Vec3::Constant(s.radius));
    upper_ = upper_.cwiseMax(s.a.cwiseMax(s.b) + Vec3::Constant(s.radius));
  }
  dims_ = ((upper_ - lower_) / cell_size_).array().ceil().cast<int>().cwiseMax(1);

  // Walk each segment in steps of half a bucket and enter every bucket that a ball of radius
  // (fiber radius + half a step) around a step point touches: together they cover the cylinder.
  std::vector<std::pair<std::int64_t, std::int32_t>> entries;
  std::vector<std::int64_t> mine;
  for (std::size_t id = 0; id < segments_.size(); ++id) {
    const FiberSegment& s = segments_[id];
    const double step = 0.5 * cell_size_;
    const int steps = std::max(1, int(std::ceil((s.b - s.a).norm() / step)));
    const Vec3 reach = Vec3::Constant(s.radius + 0.5 * step);
    mine.clear();
    for (int k = 0; k <= steps; ++k) {
      const Vec3 q = s.a + (s.b - s.a) * (double(k) / steps);
      const Eigen::Vector3i lo = cellOf(q - reach), hi = cellOf(q + reach);
      for (int x = lo.x(); x <= hi.x(); ++x)
        for (int y = lo.y(); y <= hi.y(); ++y)
          for (int z = lo.z(); z <= hi.z(); ++z) mine.push_back(bucketOf({x, y, z}));
    }
    std::sort(mine.begin(), mine.end());
    mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
    for (std::int64_t b : mine) entries.emplace_back(b, std::int32_t(id));
  }
  std::sort(entries.begin(), entries.end());  // by bucket, then id: find() returns the lowest id
  const std::int64_t buckets = std::int64_t(dims_.x()) * dims_.y() * dims_.z();
  first_.assign(std::size_t(buckets) + 1, 0);
  ids_.reserve(entries.size());
  for (const auto& [bucket, id] : entries) {
    ++first_[std::size_t(bucket) + 1];
    ids_.push_back(id);
  }
  for (std::size_t b = 1; b < first_.size(); ++b) first_[b] += first_[b - 1];
}

Eigen::Vector3i SegmentIndex::cellOf(const Vec3& p) const {
  const Eigen::Vector3i c = ((p - lower_) / cell_size_).array().floor().cast<int>();
  return c.cwiseMax(0).cwiseMin(dims_ - Eigen::Vector3i::Ones());
}

std::int64_t SegmentIndex::bucketOf(const Eigen::Vector3i& c) const {
  return (std::int64_t(c.x()) * dims_.y() + c.y()) * dims_.z() + c.z();
}

int SegmentIndex::find(const Vec3& p) const {
  if ((p.array() < lower_.array()).any() || (p.array() > upper_.array()).any()) return -1;
  const std::int64_t b = bucketOf(cellOf(p));
  for (std::uint32_t k = first_[std::size_t(b)]; k < first_[std::size_t(b) + 1]; ++k)
    if (insideSegment(segments_[std::size_t(ids_[k])], p)) return ids_[k];
  return -1;
}

}  // namespace vdbappear
