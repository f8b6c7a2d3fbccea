#include "libvdbappear/render/render_image.h"

#include "libvdbappear/cluster/process_group.h"
#include "libvdbappear/io/resource_limits.h"
#include "libvdbappear/render/path_gradients.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/util/stopwatch.h"

#include <fmt/format.h>
#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <tuple>

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
  Film(int width, int height, int clusters, int gradient_parameters, bool pixel_seconds)
      : width_(width), clusters_(clusters), parameters_(gradient_parameters), pixels_(std::size_t(width) * height),
        coverage_(std::size_t(width) * height * clusters, 0),
        gradient_sums_(std::size_t(width) * height * gradient_parameters, Rgb::Zero()),
        seconds_(pixel_seconds ? pixels_.size() : 0, 0.0) {}

  // What a render holds per pixel: the film's sums, and the result they resolve to twice over (the
  // result, and the copy an output writer makes of it).
  static std::uint64_t bytesPerPixel(int clusters, int gradient_parameters, bool pixel_seconds) {
    const std::uint64_t film = sizeof(PixelSums) + sizeof(std::uint32_t) * clusters + sizeof(Rgb) * gradient_parameters +
                               (pixel_seconds ? sizeof(double) : 0);
    const std::uint64_t result =
        sizeof(float) * (3 + 3 + 1 + clusters + 3 * std::uint64_t(gradient_parameters) + (pixel_seconds ? 1 : 0));
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

  bool timesPixels() const { return !seconds_.empty(); }
  void addSeconds(int x, int y, double seconds) { seconds_[std::size_t(y) * width_ + x] += seconds; }

  // Every rank's sums, added up on every rank. A pixel rendered by one rank alone is exact: the
  // others add zeros.
  void sumOver(const ProcessGroup& group) {
    static_assert(sizeof(Rgb) == 3 * sizeof(double), "Rgb: three packed doubles");
    std::vector<double> sums(pixels_.size() * 6);
    std::vector<std::uint32_t> collisions(pixels_.size());
    for (std::size_t i = 0; i < pixels_.size(); ++i) {
      std::copy_n(pixels_[i].sum.data(), 3, &sums[6 * i]);
      std::copy_n(pixels_[i].sum_squares.data(), 3, &sums[6 * i + 3]);
      collisions[i] = pixels_[i].collisions;
    }
    group.sum(sums.data(), sums.size());
    group.sum(collisions.data(), collisions.size());
    group.sum(coverage_.data(), coverage_.size());
    group.sum(gradient_sums_.empty() ? nullptr : gradient_sums_.front().data(), 3 * gradient_sums_.size());
    group.sum(seconds_.data(), seconds_.size());
    for (std::size_t i = 0; i < pixels_.size(); ++i) {
      std::copy_n(&sums[6 * i], 3, pixels_[i].sum.data());
      std::copy_n(&sums[6 * i + 3], 3, pixels_[i].sum_squares.data());
      pixels_[i].collisions = collisions[i];
    }
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
    if (timesPixels()) result->extra_channels.emplace_back("time", std::vector<float>(seconds_.begin(), seconds_.end()));
    if (clusters_ == 0) return;
    result->cluster_coverage.resize(coverage_.size());
    for (std::size_t i = 0; i < coverage_.size(); ++i) result->cluster_coverage[i] = float(double(coverage_[i]) / spp);
  }

 private:
  int width_, clusters_, parameters_;
  std::vector<PixelSums> pixels_;
  std::vector<std::uint32_t> coverage_;
  std::vector<Rgb> gradient_sums_;  // per pixel and parameter
  std::vector<double> seconds_;     // per pixel, with the AOV "time"
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
  const std::uint64_t bytes = std::uint64_t(settings.width) * std::uint64_t(settings.height) *
                              Film::bytesPerPixel(clusters, gradient_parameters, settings.pixel_seconds);
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

// One pass of samples [first, last) over pixels: what every tile of it shares.
class SamplePass {
 public:
  SamplePass(const RenderScene& scene, const PinholeCamera& camera, const RenderSettings& settings, int first, int last,
             Film& film, tbb::enumerable_thread_specific<ThreadState>& threads)
      : scene_(scene), camera_(camera), settings_(settings), tracer_(scene, settings.path), first_(first), last_(last),
        film_(film), threads_(threads) {
    std::tie(gradient_clusters_, gradient_lobes_) = gradientShape(scene, settings);
  }

  int samples() const { return last_ - first_; }

  // The samples of the pixels [x0, x1) x [y0, y1), on the calling thread.
  void renderPixels(int x0, int x1, int y0, int y1) const {
    ThreadState& state = threads_.local();
    if (scene_.medium && !state.lookup) state.lookup = scene_.medium->lookup();
    if (gradient_clusters_ > 0 && !state.gradients)
      state.gradients = std::make_unique<PathGradients>(gradient_clusters_, gradient_lobes_);
    for (int y = y0; y != y1; ++y)
      for (int x = x0; x != x1; ++x) {
        const std::optional<Stopwatch> clock = film_.timesPixels() ? std::optional<Stopwatch>(std::in_place) : std::nullopt;
        for (int s = first_; s < last_; ++s) {
          RandomStream rng(settings_.seed, {x, y, s});
          const Point2 jitter = rng.uniform2();
          const PathSample sample =
              tracer_.trace(camera_.ray(x + jitter.x(), y + jitter.y()), rng, state.lookup.get(), state.gradients.get());
          film_.add(x, y, sample, state.gradients.get());
          ++state.paths;
          state.events += sample.scattering_events;
        }
        if (clock) film_.addSeconds(x, y, clock->seconds());
      }
  }

 private:
  const RenderScene& scene_;
  const PinholeCamera& camera_;
  const RenderSettings& settings_;
  const VolumePathTracer tracer_;
  int first_, last_;
  int gradient_clusters_ = 0, gradient_lobes_ = 0;
  Film& film_;
  tbb::enumerable_thread_specific<ThreadState>& threads_;
};

// A pass by this process alone: TBB's blocks of about a tile.
void renderPassAlone(const SamplePass& pass, int width, int height, ProgressBar* progress) {
  constexpr int kGrain = kRenderTileSize;
  tbb::parallel_for(tbb::blocked_range2d<int>(0, height, kGrain, 0, width, kGrain), [&](const auto& block) {
    pass.renderPixels(block.cols().begin(), block.cols().end(), block.rows().begin(), block.rows().end());
    if (progress) progress->advance(std::uint64_t(block.rows().size()) * block.cols().size() * pass.samples());
  });
}

// The image's tiles of kTileSize x kTileSize pixels, numbered row by row.
constexpr int kTileSize = kRenderTileSize;
struct TileGrid {
  int width, height, columns, rows;
  TileGrid(int w, int h) : width(w), height(h), columns((w + kTileSize - 1) / kTileSize), rows((h + kTileSize - 1) / kTileSize) {}
  std::uint64_t count() const { return std::uint64_t(columns) * rows; }
  int x0(std::uint64_t t) const { return int(t % columns) * kTileSize; }
  int y0(std::uint64_t t) const { return int(t / columns) * kTileSize; }
  int x1(std::uint64_t t) const { return std::min(x0(t) + kTileSize, width); }
  int y1(std::uint64_t t) const { return std::min(y0(t) + kTileSize, height); }
  std::uint64_t pixels(std::uint64_t first, std::uint64_t last) const {
    std::uint64_t n = 0;
    for (std::uint64_t t = first; t < last; ++t) n += std::uint64_t(x1(t) - x0(t)) * (y1(t) - y0(t));
    return n;
  }
};

// Guided self-scheduling of a rank's next claim: up to 4 tiles per thread while much is left (few
// claims), down to 1 per thread as the tiles run out, so that the last batches are small and many
// ranks still find work. `claimed` is the counter as this rank last saw it.
std::uint64_t batchSize(std::uint64_t tiles, std::uint64_t claimed, int ranks, int threads) {
  const std::uint64_t left = tiles > claimed ? tiles - claimed : 0;
  const std::uint64_t per_thread = std::clamp<std::uint64_t>(left / (2 * std::uint64_t(ranks) * threads), 1, 4);
  return per_thread * std::uint64_t(threads);
}

// A pass shared by the ranks of `group`: each claims batches of tiles from a counter shared by the
// group until none is left (dynamic balancing: a tile through dense medium can cost 100 times one
// beside it). A pixel is rendered whole by the rank that claimed its tile.
void renderPassShared(const SamplePass& pass, const ProcessGroup& group, int width, int height, ProgressBar* progress,
                      RankWork* work) {
  const TileGrid tiles(width, height);
  Stopwatch clock;
  const std::unique_ptr<WorkCounter> counter = group.workCounter(tiles.count());
  const int threads = tbb::this_task_arena::max_concurrency();
  std::uint64_t shown = 0;    // the progress shows every tile claimed before this rank's last claim as done
  std::uint64_t claimed = 0;  // the counter as this rank last saw it
  std::uint64_t batch = 0;
  const auto claim = [&] {
    batch = batchSize(tiles.count(), claimed, group.size(), threads);
    const std::uint64_t first = counter->claim(batch);
    claimed = first + batch;
    work->claim_seconds += clock.lap();
    return first;
  };
  for (std::uint64_t first = claim(); first < tiles.count(); first = claim()) {
    const std::uint64_t last = std::min(first + batch, tiles.count());
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(first, last, 1), [&](const auto& range) {
      for (std::uint64_t t = range.begin(); t != range.end(); ++t) pass.renderPixels(tiles.x0(t), tiles.x1(t), tiles.y0(t), tiles.y1(t));
    });
    work->tile_seconds += clock.lap();
    if (progress) progress->advance(tiles.pixels(shown, last) * pass.samples());
    shown = last;
  }
  if (progress) progress->advance(tiles.pixels(shown, tiles.count()) * pass.samples());
}

// Samples [first, last) of every pixel, by the group's ranks together when it has several.
void renderPass(const RenderScene& scene, const PinholeCamera& camera, const RenderSettings& settings, int first,
                int last, Film& film, tbb::enumerable_thread_specific<ThreadState>& threads, ProgressBar* progress,
                RankWork* work) {
  const SamplePass pass(scene, camera, settings, first, last, film, threads);
  if (settings.group && settings.group->isShared())
    renderPassShared(pass, *settings.group, settings.width, settings.height, progress, work);
  else
    renderPassAlone(pass, settings.width, settings.height, progress);
}

// Each rank's RankWork (its paths counted by sumStatistics), on every rank.
std::vector<RankWork> everyRanksWork(const ProcessGroup& group, const RankWork& work) {
  const std::size_t n = std::size_t(group.size()), r = std::size_t(group.rank());
  std::vector<std::uint64_t> paths(n, 0);
  std::vector<double> seconds(3 * n, 0.0);
  paths[r] = work.paths;
  seconds[3 * r] = work.tile_seconds;
  seconds[3 * r + 1] = work.claim_seconds;
  seconds[3 * r + 2] = work.sum_seconds;
  group.sum(paths.data(), n);
  group.sum(seconds.data(), seconds.size());
  std::vector<RankWork> ranks(n);
  for (std::size_t i = 0; i < n; ++i) ranks[i] = {paths[i], seconds[3 * i], seconds[3 * i + 1], seconds[3 * i + 2]};
  return ranks;
}

// With --time: the samples of the next pass, sized to take about a quarter of the time left.
std::int64_t nextPassSize(const RenderSettings& settings, double elapsed, int done) {
  const double per_sample = elapsed / done;
  const double affordable = (settings.time_seconds - elapsed) / 4 / per_sample;
  return std::int64_t(std::clamp(affordable, 1.0, double(settings.spp - done)));
}

// Counts of every rank's threads, summed over the group; this rank's own paths into `work`.
void sumStatistics(const tbb::enumerable_thread_specific<ThreadState>& threads, const ProcessGroup* group,
                   RankWork* work, RenderResult* result) {
  std::uint64_t counts[4] = {0, 0, 0, 0};
  for (const ThreadState& state : threads) {
    counts[0] += state.paths;
    counts[1] += state.events;
    if (!state.lookup) continue;
    counts[2] += state.lookup->stats().tentative_collisions;
    counts[3] += state.lookup->stats().majorant_violations;
  }
  work->paths = counts[0];
  if (group) group->sum(counts, 4);
  result->paths = counts[0];
  result->scattering_events = counts[1];
  result->tracking.tentative_collisions = counts[2];
  result->tracking.majorant_violations = counts[3];
}

}  // namespace

std::vector<double> tileSeconds(const RenderResult& result) {
  const auto time = std::find_if(result.extra_channels.begin(), result.extra_channels.end(),
                                 [](const auto& channel) { return channel.first == "time"; });
  if (time == result.extra_channels.end()) return {};
  const TileGrid tiles(result.width, result.height);
  std::vector<double> seconds(tiles.count(), 0.0);
  for (int y = 0; y < result.height; ++y)
    for (int x = 0; x < result.width; ++x)
      seconds[std::size_t(y / kTileSize) * tiles.columns + x / kTileSize] += time->second[std::size_t(y) * result.width + x];
  return seconds;
}

RenderResult renderImage(const RenderScene& scene, const PinholeCamera& camera, const RenderSettings& settings,
                         ProgressBar* progress) {
  const Stopwatch clock;
  const int clusters = settings.cluster_coverage && scene.medium ? scene.medium->clusterCount() : 0;
  const auto [gradient_clusters, gradient_lobes] = gradientShape(scene, settings);
  checkRenderMemory(settings, clusters, gradient_clusters * gradient_lobes);
  Film film(settings.width, settings.height, clusters, gradient_clusters * gradient_lobes, settings.pixel_seconds);
  tbb::enumerable_thread_specific<ThreadState> threads;
  RankWork work;
  const std::uint64_t pixels = std::uint64_t(settings.width) * settings.height;
  int done = 0;
  if (settings.time_seconds > 0) {
    // Passes of samples until the time is spent: one sample first, then passes sized to take about
    // a quarter of the time left. Each sample is still keyed by its index, so a run that ends
    // with the same count is identical. (Under several ranks, a pixel's passes may fall to different
    // ranks: the same estimate, summed in another order.)
    if (progress) progress->setTotal(std::uint64_t(settings.time_seconds * 1000));
    int pass = 1;
    std::uint64_t shown_ms = 0;
    while (done < settings.spp) {
      const int last = std::min(settings.spp, done + pass);
      renderPass(scene, camera, settings, done, last, film, threads, nullptr, &work);
      done = last;
      const double elapsed = clock.seconds();
      const auto elapsed_ms = std::uint64_t(std::min(elapsed, settings.time_seconds) * 1000);
      if (progress) progress->advance(elapsed_ms - shown_ms);
      shown_ms = elapsed_ms;
      // The root's clock decides for the whole group: 0 ends the render.
      std::int64_t next = elapsed >= settings.time_seconds ? 0 : nextPassSize(settings, elapsed, done);
      if (settings.group) settings.group->broadcast(&next, 1);
      if (next == 0) break;
      pass = int(next);
    }
  } else {
    if (progress) progress->setTotal(pixels * settings.spp);
    renderPass(scene, camera, settings, 0, settings.spp, film, threads, progress, &work);
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
  if (settings.group && settings.group->isShared()) {
    Stopwatch sum_clock;
    film.sumOver(*settings.group);
    work.sum_seconds = sum_clock.seconds();
  }
  film.resolve(done, &result);
  sumStatistics(threads, settings.group, &work, &result);
  if (settings.group && settings.group->isShared()) result.ranks = everyRanksWork(*settings.group, work);
  result.seconds = clock.seconds();
  return result;
}

}  // namespace vdbappear
