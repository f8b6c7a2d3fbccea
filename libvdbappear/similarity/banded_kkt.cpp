#include "libvdbappear/similarity/banded_kkt.h"

#include <Eigen/Cholesky>

#include <cmath>

namespace vdbappear {

Eigen::VectorXd PentadiagonalMatrix::operator*(const Eigen::VectorXd& v) const {
  const Eigen::Index n = size();
  Eigen::VectorXd out = diagonal.cwiseProduct(v);
  for (Eigen::Index i = 0; i + 1 < n; ++i) {
    out[i] += first[i] * v[i + 1];
    out[i + 1] += first[i] * v[i];
  }
  for (Eigen::Index i = 0; i + 2 < n; ++i) {
    out[i] += second[i] * v[i + 2];
    out[i + 2] += second[i] * v[i];
  }
  return out;
}

namespace {

// A = L D L^T of a symmetric positive definite pentadiagonal A, L unit lower triangular with two
// subdiagonals (l1[i] = L(i,i-1), l2[i] = L(i,i-2)): the band case of Golub and Van Loan's LDL^T.
class PentadiagonalLdlt {
 public:
  explicit PentadiagonalLdlt(const PentadiagonalMatrix& a) : d_(a.size()), l1_(a.size()), l2_(a.size()) {
    const Eigen::Index n = a.size();
    for (Eigen::Index i = 0; i < n; ++i) {
      l2_[i] = i >= 2 ? a.second[i - 2] / d_[i - 2] : 0.0;
      l1_[i] = i >= 1 ? (a.first[i - 1] - (i >= 2 ? l2_[i] * d_[i - 2] * l1_[i - 1] : 0.0)) / d_[i - 1] : 0.0;
      d_[i] = a.diagonal[i] - (i >= 1 ? l1_[i] * l1_[i] * d_[i - 1] : 0.0) - (i >= 2 ? l2_[i] * l2_[i] * d_[i - 2] : 0.0);
      if (!(d_[i] > 0)) positive_ = false;
    }
  }
  bool positive() const { return positive_; }

  void solveInPlace(Eigen::Ref<Eigen::VectorXd> v) const {
    const Eigen::Index n = d_.size();
    for (Eigen::Index i = 1; i < n; ++i) v[i] -= l1_[i] * v[i - 1] + (i >= 2 ? l2_[i] * v[i - 2] : 0.0);
    v.array() /= d_.array();
    for (Eigen::Index i = n - 2; i >= 0; --i) v[i] -= l1_[i + 1] * v[i + 1] + (i + 2 < n ? l2_[i + 2] * v[i + 2] : 0.0);
  }

 private:
  Eigen::VectorXd d_, l1_, l2_;
  bool positive_ = true;
};

}  // namespace

bool solveBandedKkt(const PentadiagonalMatrix& h, const Eigen::MatrixXd& b, const Eigen::VectorXd& r1,
                    const Eigen::VectorXd& r2, double delta, Eigen::VectorXd& x, Eigen::VectorXd& lambda) {
  PentadiagonalMatrix shifted = h;
  shifted.diagonal.array() += delta;
  const PentadiagonalLdlt a(shifted);
  if (!a.positive()) return false;
  Eigen::MatrixXd y = b.transpose();  // A^-1 B^T
  for (Eigen::Index c = 0; c < y.cols(); ++c) a.solveInPlace(y.col(c));
  Eigen::MatrixXd schur = b * y;  // B A^-1 B^T + delta I: the negated Schur complement, positive definite
  schur.diagonal().array() += delta;
  const Eigen::LLT<Eigen::MatrixXd> s(schur);
  if (s.info() != Eigen::Success) return false;
  // The shifted system: x = A^-1 (r1 - B^T lambda), (B A^-1 B^T + delta I) lambda = B A^-1 r1 - r2.
  auto solveShifted = [&](const Eigen::VectorXd& e1, const Eigen::VectorXd& e2, Eigen::VectorXd& dx, Eigen::VectorXd& dl) {
    Eigen::VectorXd w = e1;
    a.solveInPlace(w);
    dl = s.solve(b * w - e2);
    dx = w - y * dl;
  };
  solveShifted(r1, r2, x, lambda);
  for (int refinement = 0; refinement < 8; ++refinement) {
    const Eigen::VectorXd e1 = r1 - h * x - b.transpose() * lambda, e2 = r2 - b * x;
    const double residual = std::max(e1.cwiseAbs().maxCoeff(), e2.cwiseAbs().maxCoeff());
    if (!std::isfinite(residual)) return false;
    if (residual <= 1e-14) return true;
    Eigen::VectorXd dx, dl;
    solveShifted(e1, e2, dx, dl);
    x += dx;
    lambda += dl;
  }
  const double residual =
      std::max((r1 - h * x - b.transpose() * lambda).cwiseAbs().maxCoeff(), (r2 - b * x).cwiseAbs().maxCoeff());
  return residual <= 1e-13;
}

}  // namespace vdbappear
