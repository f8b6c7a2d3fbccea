#pragma once
// Quantising a continuous HG asymmetry g, so that a medium with per-voxel g needs one altered phase
// function per level instead of one per voxel. Light header.
//
// Levels sit at the centres of M equal cells of (-1,1): g_q = -1 + (q + 1/2) h, h = 2 / M, so every
// level is a valid g and every g in (-1,1) lies within h/2 of one. The Legendre moments of HG are
// f_n = g^n (Eq. 8), and |g^n - g_q^n| <= n |g - g_q| <= n h / 2. M is the smallest count with
// N0 h / 2 <= epsilon, which bounds every moment the similarity relations use (n <= N0) by epsilon:
//   |f_n(g) - f_n(g_q)| <= epsilon for n = 0..N0.

#include <algorithm>
#include <cmath>

namespace vdbappear {

class GQuantiser {
 public:
  GQuantiser(double moment_tolerance, int max_order)
      : levels_(std::max(1, int(std::ceil(max_order / moment_tolerance)))) {}

  int levels() const { return levels_; }
  double step() const { return 2.0 / levels_; }
  int level(double g) const { return std::clamp(int(std::floor((g + 1) / step())), 0, levels_ - 1); }
  double value(int level) const { return -1 + (level + 0.5) * step(); }

 private:
  int levels_;
};

}  // namespace vdbappear
