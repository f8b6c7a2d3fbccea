#pragma once
// Pass 2 of the translucent-caching seed (§3.3-3.4): caches of S, grad S and V wherever a visible
// point finds no valid cache, visited in a fixed order, each valid within the radius that the
// split-disk bound (Eq. 3.10) allows for the error a.

#include "libvdbappear/subsurface/illuminance_cache.h"
#include "libvdbappear/subsurface/irradiance_octree.h"
#include "libvdbappear/subsurface/visible_point.h"

#include <memory>
#include <vector>

namespace vdbappear {

struct RgbDipole;
class TranslucentObject;
struct SubsurfaceSettings;

// r_k = a S_k / (V_k |dS/du|_1) per channel, where |dS/du|_1 is the split disk's slope per unit V
// (DipoleProfile::splitDiskSlope), the smallest over the channels, clamped to [min_radius,
// max_radius] diffusion lengths. The seed's a is an absolute bound on S (w_k > 1/a with w = 1 /
// epsilon); here it is relative to S_k, so that the caches do not depend on the lights' scale
// (docs/subsurface.md §6).
double cacheRadius(const SubsurfaceEstimate& estimate, const RgbDipole& dipole, const SubsurfaceSettings& settings);

struct CachePass {
  std::shared_ptr<IlluminanceCache> cache;
  std::vector<int> generated_pixels;  // the pixels whose own central point made a cache, in order
  // With one_pass: S at each visible point as a one-pass scan would shade it, from the caches made
  // before it (or its own new cache): the seed's §3.5 comparison.
  std::vector<Rgb> one_pass;
};

// The caches of one object over its visible points, in their order (single-threaded, so that the
// caches do not depend on the thread count).
CachePass generateCaches(const TranslucentObject& object, const std::vector<VisiblePoint>& points,
                         const SubsurfaceSettings& settings, bool one_pass = false);

}  // namespace vdbappear
