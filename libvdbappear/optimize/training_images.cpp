#include "libvdbappear/optimize/training_images.h"

#include "libvdbappear/render/scene_description.h"
#include "libvdbappear/version.h"

#include <stdexcept>

namespace vdbappear {

namespace {

RenderScene sceneOf(std::shared_ptr<const MediumView> medium, const TrainingConfig& config) {
  SceneDescription description;
  description.lights = config.lighting.lights;
  if (config.lighting.ground) description.ground = GroundDescription{config.ground_height, Rgb::Constant(0.5), std::nullopt};
  return buildRenderScene(description, std::move(medium), [](const std::string& file) -> RgbImage {
    throw std::runtime_error("training lights read no images (" + file + ")");
  });
}

nlohmann::json vectorJson(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

RenderSettings trainingRenderSettings(const TrainingView& view, int spp, std::uint64_t seed, const PathSettings& path) {
  RenderSettings s;
  s.width = view.width;
  s.height = view.height;
  s.spp = spp;
  s.seed = seed;
  s.path = path;
  return s;
}

TrainingScenes::TrainingScenes(std::shared_ptr<const MediumView> reduced, const std::vector<TrainingConfig>& configs,
                               const ProcessGroup* group)
    : configs_(configs), group_(group) {
  for (const TrainingConfig& config : configs_) scenes_.push_back(sceneOf(reduced, config));
}

RenderResult TrainingScenes::render(std::size_t i, RenderSettings settings, std::shared_ptr<const LobeWeightScales> scales) {
  settings.group = group_;
  RenderScene& scene = scenes_.at(i);
  scene.lobe_scales = std::move(scales);
  const TrainingView& view = configs_[i].view;
  return renderImage(scene, PinholeCamera(view.pose, view.width, view.height), settings);
}

std::string referenceKey(const std::string& full_hash, const TrainingConfig& config, const TrainingRenderSettings& s) {
  const CameraPose& pose = config.view.pose;
  const nlohmann::json key = {
      {"medium", full_hash},
      {"camera", {vectorJson(pose.position), vectorJson(pose.target), vectorJson(pose.up), pose.fov_degrees}},
      {"size", {config.view.width, config.view.height}},
      {"lights", config.lighting.lights},
      {"ground", config.lighting.ground ? nlohmann::json(config.ground_height) : nlohmann::json()},
      {"spp", s.reference_spp},
      {"seed", s.reference_seed},
      {"max_depth", s.path.max_depth},
      {"roulette_depth", s.path.roulette_depth},
      {"strategy", lightStrategyName(s.path.strategy)},
      {"version", kVersion}};
  return hashText(key.dump());
}

std::vector<TrainingImage> prepareTrainingImages(std::shared_ptr<const MediumView> full, const std::string& full_hash,
                                                 TrainingScenes& reduced, const TrainingRenderSettings& settings,
                                                 const ReferenceCache& cache,
                                                 const std::function<void(std::size_t)>& on_image) {
  const ProcessGroup& group = reduced.group();
  std::vector<TrainingImage> images;
  for (std::size_t i = 0; i < reduced.size(); ++i) {
    TrainingImage image;
    image.config = reduced.config(i);
    const TrainingView& view = image.config.view;
    // Pixel sets: where the reduced medium's clusters are directly visible (camera rays only).
    RenderSettings coverage = trainingRenderSettings(view, settings.mask_spp, settings.reference_seed, settings.path);
    coverage.cluster_coverage = true;
    coverage.path.max_depth = 0;
    image.masks = ClusterMasks(reduced.render(i, coverage, nullptr));
    // The reference image of the full medium (RGB and alpha): cached, or rendered and stored.
    const std::string key = referenceKey(full_hash, image.config, settings);
    CachedImage reference;
    // A damaged entry ends every rank at once. Every rank renders, or none: a rank may miss what
    // another finds (a job beside this one storing it).
    std::optional<CachedImage> cached;
    group.together([&] {
      cached = cache.find(key);
      if (cached && (cached->width != view.width || cached->height != view.height)) cached.reset();
    });
    if (group.firstFailingRank(!cached) < 0) {
      reference = std::move(*cached);
      image.cache_hit = true;
    } else {
      const RenderScene scene = sceneOf(full, image.config);
      RenderSettings render_settings = trainingRenderSettings(view, settings.reference_spp, settings.reference_seed, settings.path);
      render_settings.group = &group;
      const RenderResult r = renderImage(scene, PinholeCamera(view.pose, view.width, view.height), render_settings);
      reference = {view.width, view.height, {}};
      for (std::size_t p = 0; p < r.alpha.size(); ++p)
        reference.rgba.insert(reference.rgba.end(), {r.mean[3 * p], r.mean[3 * p + 1], r.mean[3 * p + 2], r.alpha[p]});
      image.reference_seconds = r.seconds;
      if (group.isRoot()) cache.store(key, reference);
    }
    std::vector<float> rgb, alpha;
    for (std::size_t p = 0; p < reference.rgba.size() / 4; ++p) {
      rgb.insert(rgb.end(), {reference.rgba[4 * p], reference.rgba[4 * p + 1], reference.rgba[4 * p + 2]});
      alpha.push_back(reference.rgba[4 * p + 3]);
    }
    image.masks.restrictToForeground(alpha);
    image.reference = restrictedMeans(rgb, image.masks);
    const Rgb mean = foregroundMean(rgb, image.masks);
    image.normalisation = mean.max(0.05).inverse();
    images.push_back(std::move(image));
    if (on_image) on_image(i);
  }
  return images;
}

}  // namespace vdbappear
