#include "libvdbappear/optimize/step_sizes.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <stdexcept>

namespace vdbappear {

const char* stepRuleName(StepRule rule) { return rule == StepRule::kNewton ? "newton" : "diagonal"; }

StepRule parseStepRule(const std::string& name) {
  if (name == "newton") return StepRule::kNewton;
  if (name == "diagonal") return StepRule::kDiagonal;
  throw std::invalid_argument("step rule '" + name + "': expected newton or diagonal");
}

int StepSizes::parameters() const { return int(std::lround(std::sqrt(double(A.size())))); }

std::vector<double> StepSizes::update(const std::vector<double>& gradient, int t) const {
  const int P = parameters();
  if (int(gradient.size()) != P) throw std::invalid_argument("StepSizes::update: wrong gradient size");
  std::vector<double> change(P, 0.0);
  for (int p = 0; p < P; ++p)
    for (int q = 0; q < P; ++q) change[p] += A[std::size_t(p) * P + q] * gradient[q] / (t + b);
  return change;
}

std::vector<double> StepSizes::diagonal(int t) const {
  const int P = parameters();
  std::vector<double> d(P);
  for (int p = 0; p < P; ++p) d[p] = A[std::size_t(p) * P + p] / (t + b);
  return d;
}

nlohmann::json StepSizes::toJson() const {
  return {{"rule", stepRuleName(rule)}, {"A", A}, {"b", b}, {"eta", eta}};
}

StepSizes StepSizes::fromJson(const nlohmann::json& json) {
  try {
    StepSizes s;
    s.rule = parseStepRule(json.at("rule").get<std::string>());
    s.A = json.at("A").get<std::vector<double>>();
    s.b = json.at("b").get<double>();
    s.eta = json.at("eta").get<double>();
    if (std::size_t(s.parameters()) * s.parameters() != s.A.size()) throw std::invalid_argument("step sizes: A is not square");
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("step sizes: ") + e.what());
  }
}

GaussNewton& GaussNewton::operator+=(const GaussNewton& o) {
  if (H.empty()) {
    *this = o;
    return *this;
  }
  if (o.H.size() != H.size() || o.D.size() != D.size()) throw std::invalid_argument("GaussNewton: sizes differ");
  for (std::size_t i = 0; i < H.size(); ++i) H[i] += o.H[i];
  for (std::size_t i = 0; i < D.size(); ++i) D[i] += o.D[i];
  return *this;
}

GaussNewton GaussNewton::scaled(double factor) const {
  GaussNewton g = *this;
  for (double& h : g.H) h *= factor;
  for (double& d : g.D) d *= factor;
  return g;
}

GaussNewton gaussNewton(const std::vector<Residual>& residuals, const WeightFactors& factors) {
  const int P = factors.parameterCount();
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(P, P);
  GaussNewton g;
  g.D.assign(P, 0.0);
  for (const Residual& r : residuals) {
    const std::vector<double> row = factors.chainRule(r.derivative);
    const Eigen::Map<const Eigen::VectorXd> j(row.data(), P);
    H += 2 * j * j.transpose();
    const std::vector<double> alone = factors.chainRule(r.derivative, false);
    for (int p = 0; p < P; ++p) g.D[p] += 2 * alone[p] * alone[p];
  }
  g.H.assign(H.data(), H.data() + H.size());  // symmetric: the storage order does not matter
  return g;
}

StepSizes stepSizesFrom(const GaussNewton& gauss_newton, StepRule rule, double b, double scale) {
  const int P = int(gauss_newton.D.size());
  if (std::size_t(P) * P != gauss_newton.H.size()) throw std::invalid_argument("stepSizesFrom: H is not P x P");
  const Eigen::Map<const Eigen::MatrixXd> H(gauss_newton.H.data(), P, P);
  StepSizes steps;
  steps.rule = rule;
  steps.b = b;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(P, P);
  Eigen::VectorXd inv_sqrt = Eigen::VectorXd::Zero(P);  // D^-1/2
  for (int p = 0; p < P; ++p)
    if (gauss_newton.D[p] > 0) inv_sqrt[p] = 1 / std::sqrt(gauss_newton.D[p]);
  const Eigen::MatrixXd preconditioned = inv_sqrt.asDiagonal() * H * inv_sqrt.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(preconditioned);
  if (rule == StepRule::kNewton) {
    // A = (1 + b) D^-1/2 (sum over kept eigenpairs of v v^T / lambda) D^-1/2
    Eigen::VectorXd inverse = Eigen::VectorXd::Zero(P);
    for (int i = 0; i < P; ++i)
      if (eigen.eigenvalues()[i] >= kNewtonKeep) inverse[i] = 1 / eigen.eigenvalues()[i];
    A = scale * (1 + b) * inv_sqrt.asDiagonal() * eigen.eigenvectors() * inverse.asDiagonal() *
        eigen.eigenvectors().transpose() * inv_sqrt.asDiagonal();
  } else {
    const double lambda_max = P > 0 ? eigen.eigenvalues().maxCoeff() : 0;
    steps.eta = lambda_max > 1 ? 1 / lambda_max : 1.0;
    for (int p = 0; p < P; ++p)
      if (gauss_newton.D[p] > 0) A(p, p) = scale * steps.eta * (1 + b) / gauss_newton.D[p];
  }
  steps.A.assign(std::size_t(P) * P, 0.0);
  for (int p = 0; p < P; ++p)
    for (int q = 0; q < P; ++q) steps.A[std::size_t(p) * P + q] = A(p, q);
  return steps;
}

StepSizes tuneStepSizes(const std::vector<Residual>& residuals, const WeightFactors& factors, StepRule rule, double b,
                        double scale) {
  return stepSizesFrom(gaussNewton(residuals, factors), rule, b, scale);
}

}  // namespace vdbappear
