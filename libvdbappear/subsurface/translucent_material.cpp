#include "libvdbappear/subsurface/translucent_material.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace vdbappear {

void validateTranslucentMaterial(const TranslucentMaterial& m, const std::string& where) {
  const auto fail = [&](const std::string& what) { throw std::invalid_argument(fmt::format("{}: {}", where, what)); };
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(m.sigma_t[c]) || m.sigma_t[c] < 0)
      fail(fmt::format("density (sigma_t) {} must be finite and >= 0", m.sigma_t[c]));
    if (!(m.albedo[c] >= 0 && m.albedo[c] <= 1)) fail(fmt::format("albedo {} must lie in [0, 1]", m.albedo[c]));
  }
  if (!(std::abs(m.g) < 1)) fail(fmt::format("g {} must lie in (-1, 1)", m.g));
  if (!(m.eta > 0)) fail(fmt::format("eta {} must be > 0", m.eta));
  if (!(m.eta <= 10)) fail(fmt::format("eta {} is beyond 10 (the dipole's boundary term 1 - F_dr vanishes)", m.eta));
  const Rgb sigma_t_reduced = m.sigmaA() + m.sigmaS() * (1 - m.g);
  for (int c = 0; c < 3; ++c)
    if (!(sigma_t_reduced[c] > 0)) fail("the interior neither absorbs nor scatters in some channel (sigma_t' = 0)");
}

}  // namespace vdbappear
