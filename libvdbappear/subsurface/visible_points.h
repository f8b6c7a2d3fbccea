#pragma once
// The visible points X of pass 2 (§3.4 of the translucent-caching seed): where each pixel's central
// camera ray first meets a translucent object, facing it, in the seed's bottom-up scan-line order.

#include "libvdbappear/math/vector.h"

#include <vector>

namespace vdbappear {

class PinholeCamera;
struct RenderScene;

struct VisiblePoint {
  Vec3 p, normal;  // outward unit normal
  int pixel = 0;   // y * width + x, row 0 at the top
};

// One list per translucent object (RenderScene::translucent), rows from the bottom, left to right.
std::vector<std::vector<VisiblePoint>> visiblePoints(const RenderScene& scene, const PinholeCamera& camera, int width,
                                                     int height);

}  // namespace vdbappear
