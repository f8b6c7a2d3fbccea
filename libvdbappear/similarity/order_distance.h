#pragma once
// What an order of the similarity relations gives up, as a distance (issue 27): Eq. (23) makes the
// first N moments of f equal those of alpha f* + (1 - alpha) delta(mu = 1), the altered medium's
// scattering plus the forward "scattering" it no longer does. The Wasserstein-1 distance between
// the two distributions of mu = cos theta measures how far they differ beyond order N. Light header.

#include <vector>

namespace vdbappear {

// The cumulative distribution of mu at the k+1 edges of k equal bins over [-1,1], from a table on
// those bins (normalised as docs/medium.md §6: 2 pi sum f (2/k) = 1).
std::vector<double> tableCdf(const std::vector<double>& table);

// W1 = integral over [-1,1] of |F(mu) - alpha F*(mu)|, with F the input's CDF (tableCdf) and F* the
// altered table's; the delta at mu = 1 adds 1 - alpha to the mixture only at the end point, where
// both CDFs are 1. Both CDFs are piecewise linear; the integral is taken on the finer grid's bins,
// each split at the coarser grid's edges (midpoint rule on pieces where the difference is linear;
// a sign change inside a piece makes it an estimate).
double similarityDistance(const std::vector<double>& input_cdf, const std::vector<double>& altered_table, double alpha);

}  // namespace vdbappear
