#include "libvdbappear/render/visible_points.h"

#include "libvdbappear/render/camera.h"
#include "libvdbappear/render/render_scene.h"
#include "libvdbappear/subsurface/translucent_object.h"

namespace vdbappear {

namespace {

constexpr int kMirrorBounces = 2;

// The points along one pixel's central ray: where it meets a translucent object facing it, then
// along the mirror reflection of a boundary that reflects (eta != 1), up to kMirrorBounces times.
void tracePixel(const RenderScene& scene, Ray ray, int pixel, std::vector<std::vector<VisiblePoint>>* points) {
  double reflectance = 1;  // of the reflections on the way
  for (int bounce = 0; bounce <= kMirrorBounces; ++bounce) {
    const std::optional<SurfaceHit> hit = scene.surfaces->intersect(ray.o, ray.d, bounce == 0 ? 0.0 : scene.ray_epsilon, kInfinity);
    if (!hit || hit->translucent < 0 || hit->normal.dot(ray.d) >= 0) return;
    const Vec3 p = ray(hit->t);
    (*points)[std::size_t(hit->translucent)].push_back({p, hit->normal, pixel, bounce == 0, cacheReach(reflectance)});
    const TranslucentObject& object = *scene.translucent[std::size_t(hit->translucent)];
    reflectance *= object.specularReflectance(-hit->normal.dot(ray.d));
    if (!(reflectance > 0)) return;
    ray = {p + scene.ray_epsilon * hit->normal, ray.d - 2 * ray.d.dot(hit->normal) * hit->normal};
  }
}

}  // namespace

std::vector<std::vector<VisiblePoint>> visiblePoints(const RenderScene& scene, const PinholeCamera& camera, int width,
                                                     int height) {
  std::vector<std::vector<VisiblePoint>> points(scene.translucent.size());
  if (!scene.surfaces) return points;
  for (int y = height - 1; y >= 0; --y)
    for (int x = 0; x < width; ++x) tracePixel(scene, camera.ray(x + 0.5, y + 0.5), y * width + x, &points);
  return points;
}

}  // namespace vdbappear
