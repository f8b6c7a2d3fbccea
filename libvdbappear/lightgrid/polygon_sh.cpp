#include "libvdbappear/lightgrid/polygon_sh.h"

#include "libvdbappear/lightgrid/zonal_factorisation.h"
#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/legendre.h"
#include "libvdbappear/math/spherical_harmonics.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace vdbappear {

namespace {

// One edge of the projected polygon, in the frame of Algorithm 2, lines 5-7.
struct Arc {
  Vec3 w, lambda, n;       // w_i, lambda_i = n_i x w_i, n_i = w_i x w_{i+1} / |...|  (Eq. 5.12-5.13)
  double T = 0;            // arccos(w_i . w_{i+1})
  double l0 = 0, l1 = 0;   // distances from x to p_i and p_{i+1}
};

// int_0^T sin(t - T) P_l(h) dt and int_0^T sin(t) P_l(h) dt from C_l and E_l (Eq. 5.22, C.6-C.9),
// written with cos t = (c_x h + c_y h') / A^2 and sin t = (c_y h - c_x h') / A^2, A^2 = c_x^2 + c_y^2,
// which needs no arctan. When the lobe axis is the arc's pole (A = 0), h = 0 along the arc.
struct SineMoments {
  double shifted, plain;
};
SineMoments sineMoments(double c_x, double c_y, double T, double C_l, double E_l, double P_l_at_0) {
  const double A2 = c_x * c_x + c_y * c_y;
  const double cosT = std::cos(T), sinT = std::sin(T);
  if (A2 < 1e-24) return {P_l_at_0 * (cosT - 1), P_l_at_0 * (1 - cosT)};
  return {((c_y * cosT - c_x * sinT) * C_l - (c_x * cosT + c_y * sinT) * E_l) / A2, (c_y * C_l - c_x * E_l) / A2};
}

}  // namespace

EdgeIntegrals edgeIntegrals(double c_x, double c_y, double T, int lmax) {
  EdgeIntegrals e;
  e.B.assign(lmax + 1, 0.0);
  e.C.assign(lmax + 1, 0.0);
  e.E.assign(lmax + 1, 0.0);
  const double cosT = std::cos(T), sinT = std::sin(T);
  const double h0 = c_x, h1 = c_x * cosT + c_y * sinT;
  std::vector<double> P0, P1;
  legendrePolynomials(lmax + 1, h0, P0);
  legendrePolynomials(lmax + 1, h1, P1);
  const double boundary = c_x * sinT - c_y * cosT;  // -h'(T)
  // Base cases (Eq. 5.28, Algorithm 3 line 2-3); D_l = int P_l'(h) dt.
  e.B[0] = T;
  e.C[0] = boundary + c_y;
  e.E[0] = h1 - h0;
  std::vector<double> D(lmax + 1, 0.0);
  for (int l = 1; l <= lmax; ++l) {
    const double B_lm2 = l >= 2 ? e.B[l - 2] : 0.0, D_lm2 = l >= 2 ? D[l - 2] : 0.0;
    e.B[l] = ((2 * l - 1) * e.C[l - 1] - (l - 1) * B_lm2) / l;                          // Eq. (5.26), Bonnet
    D[l] = (2 * l - 1) * e.B[l - 1] + D_lm2;                                            // Eq. (5.27)
    e.C[l] = (boundary * P1[l] + c_y * P0[l] + (c_x * c_x + c_y * c_y - 1) * D[l] + l * e.B[l - 1]) / (l + 1);  // Eq. (5.25)
    e.E[l] = ((P1[l + 1] - P1[l - 1]) - (P0[l + 1] - P0[l - 1])) / (2 * l + 1);          // Eq. (5.24)
  }
  return e;
}

double projectedSolidAngle(const std::vector<Vec3>& w) {
  double omega = 0;
  for (std::size_t i = 1; i + 1 < w.size(); ++i) {
    const Vec3 &a = w[0], &b = w[i], &c = w[i + 1];
    omega += 2 * std::atan2(a.dot(b.cross(c)), 1 + a.dot(b) + b.dot(c) + c.dot(a));
  }
  return omega;
}

PolygonSh polygonSh(const std::vector<Vec3>& polygon, const Vec3& x, const ZonalFactorisation& zh) {
  const int lmax = zh.lmax(), n_sh = shCount(lmax);
  PolygonSh out{std::vector<double>(n_sh, 0.0), std::vector<Vec3>(n_sh, Vec3::Zero())};
  const std::size_t N = polygon.size();
  // Precomputation per vertex and per edge (Algorithm 2, lines 2-8).
  std::vector<Vec3> w(N);
  std::vector<double> dist(N);
  for (std::size_t i = 0; i < N; ++i) {
    const Vec3 p = polygon[i] - x;
    dist[i] = p.norm();
    if (dist[i] == 0) return out;
    w[i] = p / dist[i];
  }
  std::vector<Arc> arcs;
  for (std::size_t i = 0; i < N; ++i) {
    const std::size_t k = (i + 1) % N;
    const Vec3 c = w[i].cross(w[k]);
    if (c.norm() == 0) continue;  // an edge seen end-on subtends no arc
    Arc a;
    a.w = w[i];
    a.n = c.normalized();
    a.lambda = a.n.cross(a.w);
    a.T = std::atan2(c.norm(), w[i].dot(w[k]));  // arccos(w_i . w_k), accurate for small angles
    a.l0 = dist[i];
    a.l1 = dist[k];
    arcs.push_back(a);
  }
  // With the face normal pointing away from x the fan's triangles are positively oriented.
  const double omega = projectedSolidAngle(w);
  if (!(omega > 0)) return out;  // x in the plane of the polygon
  std::vector<double> P_at_0;
  legendrePolynomials(lmax, 0.0, P_at_0);
  std::vector<double> K(lmax + 1);
  for (int l = 0; l <= lmax; ++l) K[l] = std::sqrt((2 * l + 1) / (4 * kPi));
  // ZH integrals Lambda_l = int_Q P_l(w . w_c) dw and their gradients, per lobe (lines 9-29).
  const int lobes = 2 * lmax + 1;
  std::vector<std::vector<double>> Lambda(lobes, std::vector<double>(lmax + 1, 0.0));
  std::vector<std::vector<Vec3>> grad(lobes, std::vector<Vec3>(lmax + 1, Vec3::Zero()));
  for (int j = 0; j < lobes; ++j) {
    const Vec3& w_c = zh.directions()[j];
    std::vector<double> H(lmax + 1, 0.0);  // sum_i c_z B_l  (Eq. 5.30 without K_l)
    for (const Arc& a : arcs) {
      const double c_x = w_c.dot(a.w), c_y = w_c.dot(a.lambda), c_z = w_c.dot(a.n);
      const EdgeIntegrals e = edgeIntegrals(c_x, c_y, a.T, lmax);
      const double sinT = std::sin(a.T);
      for (int l = 0; l <= lmax; ++l) {
        H[l] += c_z * e.B[l];
        // Eq. (5.20)/(5.23), with <n, dw/dx> = -(n/sin T)(sin t / l_{i+1} - sin(t - T) / l_i) (Eq. 5.18).
        // In our vertex order n_i points into Q, so Reynolds' outward normal (Eq. 5.8) is -n_i.
        const SineMoments s = sineMoments(c_x, c_y, a.T, e.C[l], e.E[l], P_at_0[l]);
        grad[j][l] -= a.n * ((s.shifted / a.l0 - s.plain / a.l1) / sinT);
      }
    }
    // Eq. (5.31)-(5.32) for the unnormalised Legendre integrals.
    Lambda[j][0] = omega;
    for (int l = 1; l <= lmax; ++l)
      Lambda[j][l] = (2 * l - 1) * H[l - 1] / (l * (l + 1)) + (l >= 2 ? (l - 2) * (l - 1) * Lambda[j][l - 2] / (l * (l + 1)) : 0.0);
  }
  // SH from ZH, Eq. (5.5) and (5.29): L_lm = sum_j alpha^m_{l,j} K_l Lambda_{l,j}.
  for (int l = 0; l <= lmax; ++l) {
    const Eigen::MatrixXd& alpha = zh.weights(l);
    for (int m = -l; m <= l; ++m) {
      double L = 0;
      Vec3 G = Vec3::Zero();
      for (int j = 0; j <= 2 * l; ++j) {
        L += alpha(m + l, j) * K[l] * Lambda[j][l];
        G += alpha(m + l, j) * K[l] * grad[j][l];
      }
      out.coeffs[shIndex(l, m)] = L;
      out.gradients[shIndex(l, m)] = G;
    }
  }
  return out;
}

}  // namespace vdbappear
