#pragma once
// The seed's cache of subsurface illuminance (§3.3-3.4 of the translucent-caching seed): caches of
// S, grad S and V at surface points, each valid within a radius r_k, kept in an octree where a
// cache lives in a node of side 2 r_k to 4 r_k (StoredCaches, Fig. 3.4), found through the nodes'
// shells (Fig. 3.5), and interpolated with gradients (Eq. 3.9).

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/vector.h"
#include "libvdbappear/subsurface/irradiance_octree.h"  // SubsurfaceEstimate

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

namespace vdbappear {

struct IlluminanceCacheEntry {
  Vec3 p = Vec3::Zero(), normal = Vec3::UnitZ();
  Rgb S = Rgb::Zero();
  std::array<Vec3, 3> gradS{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  Rgb V = Rgb::Zero();
  double radius = 0;  // r_k: the cache serves points closer than this
};

// How far a cache may reach for a point seen through mirror reflections of total reflectance F
// (the product of F_r along the way): its light reaches the pixel scaled by F, so a cache may serve
// it out to 1/F times its radius, at most 8 (docs/subsurface.md §6); 1 for a point seen directly.
inline double cacheReach(double reflectance) {
  return reflectance >= 1 ? 1.0 : reflectance <= 1.0 / 8 ? 8.0 : 1 / reflectance;
}

class IlluminanceCache {
 public:
  // A cube around [lo, hi] is the root; min_normal_cos: a cache serves a point only where their
  // normals agree this well (docs/subsurface.md §5: against leaks across thin parts, a deviation).
  IlluminanceCache(const Vec3& lo, const Vec3& hi, double min_normal_cos);

  // StoredCaches: down to the node whose side is no more than 4 r_k (split on demand).
  void insert(const IlluminanceCacheEntry& entry);
  // FindAnyValidCache and FindAllValidCache: caches k with |x - p_k| < reach r_k (and normals that
  // agree); reach > 1 for points seen through reflections (cacheReach).
  bool anyValid(const Vec3& x, const Vec3& normal, double reach = 1) const;
  void allValid(const Vec3& x, const Vec3& normal, std::vector<std::size_t>* found, double reach = 1) const;
  // Eq. (3.9) over the valid caches with the weights w_k = r_k / |x - p_k|: the seed's 1 / epsilon_k
  // (Eq. 3.10) with epsilon_k relative to the cache's own S_k and a, and its clamps (1 at the edge of
  // the valid domain, where the seed's w_k a is 1); the offset x - p_k is taken in the cache's
  // tangent plane. Nothing where no cache is valid. It gives S, and the weighted means of the caches'
  // grad S (their tangential parts) and V (the AOVs), with terms = |C|, the caches used.
  std::optional<SubsurfaceEstimate> interpolate(const Vec3& x, const Vec3& normal, double reach = 1) const;

  const std::vector<IlluminanceCacheEntry>& entries() const { return entries_; }
  std::size_t nodeCount() const { return nodes_.size(); }

 private:
  struct Node {
    Node(const Vec3& lo_corner, double side_length) : lo(lo_corner), side(side_length) {}
    Vec3 lo;
    double side;
    std::array<int, 8> child{-1, -1, -1, -1, -1, -1, -1, -1};
    std::vector<std::size_t> entries;
  };
  bool valid(const IlluminanceCacheEntry& e, const Vec3& x, const Vec3& normal, double reach) const;
  bool inShell(const Node& node, const Vec3& x, double reach) const;
  int childContaining(int node, const Vec3& p);
  bool anyValidBelow(int node, const Vec3& x, const Vec3& normal, double reach) const;
  void allValidBelow(int node, const Vec3& x, const Vec3& normal, double reach, std::vector<std::size_t>* found) const;

  std::vector<Node> nodes_;
  std::vector<IlluminanceCacheEntry> entries_;
  double min_normal_cos_;
};

}  // namespace vdbappear
