#pragma once
// The training images of the weight optimisation prepared once (§6.3 of the downsampling paper):
// for each configuration, the scene of the reduced medium (re-rendered at every iteration with the
// candidate factors), the pixel sets of the restricted means (the reduced medium's `cluster` AOV,
// within the full medium's foreground: optimize/restricted_means.h),
// and the reference: the full-resolution medium's restricted means mean_k(I_r) and the
// normalisation c_r = 1 / max(mean(I_r), 0.05) per channel (Eq. 14), from a render that is cached
// on disk (optimize/reference_cache.h). Light header.

#include "libvdbappear/cluster/process_group.h"
#include "libvdbappear/optimize/reference_cache.h"
#include "libvdbappear/optimize/restricted_means.h"
#include "libvdbappear/optimize/training_set.h"
#include "libvdbappear/render/render_image.h"
#include "libvdbappear/render/render_scene.h"

#include <functional>
#include <memory>
#include <vector>

namespace vdbappear {

struct TrainingImage {
  TrainingConfig config;
  ClusterMasks masks;
  std::vector<Rgb> reference;  // mean_k(I_r), per cluster
  Rgb normalisation = Rgb::Ones();  // c_r per channel
  bool cache_hit = false;
  double reference_seconds = 0;  // rendering the reference (0 on a cache hit)
};

struct TrainingRenderSettings {
  int reference_spp = 64;
  std::uint64_t reference_seed = 0;  // fixed, so that references are shared across runs
  int mask_spp = 16;                 // camera rays per pixel for the cluster pixel sets
  PathSettings path;
};

// Render settings of a training view: its size, spp, seed and path settings.
RenderSettings trainingRenderSettings(const TrainingView& view, int spp, std::uint64_t seed, const PathSettings& path);

// The reduced medium under every training configuration, and the processes that share each of
// their renders and the references' (cluster/process_group.h; null: this process alone).
class TrainingScenes {
 public:
  TrainingScenes(std::shared_ptr<const MediumView> reduced, const std::vector<TrainingConfig>& configs,
                 const ProcessGroup* group = nullptr);
  std::size_t size() const { return configs_.size(); }
  const TrainingConfig& config(std::size_t i) const { return configs_[i]; }
  const ProcessGroup& group() const { return group_ ? *group_ : solo_; }
  // Renders configuration i with the lobe weights scaled by `scales` (null: as stored), shared by
  // the group.
  RenderResult render(std::size_t i, RenderSettings settings, std::shared_ptr<const LobeWeightScales> scales);

 private:
  std::vector<TrainingConfig> configs_;
  std::vector<RenderScene> scenes_;
  const ProcessGroup* group_;
  SoloProcessGroup solo_;  // the group when none is given
};

// The cache key of the reference of `config`: a hash of the full medium's content hash and every
// setting that changes the image.
std::string referenceKey(const std::string& full_hash, const TrainingConfig& config, const TrainingRenderSettings& settings);

// Masks from the reduced scenes, references from the cache or rendered (and stored), each render
// shared by the scenes' group. A reference is taken from the cache only when every rank finds it
// there, and only the root stores one. on_image(i) is called after each image (progress).
std::vector<TrainingImage> prepareTrainingImages(std::shared_ptr<const MediumView> full, const std::string& full_hash,
                                                 TrainingScenes& reduced, const TrainingRenderSettings& settings,
                                                 const ReferenceCache& cache,
                                                 const std::function<void(std::size_t)>& on_image = {});

}  // namespace vdbappear
