#pragma once
// The multi-lobe BRDF of Eq. (4.5) in the displacement chapter (shared/papers/002_6a636dc24396287c.txt,
// after Han et al. 2007), the initial prefiltered SVBRDF f'_low of Eq. (4.11) for one patch:
//   rho(wi, wo; D, f) = 1 / cos theta_i int f(R_w(wi), R_w(wo)) <w, wi> D(w) dw,
// the base BRDF f seen through micro-normals distributed as D, with no shadowing, masking or
// interreflection (which the scaling function restores, Eq. 4.12-4.13).

#include "libvdbappear/math/frame.h"
#include "libvdbappear/surface/microfacet_brdf.h"
#include "libvdbappear/surface/vmf_ndf.h"

#include <vector>

namespace vdbappear {

class MultiLobeBrdf {
 public:
  // D's lobes are represented by samples_per_side^2 stratified micro-normals each (sampleVmf at
  // cell-centred points of a grid on [0,1)^2), weighted alpha_k / samples: a fixed quadrature, so
  // eval() is deterministic and smooth in wi and wo.
  MultiLobeBrdf(const VmfMixture& ndf, const MicrofacetBrdf& base, int samples_per_side = 16);

  // Eq. (4.5), wi and wo in the macro-surface's frame (n = +z); zero below its horizon. R_w takes
  // directions into the frame of the micro-normal w, where f is evaluated.
  Rgb eval(const Vec3& wi, const Vec3& wo) const;

 private:
  struct MicroNormal {
    Frame frame;
    double weight;  // alpha_k / samples
  };
  std::vector<MicroNormal> normals_;
  MicrofacetBrdf base_;
};

}  // namespace vdbappear
