#pragma once
// A visible point of pass 2 (§3.4 of the translucent-caching seed): where a pixel's central camera
// ray first meets a translucent object, or its mirror reflection does (render/visible_points.h).

#include "libvdbappear/math/vector.h"

namespace vdbappear {

struct VisiblePoint {
  Vec3 p, normal;       // outward unit normal
  int pixel = 0;        // y * width + x, row 0 at the top
  bool direct = true;   // on the pixel's central ray itself, not seen in a mirror reflection
  double reach = 1;     // cacheReach of the reflections on the way (1 for a direct point)
};

}  // namespace vdbappear
