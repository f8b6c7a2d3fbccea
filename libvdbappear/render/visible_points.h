#pragma once
// The visible points X of pass 2 (§3.4 of the translucent-caching seed): where each pixel's central
// camera ray first meets a translucent object, facing it, in the seed's bottom-up scan-line order;
// and, beyond the seed, where its mirror reflection off a translucent boundary (eta != 1) meets one,
// up to two reflections, after the pixel's own point. Paths reach those points in pass 3 too (the
// boundary reflects specularly), and without caches there they would be integrated.

#include "libvdbappear/subsurface/visible_point.h"

#include <vector>

namespace vdbappear {

class PinholeCamera;
struct RenderScene;

// One list per translucent object (RenderScene::translucent), rows from the bottom, left to right.
std::vector<std::vector<VisiblePoint>> visiblePoints(const RenderScene& scene, const PinholeCamera& camera, int width,
                                                     int height);

}  // namespace vdbappear
