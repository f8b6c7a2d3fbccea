#include "libvdbappear/render/render_image.h"

#include "libvdbappear/io/resource_limits.h"
#include "libvdbappear/render/path_gradients.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/util/stopwatch.h"

#include <fmt/format.h>
#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>

namespace vdbappear {

namespace {

// Running sums of one pixel.
struct PixelSums {
  Rgb sum = Rgb::Zero(), sum_squares = Rgb::Zero();
  std::uint32_t collisions = 0;
};

struct ThreadState {
  std::unique_ptr<MediumLookup> lookup;
  std::unique_ptr<PathGradients> gradients;
  std::uint64_t paths = 0, events = 0;
};

class Film {
 public:
  Film(int width, int height, int clusters, int gradient_parameters)
      : width_(width), clusters_(clusters), parameters_(gradient_parameters), pixels_(std::size_t(width) * height),
        coverage_(std::size_t(width) * height * clusters, 0),
        gradient_sums_(std::size_t(width) * height * gradient_parameters, Rgb::Zero()) {}

  // What a render holds per pixel: the film's sums, and the result they resolve to twice over (the
  // result, and the copy an output writer makes of it).
  static std::uint64_t bytesPerPixel(int clusters, int gradient_parameters) {
    const std::uint64_t film = sizeof(PixelSums) + sizeof(std::uint32_t) * clusters + sizeof(Rgb) * gradient_parameters;
    const std::uint64_t result = sizeof(float) * (3 + 3 + 1 + clusters + 3 * std::uint64_t(gradient_parameters));
    return film + 2 * result;
  }

  void add(int x, int y, const PathSample& s, const PathGradients* gradients) {
    const std::size_t pixel = std::size_t(y) * width_ + x;
    if (gradients) {
      const std::vector<Rgb>& dL = gradients->radianceDerivatives();
      for (int p = 0; p < parameters_; ++p) gradient_sums_[pixel * parameters_ + p] += dL[p];
    }
    PixelSums& p = pixels_[pixel];
    p.sum += s.L;
    p.collisions += s.camera_ray_collided;
    p.sum_squares += s.L * s.L;
    if (clusters_ > 0 && s.first_cluster >= 0 && s.first_cluster < clusters_)
      ++coverage_[(std::size_t(y) * width_ + x) * clusters_ + s.first_cluster];
  }

  void resolve(int spp, RenderResult* result) const {
    result->mean.assign(pixels_.size() * 3, 0.0f);
    result->variance.assign(pixels_.size() * 3, 0.0f);
    result->alpha.assign(pixels_.size(), 0.0f);
    for (std::size_t i = 0; i < pixels_.size(); ++i) {
      result->alpha[i] = float(double(pixels_[i].collisions) / spp);
      const Rgb mean = pixels_[i].sum / spp;
      const Rgb sample_variance = spp > 1 ? Rgb((pixels_[i].sum_squares - spp * mean * mean) / (spp - 1)) : Rgb(Rgb::Zero());
      for (int c = 0; c < 3; ++c) {
        result->mean[3 * i + c] = float(mean[c]);
        result->variance[3 * i + c] = float(std::max(0.0, sample_variance[c]) / spp);
      }
    }
    result->weight_gradients.resize(gradient_sums_.size() * 3);
    for (std::size_t i = 0; i < gradient_sums_.size(); ++i)
      for (int c = 0; c < 3; ++c) result->weight_gradients[3 * i + c] = float(gradient_sums_[i][c] / spp);
    if (clusters_ == 0) return;
    result->cluster_coverage.resize(coverage_.size());
    for (std::size_t i = 0; i < coverage_.size(); ++i) result->cluster_coverage[i] = float(double(coverage_[i]) / spp);
  }

 private:
  int width_, clusters_, parameters_;
  std::vector<PixelSums> pixels_;
  std::vector<std::uint32_t> coverage_;
  std::vector<Rgb> gradient_sums_;  // per pixel and parameter
};

// The (clusters, lobes) of the gradient images: both 0 when none are asked.
std::pair<int, int> gradientShape(const RenderScene& scene, const RenderSettings& settings) {
  if (!settings.weight_gradients) return {0, 0};
  if (!scene.medium || scene.medium->phaseSource() != PhaseSource::kLobes || scene.medium->clusterCount() == 0)
    throw std::invalid_argument("gradient images need a multi-lobe medium with a 'cluster' grid (vdb_lobe_cluster)");
  if (scene.sh_lights) throw std::invalid_argument("gradient images cannot be rendered with an SH light grid");
  return {scene.medium->clusterCount(), scene.medium->lobeCount()};
}

// Refuses, before anything is allocated, a render that would hold more than the limit of
// io/resource_limits.h (the machine's memory unless set).
void checkRenderMemory(const RenderSettings& settings, int clusters, int gradient_parameters) {
  const std::uint64_t bytes =
      std::uint64_t(settings.width) * std::uint64_t(settings.height) * Film::bytesPerPixel(clusters, gradient_parameters);
  const std::uint64_t limit = maxRenderBytes();
  if (bytes <= limit) return;
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  throw std::invalid_argument(fmt::format(
      "a {}x{} render{} needs about {:.2f} GiB, more than the limit of {:.2f} GiB (the machine's memory; "
      "VDBAPPEAR_MAX_RENDER_BYTES sets another)",
      settings.width, settings.height,
      gradient_parameters > 0 ? fmt::format(" with {} gradient images", gradient_parameters) : std::string(),
      double(bytes) / kGiB, double(limit) / kGiB));
}

// Samples [first, last) of every pixel.
void renderPass(const RenderScene& scene, const PinholeCamera& camera, const RenderSettings& settings, int first,
                int last, Film& film, tbb::enumerable_thread_specific<ThreadState>& threads, ProgressBar* progress) {
  const VolumePathTracer tracer(scene, settings.path);
  const std::pair<int, int> gradient_shape = gradientShape(scene, settings);  // lambdas cannot capture bindings (C++17)
  const int gradient_clusters = gradient_shape.first, gradient_lobes = gradient_shape.second;
  tbb::parallel_for(tbb::blocked_range2d<int>(0, settings.height, 8, 0, settings.width, 8), [&](const auto& tile) {
    ThreadState& state = threads.local();
    if (scene.medium && !state.lookup) state.lookup = scene.medium->lookup();
    if (gradient_clusters > 0 && !state.gradients)
      state.gradients = std::make_unique<PathGradients>(gradient_clusters, gradient_lobes);
    for (int y = tile.rows().begin(); y != tile.rows().end(); ++y)
      for (int x = tile.cols().begin(); x != tile.cols().end(); ++x)
        for (int s = first; s < last; ++s) {
          RandomStream rng(settings.seed, {x, y, s});
          const Point2 jitter = rng.uniform2();
          const PathSample sample =
              tracer.trace(camera.ray(x + jitter.x(), y + jitter.y()), rng, state.lookup.get(), state.gradients.get());
          film.add(x, y, sample, state.gradients.get());
          ++state.paths;
          state.events += sample.scattering_events;
        }
    if (progress) progress->advance(std::uint64_t(tile.rows().size()) * tile.cols().size() * (last - first));
  });
}

}  // namespace

RenderResult renderImage(const RenderScene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                         ProgressBar* progress) {
  const Stopwatch clock;
  const int clusters = settings.cluster_coverage && scene.medium ? scene.medium->clusterCount() : 0;
  const auto [gradient_clusters, gradient_lobes] = gradientShape(scene, settings);
  checkRenderMemory(settings, clusters, gradient_clusters * gradient_lobes);
  Film film(settings.width, settings.height, clusters, gradient_clusters * gradient_lobes);
  tbb::enumerable_thread_specific<ThreadState> threads;
  const std::uint64_t pixels = std::uint64_t(settings.width) * settings.height;
  int done = 0;
  if (settings.time_seconds > 0) {
    // Passes of samples until the time is spent: one sample first, then passes sized to take about
    // a quarter of the time left. Each sample is still keyed by its index, so a run that ends
    // with the same count is identical.
    if (progress) progress->setTotal(std::uint64_t(settings.time_seconds * 1000));
    int pass = 1;
    std::uint64_t shown_ms = 0;
    while (done < settings.spp) {
      const int last = std::min(settings.spp, done + pass);
      renderPass(scene, camera, settings, done, last, film, threads, nullptr);
      done = last;
      const double elapsed = clock.seconds();
      const auto elapsed_ms = std::uint64_t(std::min(elapsed, settings.time_seconds) * 1000);
      if (progress) progress->advance(elapsed_ms - shown_ms);
      shown_ms = elapsed_ms;
      if (elapsed >= settings.time_seconds) break;
      const double per_sample = elapsed / done;
      const double affordable = (settings.time_seconds - elapsed) / 4 / per_sample;
      pass = int(std::clamp(affordable, 1.0, double(settings.spp - done)));
    }
  } else {
    if (progress) progress->setTotal(pixels * settings.spp);
    renderPass(scene, camera, settings, 0, settings.spp, film, threads, progress);
    done = settings.spp;
  }
  if (progress) progress->finish();

  RenderResult result;
  result.width = settings.width;
  result.height = settings.height;
  result.spp = done;
  result.cluster_count = clusters;
  result.gradient_clusters = gradient_clusters;
  result.gradient_lobes = gradient_lobes;
  film.resolve(done, &result);
  for (const ThreadState& state : threads) {
    result.paths += state.paths;
    result.scattering_events += state.events;
    if (state.lookup) result.tracking += state.lookup->stats();
  }
  result.seconds = clock.seconds();
  return result;
}

}  // namespace vdbappear
