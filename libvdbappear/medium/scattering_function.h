#pragma once
// What happens at a real collision in a medium: the single-scattering albedo and the phase
// function of the voxel, combined as a scaled phase function (downsampling paper, Eq. 8):
// f_s(wi -> wo) = sum_j W_j f_j(wi -> wo), whose integral over wo is the albedo sum_j W_j.
// A single-lobe voxel is the case of one lobe with W = albedo.
//
// Conventions: wi and wo both point away from the scattering point (docs/medium.md §4).

#include "libvdbappear/math/henyey_greenstein.h"
#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/sggx.h"
#include "libvdbappear/math/tabulated_phase.h"

#include <array>

namespace vdbappear {

enum class PhaseKind { kIsotropic, kHenyeyGreenstein, kSggx, kTabulated };

// One phase function lobe, of any kind.
struct PhaseLobe {
  PhaseKind kind = PhaseKind::kIsotropic;
  double g = 0;                            // kHenyeyGreenstein
  Sggx sggx;                               // kSggx
  const TabulatedPhase* table = nullptr;   // kTabulated

  double eval(const Vec3& wi, const Vec3& wo) const;
  PhaseSample sample(const Vec3& wi, const Point2& u) const;
  // The density of sample(): eval() for every lobe that samples its phase function exactly, that
  // is all but HG lobes with |g| < kHenyeyGreensteinUniformBelow (sampled uniformly).
  bool samplesItsPhase() const { return kind != PhaseKind::kHenyeyGreenstein || std::abs(g) >= kHenyeyGreensteinUniformBelow; }
  double pdf(const Vec3& wi, const Vec3& wo) const { return samplesItsPhase() ? eval(wi, wo) : 1 / (4 * kPi); }

  // Legendre moments f_l = 2 pi int p(mu) P_l(mu) dmu (similarity paper, Eq. 8) in closed form:
  // isotropic (1, 0, 0, ...) and HG (g^l). SGGX lobes depend on more than mu and tables have no
  // closed form: hasClosedFormMoments() is false for them and legendreMoment() must not be called.
  bool hasClosedFormMoments() const { return kind == PhaseKind::kIsotropic || kind == PhaseKind::kHenyeyGreenstein; }
  double legendreMoment(int l) const;
};

// A sampled scattering direction: weight = f_s / pdf (RGB), including the albedo.
struct ScatterSample {
  Vec3 wo;
  double pdf = 0;
  Rgb weight = Rgb::Zero();
};

class ScatteringFunction {
 public:
  static constexpr int kMaxLobes = 8;

  // slot: the lobe grid the lobe came from (lobe{slot}_*, docs/medium.md §5), -1 for a voxel
  // without lobe grids. Slots and the voxel's cluster say which weight factor w_kj scales the lobe
  // (Eq. 12, downsampling paper).
  void addLobe(const PhaseLobe& lobe, const Rgb& weight, int slot = -1);
  // As addLobe, with the lobe set in place: returns it, of kind isotropic until set (a caller that
  // sets kSggx sets sggx too: a reused function's lobes keep their old S).
  PhaseLobe& appendLobe(const Rgb& weight, int slot = -1);
  // No lobes and no cluster, for reuse: a path refills one function at each collision rather than
  // building and copying a new one (kMaxLobes lobes, 1.6 kB).
  void clear() {
    lobe_count_ = 0;
    cluster_ = -1;
  }
  int lobeCount() const { return lobe_count_; }
  const PhaseLobe& lobe(int j) const { return lobes_[j]; }
  const Rgb& weight(int j) const { return weights_[j]; }  // W_j
  int slot(int j) const { return slots_[j]; }
  Rgb albedo() const;  // sum_j W_j
  // W_j *= factor (the lobe pick follows the new weights).
  void scaleWeight(int j, const Rgb& factor);
  int cluster() const { return cluster_; }  // the voxel's cluster c(i), -1 for none
  void setCluster(int k) { cluster_ = k; }

  Rgb eval(const Vec3& wi, const Vec3& wo) const;  // f_s, RGB
  // f_s, and per lobe its term W_j f_j(wi -> wo) in per_lobe[0 .. lobeCount()-1]: the derivative of
  // f_s with respect to the log of lobe j's weight (Appendix A, downsampling paper).
  Rgb evalLobes(const Vec3& wi, const Vec3& wo, Rgb* per_lobe) const;
  // The density of sample(): a lobe is picked with probability proportional to the mean of its
  // weight, so pdf = sum_j P(j) f_j.
  double pdf(const Vec3& wi, const Vec3& wo) const;
  // u_lobe picks the lobe; u samples the direction from it. weight = eval / pdf over all lobes
  // (one-sample MIS across lobes: lower variance than W_j / P(j)). per_lobe, when given, receives
  // evalLobes' terms at the sampled direction, from the same phase evaluations (gradient images).
  ScatterSample sample(const Vec3& wi, double u_lobe, const Point2& u, Rgb* per_lobe = nullptr) const;

 private:
  std::array<double, kMaxLobes> pickProbabilities() const;

  std::array<PhaseLobe, kMaxLobes> lobes_;
  std::array<Rgb, kMaxLobes> weights_;
  std::array<int, kMaxLobes> slots_{};
  int lobe_count_ = 0;
  int cluster_ = -1;
};

}  // namespace vdbappear
