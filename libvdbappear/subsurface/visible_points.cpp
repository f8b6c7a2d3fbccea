#include "libvdbappear/subsurface/visible_points.h"

#include "libvdbappear/render/camera.h"
#include "libvdbappear/render/render_scene.h"

namespace vdbappear {

std::vector<std::vector<VisiblePoint>> visiblePoints(const RenderScene& scene, const PinholeCamera& camera, int width,
                                                     int height) {
  std::vector<std::vector<VisiblePoint>> points(scene.translucent.size());
  if (!scene.surfaces) return points;
  for (int y = height - 1; y >= 0; --y)
    for (int x = 0; x < width; ++x) {
      const Ray ray = camera.ray(x + 0.5, y + 0.5);
      const std::optional<SurfaceHit> hit = scene.surfaces->intersect(ray.o, ray.d, 0.0, kInfinity);
      if (!hit || hit->translucent < 0 || hit->normal.dot(ray.d) >= 0) continue;
      points[std::size_t(hit->translucent)].push_back({ray(hit->t), hit->normal, y * width + x});
    }
  return points;
}

}  // namespace vdbappear
