#pragma once
// Pass 2 for every translucent object of a scene, before the render (which is pass 3), and what
// the seed reports of it (Table 4.1: N, C, H, C/H; Figs. 4.2, 4.4, 4.5: where the caches are,
// |grad S| and V per pixel).

#include "libvdbappear/subsurface/translucent_object.h"

#include <string>
#include <utility>
#include <vector>

namespace vdbappear {

class PinholeCamera;
struct RenderScene;

struct SubsurfaceObjectStats {
  std::size_t irradiance_samples = 0;  // N
  std::size_t caches = 0;              // C
  std::size_t hit_pixels = 0;          // H: pixels whose central ray meets the object
  double pass1_seconds = 0, pass2_seconds = 0;
};

struct SubsurfaceCaching {
  std::vector<SubsurfaceObjectStats> objects;
  // With channels, per pixel (row 0 at the top; 0 off the objects) at the pixel's centre:
  // "sss.hit" 1 on a translucent object; "sss.cache" 1 where a cache was made; "sss.S.R/G/B" S as
  // the render uses it (pass 3: interpolated, or integrated where no cache serves or without
  // caches); "sss.S1.R/G/B" S as a one-pass scan gives it (only the caches made before the pixel;
  // the seed's §3.5); "sss.gradS.R/G/B" |grad S| (tangential) and "sss.V.R/G/B" V, interpolated
  // from the caches.
  std::vector<std::pair<std::string, std::vector<float>>> channels;
};

// Refuses (std::invalid_argument) subsurface channels that would not fit the render memory limit
// (io/resource_limits.h) beside the render: 14 floats per pixel, held twice while they are made.
void checkSubsurfaceChannelMemory(int width, int height);

// Runs pass 2 for each object with settings.cache_error > 0 (a fixed order: objects in scene
// order, each over its visible points in bottom-up scan lines) and attaches the caches.
SubsurfaceCaching cacheTranslucentObjects(RenderScene& scene, const PinholeCamera& camera, int width, int height,
                                          const SubsurfaceSettings& settings, bool with_channels = false);

}  // namespace vdbappear
