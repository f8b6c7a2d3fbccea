#pragma once
// What happens at a real collision in a medium: the single-scattering albedo and the phase
// function of the voxel, combined as a scaled phase function (downsampling paper, Eq. 8):
// f_s(wi -> wo) = sum_j W_j f_j(wi -> wo), whose integral over wo is the albedo sum_j W_j.
// A single-lobe voxel is the case of one lobe with W = albedo.
//
// Conventions: wi and wo both point away from the scattering point (docs/medium.md §4).

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

  double eval(const Vec3& wi, const Vec3& wo) const;  // also the pdf of sample()
  PhaseSample sample(const Vec3& wi, const Point2& u) const;

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

  void addLobe(const PhaseLobe& lobe, const Rgb& weight);
  int lobeCount() const { return lobe_count_; }
  const PhaseLobe& lobe(int j) const { return lobes_[j]; }
  const Rgb& weight(int j) const { return weights_[j]; }  // W_j
  Rgb albedo() const;  // sum_j W_j

  Rgb eval(const Vec3& wi, const Vec3& wo) const;  // f_s, RGB
  // The density of sample(): a lobe is picked with probability proportional to the mean of its
  // weight, so pdf = sum_j P(j) f_j.
  double pdf(const Vec3& wi, const Vec3& wo) const;
  // u_lobe picks the lobe; u samples the direction from it. weight = eval / pdf over all lobes
  // (one-sample MIS across lobes: lower variance than W_j / P(j)).
  ScatterSample sample(const Vec3& wi, double u_lobe, const Point2& u) const;

 private:
  std::array<PhaseLobe, kMaxLobes> lobes_;
  std::array<Rgb, kMaxLobes> weights_;
  std::array<double, kMaxLobes> pick_probability_{};
  int lobe_count_ = 0;
};

}  // namespace vdbappear
