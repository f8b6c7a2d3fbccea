#include "libvdbappear/render/subsurface_passes.h"

#include "libvdbappear/io/resource_limits.h"
#include "libvdbappear/render/render_scene.h"
#include "libvdbappear/subsurface/cache_generation.h"
#include "libvdbappear/render/visible_points.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <optional>

namespace vdbappear {

namespace {

// The AOVs at the visible points (pixel centres): where caches were made, S as pass 3 gives it
// (from the caches, or integrated where none is valid or there is no cache), S as a one-pass scan
// would have given it, and the caches' |grad S| and V.
struct PixelChannels {
  std::vector<float> hit, cache, S, S_one_pass, gradS, V;  // 1 or 3 values per pixel

  explicit PixelChannels(std::size_t pixels)
      : hit(pixels, 0.0f), cache(pixels, 0.0f), S(3 * pixels, 0.0f), S_one_pass(3 * pixels, 0.0f),
        gradS(3 * pixels, 0.0f), V(3 * pixels, 0.0f) {}

  void add(const TranslucentObject& object, const std::vector<VisiblePoint>& points, const CachePass* pass) {
    if (pass)
      for (int pixel : pass->generated_pixels) cache[std::size_t(pixel)] = 1;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const VisiblePoint& v = points[k];
      if (!v.direct) continue;
      const std::size_t i = std::size_t(v.pixel);
      hit[i] = 1;
      std::optional<SubsurfaceEstimate> at;
      if (pass) at = pass->cache->interpolate(v.p, v.normal);
      const Rgb S_here = at ? at->S : object.estimate(v.p).S;  // as illuminance(), uncounted
      const Rgb S_one = pass ? pass->one_pass[k] : S_here;
      for (int c = 0; c < 3; ++c) {
        S[3 * i + c] = float(S_here[c]);
        S_one_pass[3 * i + c] = float(S_one[c]);
        if (!at) continue;
        gradS[3 * i + c] = float(at->gradS[c].norm());
        V[3 * i + c] = float(at->V[c]);
      }
    }
  }
};

std::vector<float> channelOf(const std::vector<float>& rgb, int c) {
  std::vector<float> out(rgb.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = rgb[3 * i + std::size_t(c)];
  return out;
}

}  // namespace

void checkSubsurfaceChannelMemory(int width, int height) {
  const std::uint64_t bytes = std::uint64_t(width) * std::uint64_t(height) * 14 * sizeof(float) * 2;
  if (bytes <= maxRenderBytes() / 2) return;
  throw std::invalid_argument(fmt::format("--aov sss at {}x{} needs about {:.2f} GiB, more than half the render memory "
                                          "limit (VDBAPPEAR_MAX_RENDER_BYTES)",
                                          width, height, double(bytes) / (1024.0 * 1024.0 * 1024.0)));
}

SubsurfaceCaching cacheTranslucentObjects(RenderScene& scene, const PinholeCamera& camera, int width, int height,
                                          const SubsurfaceSettings& settings, bool with_channels) {
  SubsurfaceCaching result;
  if (scene.translucent.empty()) return result;
  const std::vector<std::vector<VisiblePoint>> points = visiblePoints(scene, camera, width, height);
  PixelChannels pixels(std::size_t(width) * std::size_t(height));
  for (std::size_t i = 0; i < scene.translucent.size(); ++i) {
    TranslucentObject& object = *scene.translucent[i];
    SubsurfaceObjectStats stats;
    stats.irradiance_samples = object.octree().samples().size();
    stats.hit_pixels = std::size_t(std::count_if(points[i].begin(), points[i].end(), [](const VisiblePoint& v) { return v.direct; }));
    stats.pass1_seconds = object.pass1Seconds();
    std::optional<CachePass> pass;
    if (settings.cache_error > 0) {
      const auto start = std::chrono::steady_clock::now();
      pass = generateCaches(object, points[i], settings, with_channels);
      stats.pass2_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      stats.caches = pass->cache->entries().size();
      object.setCache(pass->cache);
    }
    if (with_channels) pixels.add(object, points[i], pass ? &*pass : nullptr);
    result.objects.push_back(stats);
  }
  if (!with_channels) return result;
  result.channels.emplace_back("sss.hit", pixels.hit);
  result.channels.emplace_back("sss.cache", pixels.cache);
  const auto add_rgb = [&](const char* name, const std::vector<float>& rgb) {
    for (int c = 0; c < 3; ++c) result.channels.emplace_back(std::string(name) + "." + "RGB"[c], channelOf(rgb, c));
  };
  add_rgb("sss.S", pixels.S);
  add_rgb("sss.S1", pixels.S_one_pass);
  add_rgb("sss.gradS", pixels.gradS);
  add_rgb("sss.V", pixels.V);
  return result;
}

}  // namespace vdbappear
