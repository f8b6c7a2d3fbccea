#include "libvdbappear/prefilter/displacement_prefilter.h"

#include "libvdbappear/prefilter/effective_brdf.h"
#include "libvdbappear/prefilter/multi_bounce_effective_brdf.h"
#include "libvdbappear/surface/height_downsample.h"
#include "libvdbappear/surface/multi_lobe_brdf.h"
#include "libvdbappear/surface/patch_ndf.h"
#include "libvdbappear/util/hash_random.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/util/stopwatch.h"

#include <Eigen/LU>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

namespace vdbappear {
namespace {

void checkSettings(const HeightField& fine, const DisplacementPrefilterSettings& s) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  if (s.factor < 2) fail("the factor must be at least 2");
  if (fine.cellsX() % s.factor != 0 || fine.cellsY() % s.factor != 0)
    fail("the factor " + std::to_string(s.factor) + " does not divide the map's " + std::to_string(fine.cellsX()) +
         " x " + std::to_string(fine.cellsY()) + " cells (a map of (n + 1)^2 pixels has n^2 cells)");
  if (s.normals_per_cell_side < 1 || s.samples_per_side < 1 || s.max_vertices < 1)
    fail("sample counts must be at least 1");
  for (const TileStretch& stretch : s.stretches)
    if (!(stretch.matrix().determinant() > 0) || !stretch.matrix().allFinite())
      fail("a tile's stretch must be finite with a positive determinant (it may not mirror or flatten the tile)");
  if (!(s.base_curvature >= 0) || !std::isfinite(s.base_curvature))
    fail("the base's curvature must be finite and not negative (a convex base or a plane)");
  const int coarse_cells = std::min(fine.cellsX(), fine.cellsY()) / s.factor;
  if (s.relief_radius < 0 || s.relief_radius > widestReliefRadius(coarse_cells, coarse_cells))
    fail("the relief's radius must be 0 (none) or span at most the coarse map's " + std::to_string(coarse_cells) +
         " cells (2 r + 1)");
}

// R of Eq. (4.12) or R_ir of Eq. (4.20) at coarse cell (u, v): the original's effective BRDF over
// its F x F fine cells, and the prefiltered model's on the coarse cell, each times its patch's
// visible projected area. For R, f'_low does not depend on the point (its lobes are in the base
// frame), so f_eff(G_low, f'_low) = f'_low(wi, wo) times the effective BRDF of G_low with f = 1,
// which is what is estimated. For R_ir the prefiltered model's is multi-bounce too, with paths over
// the whole coarse map: the renderer traces the interreflections between coarse cells itself, and
// Eq. (4.20)'s single-bounce denominator (the assumption of Eq. 4.19) counted them twice, a white
// furnace of white bumps came out 1.14 (docs/displacement.md §6).
class ScalingEstimator {
 public:
  // `stretch`: of the tile the estimates are for (surface/tile_stretch.h): both micro-geometries
  // laid out stretched, directions the stretched surface's, and f'_low as the model shades that
  // tile (MultiLobeBrdf::onStretchedTile). Both over a base of s.base_curvature, as the renderer
  // lays h_low and the original out over a convex surface, and with s.edges: alone or as a tile.
  ScalingEstimator(const HeightField& fine, const PrefilteredSurface& low, const MicrofacetBrdf& base,
                   const DisplacementPrefilterSettings& s, const TileStretch& stretch)
      : original_(fine, stretch, s.base_curvature, s.edges),
        prefiltered_(low.height, stretch, s.base_curvature, s.edges),
        base_(base),
        s_(s) {
    for (const VmfMixture& ndf : low.ndfs) f_low_.emplace_back(ndf, base);
    low_scattering_ = lowScattering();
    original_scattering_ = microfacetScattering(base);
  }

  ScalingSample operator()(int u, int v, std::uint64_t visit, const Vec3& wi, const Vec3& wo) const {
    const int F = s_.factor;
    const std::uint64_t seed = seedOf(u, v, visit);
    if (s_.scaling == ScalingKind::Interreflection) {
      const MultiBounceSettings m = multiBounce(seed);
      const EffectiveBrdf original = multiBounceEffectiveBrdf(original_, u * F, v * F, F, original_scattering_, wi, wo, m);
      const EffectiveBrdf low = multiBounceEffectiveBrdf(prefiltered_, u, v, 1, low_scattering_, wi, wo, m);
      return {original.value * original.visible_area, low.value * low.visible_area};
    }
    const EffectiveBrdf original =
        effectiveBrdf(original_, u * F, v * F, F, microfacetPatchBrdf(base_), wi, wo, single(seed));
    if (!stretch().isIdentity()) {  // f'_low depends on the coarse facet (its weight)
      const EffectiveBrdf low = effectiveBrdf(prefiltered_, u, v, 1, stretchedLow(u, v), wi, wo, single(seed));
      return {original.value * original.visible_area, low.value * low.visible_area};
    }
    const EffectiveBrdf geometry = effectiveBrdf(prefiltered_, u, v, 1, one(), wi, wo, single(seed));
    // Each weighted by its visible projected area toward wo (Eq. 4.8): the light the patch sends
    // toward the viewer, which is what a bin's sums compare (scaling_factorization.h).
    return {original.value * original.visible_area,
            cellBrdf(u, v).eval(wi, wo) * geometry.value * geometry.visible_area};
  }

  // The samples of every wi of `wis` at once (out[k] for wis[k]), from the same positions and paths:
  // each as operator() gives it alone, whose random streams do not depend on wi.
  void forView(int u, int v, std::uint64_t visit, const std::vector<Vec3>& wis, const Vec3& wo,
               ScalingSample* out) const {
    const int F = s_.factor;
    const std::uint64_t seed = seedOf(u, v, visit);
    if (s_.scaling == ScalingKind::Interreflection) {
      const MultiBounceSettings m = multiBounce(seed);
      const std::vector<EffectiveBrdf> original =
          multiBounceEffectiveBrdfs(original_, u * F, v * F, F, original_scattering_, wis, wo, m);
      const std::vector<EffectiveBrdf> low = multiBounceEffectiveBrdfs(prefiltered_, u, v, 1, low_scattering_, wis, wo, m);
      for (std::size_t k = 0; k < wis.size(); ++k)
        out[k] = {original[k].value * original[k].visible_area, low[k].value * low[k].visible_area};
      return;
    }
    const std::vector<EffectiveBrdf> original =
        effectiveBrdfs(original_, u * F, v * F, F, microfacetPatchBrdf(base_), wis, wo, single(seed));
    if (!stretch().isIdentity()) {
      const std::vector<EffectiveBrdf> low = effectiveBrdfs(prefiltered_, u, v, 1, stretchedLow(u, v), wis, wo, single(seed));
      for (std::size_t k = 0; k < wis.size(); ++k)
        out[k] = {original[k].value * original[k].visible_area, low[k].value * low[k].visible_area};
      return;
    }
    const std::vector<EffectiveBrdf> geometry = effectiveBrdfs(prefiltered_, u, v, 1, one(), wis, wo, single(seed));
    for (std::size_t k = 0; k < wis.size(); ++k)
      out[k] = {original[k].value * original[k].visible_area,
                cellBrdf(u, v).eval(wis[k], wo) * geometry[k].value * geometry[k].visible_area};
  }

 private:
  const MultiLobeBrdf& cellBrdf(int u, int v) const {
    return f_low_[std::size_t(u) + std::size_t(prefiltered_.field().cellsX()) * std::size_t(v)];
  }
  const TileStretch& stretch() const { return prefiltered_.stretch(); }
  // f'_low on a plane as the model shades it at coarse facet normal n_c: eval() on the square tile,
  // MultiLobeBrdf::onStretchedTile on a stretched one, both cut at the base horizon.
  Rgb lowBrdf(const MultiLobeBrdf& f, const Vec3& wi, const Vec3& wo, const Vec3& coarse_normal) const {
    if (stretch().isIdentity()) return f.eval(wi, wo);
    if (wi.z() <= 0 || wo.z() <= 0) return Rgb::Zero();
    return f.onStretchedTile(wi, wo, stretch(), coarse_normal);
  }
  PatchBrdf stretchedLow(int u, int v) const {
    return [this, &f = cellBrdf(u, v)](const Vec3&, const Vec3& normal, const Vec3& wi, const Vec3& wo) {
      return lowBrdf(f, wi, wo, normal);
    };
  }
  // f'_low on G_low for paths: the lobes of the coarse cell under each point, in the base frame,
  // with the coarse surface's cosine (as vdb_render shades it, prefilter/prefiltered_brdf.h).
  PatchScattering lowScattering() const {
    const auto cell = [this](const MicroGeometry::Point& x) -> const MultiLobeBrdf& {
      const HeightField& h = prefiltered_.field();
      return cellBrdf(std::clamp(int(x.base.x()), 0, h.cellsX() - 1), std::clamp(int(x.base.y()), 0, h.cellsY() - 1));
    };
    PatchScattering s;
    s.eval = [this, cell](const MicroGeometry::Point& x, const Vec3& wi, const Vec3& wo) {
      return lowBrdf(cell(x), wi, wo, x.normal);
    };
    s.sample = [this, cell](const MicroGeometry::Point& x, const Vec3& wo, double u_lobe, const Point2& u) {
      const MultiLobeBrdf& f = cell(x);
      BrdfSample sample = f.sample(wo, u_lobe, u);
      const double cos_n = x.normal.dot(sample.wi);
      if (sample.pdf > 0)
        sample.weight = cos_n > 0 ? Rgb(lowBrdf(f, sample.wi, wo, x.normal) * (cos_n / sample.pdf)) : Rgb(Rgb::Zero());
      return sample;
    };
    return s;
  }
  // The estimate's random numbers: of the cell and the visit (scaling_factorization.h).
  std::uint64_t seedOf(int u, int v, std::uint64_t visit) const {
    return hashKeys(s_.seed, {u, v, std::int64_t(visit)});
  }
  MultiBounceSettings multiBounce(std::uint64_t seed) const {
    MultiBounceSettings m;
    m.samples_per_side = s_.samples_per_side;
    m.max_vertices = s_.max_vertices;
    m.seed = seed;
    return m;
  }
  static PatchBrdf one() {
    return [](const Vec3&, const Vec3&, const Vec3&, const Vec3&) { return Rgb::Ones(); };
  }
  EffectiveBrdfSettings single(std::uint64_t seed) const {
    EffectiveBrdfSettings e;
    e.samples_per_side = s_.samples_per_side;
    e.seed = seed;
    return e;
  }

  MicroGeometry original_, prefiltered_;
  std::vector<MultiLobeBrdf> f_low_;  // per coarse cell
  PatchScattering low_scattering_;    // f'_low over G_low, built once (every R_ir sample uses it)
  PatchScattering original_scattering_;  // f_orig over G_orig, likewise
  const MicrofacetBrdf& base_;
  const DisplacementPrefilterSettings& s_;
};

}  // namespace

std::vector<VmfMixture> fitPatchNdfs(const HeightField& fine, const DisplacementPrefilterSettings& s) {
  checkSettings(fine, s);
  const int F = s.factor, cells_x = fine.cellsX() / F, cells_y = fine.cellsY() / F;
  std::vector<VmfMixture> ndfs(std::size_t(cells_x) * cells_y);
  tbb::parallel_for(std::size_t(0), ndfs.size(), [&](std::size_t cell) {
    const int u = int(cell % cells_x), v = int(cell / cells_x);
    ndfs[cell] = fitPatchNdf(patchMicroNormals(fine, u * F, v * F, F, s.normals_per_cell_side), s.ndf);
  });
  return ndfs;
}

PrefilteredSurface prefilterDisplacement(const HeightField& fine, const MicrofacetBrdf& base,
                                         const DisplacementPrefilterSettings& s, ProgressBar* progress) {
  checkSettings(fine, s);
  PrefilteredSurface result;
  Stopwatch clock;
  result.height = downsampleHeights(fine, {s.factor, s.smoothness_weight});  // step 1
  result.seconds.height = clock.lap();
  result.ndfs = fitPatchNdfs(fine, s);  // step 2
  result.seconds.ndfs = clock.lap();
  // Steps 3-4, for the square tile and each stretched one.
  const CellRelief relief = s.relief_radius > 0 ? cellRelief(result.height, s.relief_radius) : CellRelief();
  const auto scalingOf = [&](const TileStretch& stretch, ProgressBar* bar) {
    const ScalingEstimator R(fine, result, base, s, stretch);
    const ViewScalingSampler R_view = [&R](int u, int v, std::uint64_t visit, const std::vector<Vec3>& wis,
                                           const Vec3& wo, ScalingSample* out) { R.forView(u, v, visit, wis, wo, out); };
    return factorizeScaling(std::cref(R), result.height.cellsX(), result.height.cellsY(), s.factorization, bar, R_view,
                            relief.empty() ? nullptr : &relief);
  };
  if (progress) progress->setTotal((1 + s.stretches.size()) * tableBins(s.factorization));
  result.scaling = scalingOf(TileStretch(), progress);
  for (const TileStretch& stretch : s.stretches) result.stretched.push_back({stretch, scalingOf(stretch, progress)});
  result.seconds.scaling = clock.lap();
  return result;
}

}  // namespace vdbappear
