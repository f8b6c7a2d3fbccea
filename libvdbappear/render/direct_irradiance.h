#pragma once
// Pass 1 of the translucent-caching seed (§3.4): the irradiance at each surface point from the
// scene's lights, direct light only (as in the seed), shadowed by the scene's surfaces and its
// medium, and Fresnel-transmitted into the object.

#include "libvdbappear/subsurface/irradiance_octree.h"
#include "libvdbappear/subsurface/surface_samples.h"

#include <cstdint>
#include <vector>

namespace vdbappear {

struct RenderScene;

// E^(p) = int F_t(eta, w) L(w) cos(w) dw over the lights, by light sampling: one sample of a delta
// light, light_samples of any other (each point its own random stream keyed by seed and index, so
// the result does not depend on the thread count). The seed scales E by the diffuse transmittance
// F_dt instead; the directional F_t is exact for each incident direction (docs/subsurface.md §2).
// An SH light grid (RenderScene::sh_lights) does not light pass 1.
std::vector<IrradianceSample> directIrradiance(const std::vector<SurfacePoint>& points, double eta,
                                               const RenderScene& scene, int light_samples, std::uint64_t seed);

}  // namespace vdbappear
