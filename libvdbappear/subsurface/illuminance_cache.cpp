#include "libvdbappear/subsurface/illuminance_cache.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

IlluminanceCache::IlluminanceCache(const Vec3& lo, const Vec3& hi, double min_normal_cos) : min_normal_cos_(min_normal_cos) {
  const double side = (hi - lo).maxCoeff() * (1 + 1e-6) + 1e-9;
  const Vec3 centre = 0.5 * (lo + hi);
  nodes_.emplace_back(centre - Vec3::Constant(side / 2), side);
}

bool IlluminanceCache::valid(const IlluminanceCacheEntry& e, const Vec3& x, const Vec3& normal, double reach) const {
  return (x - e.p).squaredNorm() < reach * reach * e.radius * e.radius && e.normal.dot(normal) >= min_normal_cos_;
}

// The shell of a node (Fig. 3.5): its cube grown from side S to 2S about its centre. A cache stored
// in the node lies inside it and has r_k <= S / 2, so every point it serves lies in the shell; with
// a reach above 1, the cube grown by reach S / 2 on each side.
bool IlluminanceCache::inShell(const Node& node, const Vec3& x, double reach) const {
  const Vec3 lo = node.lo - Vec3::Constant(reach * node.side / 2);
  const Vec3 hi = node.lo + Vec3::Constant((1 + reach / 2) * node.side);
  return (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
}

int IlluminanceCache::childContaining(int index, const Vec3& p) {
  const double half = nodes_[std::size_t(index)].side / 2;
  const Vec3 mid = nodes_[std::size_t(index)].lo + Vec3::Constant(half);
  const int octant = int(p.x() >= mid.x()) | int(p.y() >= mid.y()) << 1 | int(p.z() >= mid.z()) << 2;
  if (nodes_[std::size_t(index)].child[octant] < 0) {
    Vec3 lo = nodes_[std::size_t(index)].lo;
    for (int axis = 0; axis < 3; ++axis)
      if ((octant >> axis) & 1) lo[axis] += half;
    nodes_.emplace_back(lo, half);
    nodes_[std::size_t(index)].child[octant] = int(nodes_.size() - 1);
  }
  return nodes_[std::size_t(index)].child[octant];
}

// StoredCaches (§3.4): descend while r_k < side / 4, so the cache rests where 2 r_k < side <= 4 r_k
// (or at the root, when r_k is larger still).
void IlluminanceCache::insert(const IlluminanceCacheEntry& entry) {
  entries_.push_back(entry);
  int node = 0;
  while (entry.radius < nodes_[std::size_t(node)].side / 4) node = childContaining(node, entry.p);
  nodes_[std::size_t(node)].entries.push_back(entries_.size() - 1);
}

// FindAnyValidCache. The seed returns the first shell-holding child's answer ("Return
// FindAnyValidCache(x, j)"), which misses a valid cache in a sibling whose shell also holds x: a
// child's "no" here goes on to the next child (tested against a linear scan).
bool IlluminanceCache::anyValidBelow(int index, const Vec3& x, const Vec3& normal, double reach) const {
  const Node& node = nodes_[std::size_t(index)];
  for (std::size_t k : node.entries)
    if (valid(entries_[k], x, normal, reach)) return true;
  for (int child : node.child)
    if (child >= 0 && inShell(nodes_[std::size_t(child)], x, reach) && anyValidBelow(child, x, normal, reach)) return true;
  return false;
}

bool IlluminanceCache::anyValid(const Vec3& x, const Vec3& normal, double reach) const {
  return anyValidBelow(0, x, normal, reach);
}

void IlluminanceCache::allValidBelow(int index, const Vec3& x, const Vec3& normal, double reach,
                                     std::vector<std::size_t>* found) const {
  const Node& node = nodes_[std::size_t(index)];
  for (std::size_t k : node.entries)
    if (valid(entries_[k], x, normal, reach)) found->push_back(k);
  for (int child : node.child)
    if (child >= 0 && inShell(nodes_[std::size_t(child)], x, reach)) allValidBelow(child, x, normal, reach, found);
}

void IlluminanceCache::allValid(const Vec3& x, const Vec3& normal, std::vector<std::size_t>* found, double reach) const {
  found->clear();
  allValidBelow(0, x, normal, reach, found);
}

std::optional<SubsurfaceEstimate> IlluminanceCache::interpolate(const Vec3& x, const Vec3& normal, double reach) const {
  thread_local std::vector<std::size_t> found;
  allValid(x, normal, &found, reach);
  if (found.empty()) return std::nullopt;
  std::sort(found.begin(), found.end());  // a fixed order of summation, whatever the octree's
  SubsurfaceEstimate result;
  double weight_sum = 0;
  for (std::size_t k : found) {
    const IlluminanceCacheEntry& e = entries_[k];
    // Along the surface: the offset in the cache's tangent plane. S falls steeply off the surface
    // (R_s is a 3-D function), and on a curved surface the seed's full offset x - p_k would pick
    // that fall up through the offset's normal part (docs/subsurface.md §6, a deviation).
    const Vec3 along = x - e.p;
    const Vec3 offset = along - along.dot(e.normal) * e.normal;
    const double w = e.radius / std::max(along.norm(), 1e-9 * e.radius);
    for (int c = 0; c < 3; ++c) {
      result.S[c] += w * (e.S[c] + offset.dot(e.gradS[c]));  // Eq. (3.9)
      result.gradS[c] += w * (e.gradS[c] - e.gradS[c].dot(e.normal) * e.normal);
    }
    result.V += w * e.V;
    weight_sum += w;
  }
  result.S = (result.S / weight_sum).max(0.0);  // a gradient may extrapolate below zero
  for (Vec3& g : result.gradS) g /= weight_sum;
  result.V /= weight_sum;
  result.terms = found.size();
  return result;
}

}  // namespace vdbappear
