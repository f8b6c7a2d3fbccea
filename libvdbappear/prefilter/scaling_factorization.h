#pragma once
// The efficient rank-1 factorisation of the scaling function, Eq. (4.22)-(4.24) of the displacement
// chapter (shared/papers/002_6a636dc24396287c.txt, §4.6-4.7.1), from sparse samples of R_ir rather
// than the full 6-D function:
//   T_ir(x)       = 1/C int int R_ir(x, wi, wo) dwi dwo            (Eq. 4.22, C of Eq. 4.23),
//   S_ir(wi, wo)  = int_P_all R_ir(x_m(p), wi, wo) k(p) dp         (Eq. 4.24).
// T's bins average R over random positions in the bin and direction pairs drawn cosine-weighted,
// then are scaled to average one; S's bins average R at the bin's directions over stratified
// positions of the whole map (optionally the same positions and paths for every wi of one wo). Their product reproduces a separable R exactly (Appendix B.2).
//
// Each average is weighted by R's denominator: a bin is sum(original) / sum(prefiltered) over its
// samples, the scaling that gives the samples together the original's reflected light. The plain
// mean of ratios that Eq. (4.22)-(4.24) write is ruled by the samples where the coarse cell barely
// reflects (it faces away from the light while some of its micro-facets do not): on the relief of
// vdb_make_height_map such bins reached 1e5. prefilterDisplacement() passes each effective BRDF
// times its patch's visible projected area (Eq. 4.8), so that the patches count as they do in an
// image: by the area they show the viewer.

#include "libvdbappear/prefilter/scaling_tables.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace vdbappear {

class ProgressBar;

// R_ir = original / prefiltered at coarse cell (u, v) for a direction pair (Eq. 4.12 or 4.20): the
// two effective BRDFs, kept apart.
struct ScalingSample {
  Rgb original = Rgb::Zero();     // f_eff or f_ir_eff of G_orig with f_orig (times a weight)
  Rgb prefiltered = Rgb::Zero();  // f_eff of G_low with f'_low (times the same or a like weight)
};
// Called from several threads. `visit` keys the estimate's random numbers: each position of each
// bin has a visit of its own, so that two positions of a bin in one coarse cell are independent
// estimates (keyed by the cell alone, a bin of more positions than the map has cells counted each
// estimate again, and gained nothing from them; docs/displacement.md §6), and so are the positions
// of two bins in one cell (keyed by the position's number alone, the bins' errors moved together).
using ScalingSampler = std::function<ScalingSample(int u, int v, std::uint64_t visit, const Vec3& wi, const Vec3& wo)>;
// The samples of one view wo and many light directions at once: out[k] for wis[k]. Where one
// estimate serves them all (a path's directions do not depend on wi) this costs little more than
// one; sampledPerLight() makes one from a ScalingSampler, a call per wi.
using ViewScalingSampler = std::function<void(int u, int v, std::uint64_t visit, const std::vector<Vec3>& wis,
                                              const Vec3& wo, ScalingSample* out)>;
ViewScalingSampler sampledPerLight(ScalingSampler R);

// Which estimates the tables draw, recorded in the files' settings ("table_sampling") so that a
// table made before a change of them is not taken for one made after: 2 since 2026-12-01 (each
// position of each S bin its own estimate); 1 or none before (the k-th positions of all bins shared
// one where they met the same coarse cell).
constexpr int kTableSampling = 2;

struct FactorizationSettings {  // defaults: the chapter's (§4.6, §4.7.1)
  int spatial_resolution = 4;         // M
  int angular_resolution = 15;        // N
  int pairs_per_spatial_bin = 5000;   // (wi, wo) pairs per T bin
  int positions_per_angular_bin = 16; // stratified p per S bin
  // Directions beyond this are evaluated at it (same azimuth). Footnote 5 excludes theta > 75
  // degrees, where a mean of ratios is unstable; the ratios of sums here are not, and evaluated at
  // 75 the bins toward the horizon over-lit a white furnace of white bumps (rendered albedo 1.049
  // with N = 9 against the original's 0.982; at 89 degrees 1.022).
  double max_theta_degrees = 89;
  // With a polar angle here (degrees, below 90), S also has nodes of wo on the horizon, its values
  // R at this angle (AngularScaling::view_horizon); 0: none, S clamped beyond its outermost bins.
  double view_horizon_degrees = 0;
  double epsilon = 1e-6;  // footnote 2: added to both sums of a bin, so that 0 / 0 gives 1
  // The most an S bin may scale: where the prefiltered model reflects almost nothing of what the
  // original does (a coarse map that the light grazes, all in shadow, while the original's peaks
  // catch it), the ratio is no scaling the model can carry. Uncapped, the woven map at 32x had
  // bins of 3.5e6 and rendered 567 times too bright (docs/displacement.md §6).
  double max_scaling = 20;
  // S's bins with the O(1/n) bias of a ratio over n positions removed by the jackknife. Few
  // positions bias S bright, but under one sun the few bins it reads are noisier than biased at the
  // positions that make S usable; on the maps measured it moved the image by -0.03% to -0.24% at
  // 1024 positions (docs/displacement.md §9). T's bins, of many pairs each, are always plain.
  bool jackknife = false;
  // S's bins of one wo over the same positions and paths for every wi (a path's directions do not
  // depend on wi): the tables in less time, but their noise alike along wi (one view's bins move
  // together), which an image under a sky averages less than a sun's few bins
  // (docs/displacement.md §6). Off: each bin's own positions.
  bool shared_positions = false;
  std::uint64_t seed = 1;
};

// Over a map of cells_x x cells_y coarse cells. T's bins from R; S's bins from R, or with
// shared_positions those of one wo from R_view (R a call per wi when it is empty). Deterministic
// under the seed for any thread count. `progress` advances by one per bin (tableBins()); its total
// is the caller's to set.
//
// With `relief` (h_low's, of the same cells) each S bin also fits the relief term: R = S + B z over
// its samples (weighted least squares of their ratios on their cells' z, weights the model's
// light), storing the intercept and B (AngularScaling::relief_slopes); the result keeps the relief.
// T's bins are as without it (their positions span the map's relief evenly).
FactorizedScaling factorizeScaling(const ScalingSampler& R, int cells_x, int cells_y,
                                   const FactorizationSettings& settings, ProgressBar* progress = nullptr,
                                   const ViewScalingSampler& R_view = {}, const CellRelief* relief = nullptr);

// The bins of T and S together: M^2 + N^4, or M^2 + N^2 (N + 2)^2 with the view's horizon nodes.
std::uint64_t tableBins(const FactorizationSettings& settings);

// w with its polar angle limited to max_theta (radians), keeping its azimuth.
Vec3 limitPolarAngle(const Vec3& w, double max_theta);

}  // namespace vdbappear
