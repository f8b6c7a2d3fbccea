#include "libvdbappear/prefilter/scaling_function.h"

namespace vdbappear {

Rgb scalingFactor(const PatchPair& patches, int u, int v, const PatchBrdf& f_orig, const PatchBrdf& f_low,
                  const Vec3& wi, const Vec3& wo, const EffectiveBrdfSettings& settings, double epsilon) {
  const int F = patches.factor;
  const Rgb original = effectiveBrdf(patches.original, u * F, v * F, F, f_orig, wi, wo, settings).value;
  const Rgb prefiltered = effectiveBrdf(patches.low, u, v, 1, f_low, wi, wo, settings).value;
  return original / (prefiltered + epsilon);
}

}  // namespace vdbappear
