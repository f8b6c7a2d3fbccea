#include "libvdbappear/surface/multi_lobe_brdf.h"

#include <algorithm>
#include <stdexcept>

namespace vdbappear {

MultiLobeBrdf::MultiLobeBrdf(const VmfMixture& ndf, const MicrofacetBrdf& base, int samples_per_side) : base_(base) {
  if (samples_per_side < 1) throw std::invalid_argument("MultiLobeBrdf: at least one sample per side");
  const int n = samples_per_side;
  for (const VmfLobe& lobe : ndf.lobes)
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        const Vec3 w = sampleVmf(lobe.kappa, lobe.mu, Point2((a + 0.5) / n, (b + 0.5) / n));
        normals_.push_back({Frame::fromNormal(w), lobe.amplitude / (double(n) * n)});
      }
}

Rgb MultiLobeBrdf::eval(const Vec3& wi, const Vec3& wo) const {
  if (wi.z() <= 0 || wo.z() <= 0) return Rgb::Zero();
  Rgb sum = Rgb::Zero();
  for (const MicroNormal& m : normals_) {
    const double cos_i = m.frame.n.dot(wi);  // <w, wi>, clamped by f's horizon below
    if (cos_i <= 0) continue;
    sum += base_.eval(m.frame.toLocal(wo), m.frame.toLocal(wi)) * (cos_i * m.weight);
  }
  return sum / wi.z();
}

}  // namespace vdbappear
