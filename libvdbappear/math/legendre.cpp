#include "libvdbappear/math/legendre.h"

namespace vdbappear {

void legendrePolynomials(int n, double x, std::vector<double>& p) {
  p.resize(n + 1);
  p[0] = 1;
  if (n >= 1) p[1] = x;
  for (int j = 1; j < n; ++j) p[j + 1] = ((2 * j + 1) * x * p[j] - j * p[j - 1]) / (j + 1);
}

std::vector<double> legendrePolynomials(int n, double x) {
  std::vector<double> p;
  legendrePolynomials(n, x, p);
  return p;
}

}  // namespace vdbappear
