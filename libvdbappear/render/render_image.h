#pragma once
// Renders an image: pixels in parallel (TBB), each sample of each pixel from its own random stream
// keyed by (seed, x, y, sample index), so the image is bit-identical for any thread count.

#include "libvdbappear/render/camera.h"
#include "libvdbappear/render/volume_path_tracer.h"

#include <cstdint>
#include <vector>

namespace vdbappear {

class ProgressBar;

struct RenderSettings {
  int width = 256, height = 256;
  int spp = 16;               // samples per pixel; with time_seconds > 0, the most to take
  double time_seconds = 0;    // > 0: render passes of samples until this much time has passed
  std::uint64_t seed = 0;
  PathSettings path;
  bool cluster_coverage = false;  // AOV: per cluster, the share of samples whose camera ray scatters in it
};

struct RenderResult {
  int width = 0, height = 0, spp = 0;
  std::vector<float> mean;      // RGB per pixel, row 0 at the top
  std::vector<float> variance;  // RGB per pixel: variance of the pixel mean (sample variance / spp)
  int cluster_count = 0;
  std::vector<float> cluster_coverage;  // cluster_count values per pixel, when requested
  // Per pixel, the share of camera rays with a real collision in the medium: an estimate of
  // 1 - transmittance along the pixel, the medium's alpha (surfaces in front count as no collision).
  std::vector<float> alpha;
  double seconds = 0;
  std::uint64_t paths = 0, scattering_events = 0;
  TrackingStats tracking;
};

RenderResult renderImage(const RenderScene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                         ProgressBar* progress = nullptr);

}  // namespace vdbappear
