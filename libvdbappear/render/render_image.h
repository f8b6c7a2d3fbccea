#pragma once
// Renders an image: pixels in parallel (TBB), each sample of each pixel from its own random stream
// keyed by (seed, x, y, sample index), so the image is bit-identical for any thread count. Given a
// process group of several ranks (cluster/process_group.h), the ranks share the image's tiles
// through a shared counter and sum their films: every pixel is still taken whole by one process, so
// the image is bit-identical for any rank count too (docs/scaling.md).

#include "libvdbappear/render/camera.h"
#include "libvdbappear/render/volume_path_tracer.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace vdbappear {

class ProcessGroup;
class ProgressBar;

struct RenderSettings {
  int width = 256, height = 256;
  int spp = 16;               // samples per pixel; with time_seconds > 0, the most to take
  double time_seconds = 0;    // > 0: render passes of samples until this much time has passed
  std::uint64_t seed = 0;
  PathSettings path;
  bool cluster_coverage = false;  // AOV: per cluster, the share of samples whose camera ray scatters in it
  // Gradient images (render/path_gradients.h) of every (cluster, lobe slot) of a multi-lobe medium
  // with a `cluster` grid, from the same paths as the image.
  bool weight_gradients = false;
  // AOV "time" (RenderResult::extra_channels): the wall-clock seconds spent on each pixel's samples,
  // on whichever thread and rank took it.
  bool pixel_seconds = false;
  // The processes that share this render (every one of them calls renderImage with the same
  // arguments, and every one gets the whole result); null: this process alone.
  const ProcessGroup* group = nullptr;
};

// One rank's share of a render shared by a process group: its paths, and its seconds rendering
// tiles, claiming them from the shared counter, and in the final sum of the films (which includes
// waiting there for the slowest rank).
struct RankWork {
  std::uint64_t paths = 0;
  double tile_seconds = 0, claim_seconds = 0, sum_seconds = 0;
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
  // With weight_gradients: gradient_clusters * gradient_lobes parameters p = k * lobes + j, and per
  // pixel, parameter and channel (in that order) dI/de_p, the derivative of the pixel with respect
  // to a relative change of the weights of lobe slot j in cluster k (W -> W (1 + e)).
  int gradient_clusters = 0, gradient_lobes = 0;
  std::vector<float> weight_gradients;
  // Further named channels, one value per pixel, written after the others (the subsurface AOVs,
  // render/subsurface_passes.h).
  std::vector<std::pair<std::string, std::vector<float>>> extra_channels;
  double seconds = 0;
  std::uint64_t paths = 0, scattering_events = 0;
  std::vector<RankWork> ranks;  // per rank, when a group of several shared the render
  TrackingStats tracking;
};

// The side of the square tiles in which the ranks of a group claim the image.
constexpr int kRenderTileSize = 8;

// With the AOV "time": the seconds spent on each tile of kRenderTileSize pixels (row by row of
// tiles), the units of work the ranks of a group share; empty without it.
std::vector<double> tileSeconds(const RenderResult& result);

// `progress` shows the work of the whole group (give it on one rank only). Throws
// std::invalid_argument when gradients are asked of a scene that has none to give (no lobe
// or cluster grids) or that takes light from an SH grid.
RenderResult renderImage(const RenderScene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                         ProgressBar* progress = nullptr);

}  // namespace vdbappear
