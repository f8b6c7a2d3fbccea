#pragma once
// Jensen and Buhler's hierarchical integration of the dipole (§3.4 of the translucent-caching
// seed): irradiance samples in an octree whose nodes keep the sums of Eq. (3.11)-(3.13), and the
// evaluation of S (Eq. 3.1), grad S (Eq. 3.8) and the split-disk variance V (Eq. 3.14) at a point
// from the set N that Traverse_octree finds.

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/vector.h"

#include <array>
#include <cstddef>
#include <vector>

namespace vdbappear {

struct RgbDipole;

// One irradiance sample of pass 1: a face centroid, its face's area and the Fresnel-transmitted
// irradiance E^ there (docs/subsurface.md §2), and the face itself, over which the sum integrates
// where the point is near it (a zero face: a point sample).
struct IrradianceSample {
  Vec3 p = Vec3::Zero();
  double area = 0;
  Rgb E = Rgb::Zero();
  std::array<Vec3, 3> face{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
};

// What pass 2 computes at a point: S, one gradient per channel, and V, the standard deviation of
// E^ over the samples within the split disk (§3.3-3.4).
struct SubsurfaceEstimate {
  Rgb S = Rgb::Zero();
  std::array<Vec3, 3> gradS{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  Rgb V = Rgb::Zero();
  std::size_t terms = 0;  // |N|
};

struct HierarchySettings {
  // m of Traverse_octree: a node seen under a smaller solid angle, area / distance^2, is one term.
  // 0 sums every sample (the brute-force sum).
  double max_solid_angle = 0.1;
  // R of the split-disk model, world units: V is taken over the terms of N within R of the point
  // (local; the seed's Eq. 3.14 sums over all of N, docs/subsurface.md §4 says why not).
  double disk_radius = 1;
};

class IrradianceOctree {
 public:
  explicit IrradianceOctree(std::vector<IrradianceSample> samples);

  SubsurfaceEstimate evaluate(const Vec3& p, const RgbDipole& dipole, const HierarchySettings& settings) const;

  const std::vector<IrradianceSample>& samples() const { return samples_; }
  std::size_t nodeCount() const { return nodes_.size(); }

 private:
  // A node's box and the sums of Eq. (3.11)-(3.13): area A, flux Phi = sum E^ A, M = sum E^2 A,
  // and the area-weighted mean position P. Leaves hold up to kLeafSize samples [begin, end).
  struct Node {
    Vec3 lo, hi, P = Vec3::Zero();
    double A = 0;
    Rgb Phi = Rgb::Zero(), M = Rgb::Zero();
    std::array<int, 8> child{-1, -1, -1, -1, -1, -1, -1, -1};
    std::size_t begin = 0, end = 0;
    bool leaf = true;
  };
  static constexpr std::size_t kLeafSize = 8;

  int build(std::size_t begin, std::size_t end, const Vec3& lo, const Vec3& hi, int depth);

  std::vector<IrradianceSample> samples_;
  std::vector<Node> nodes_;
};

}  // namespace vdbappear
