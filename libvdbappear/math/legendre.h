#pragma once
// Legendre polynomials P_0 .. P_n by Bonnet's recurrence, (j + 1) P_{j+1} = (2j + 1) x P_j - j P_{j-1}.

#include <vector>

namespace vdbappear {

std::vector<double> legendrePolynomials(int n, double x);
// The same into `p` (resized to n + 1): no allocation once p has the room, for inner loops.
void legendrePolynomials(int n, double x, std::vector<double>& p);

}  // namespace vdbappear
