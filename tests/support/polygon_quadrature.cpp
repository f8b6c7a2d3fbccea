#include "support/polygon_quadrature.h"

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>

namespace vdbappear::test {

namespace {

struct Rule {
  double a, b, c, weight;
};

const std::vector<Rule>& radonRule() {
  static const std::vector<Rule> rule = [] {
    const double s = std::sqrt(15.0);
    const double a = (6 - s) / 21, b = (6 + s) / 21;
    const double wa = (155 - s) / 1200, wb = (155 + s) / 1200;
    return std::vector<Rule>{{1.0 / 3, 1.0 / 3, 1.0 / 3, 9.0 / 40},
                             {a, a, 1 - 2 * a, wa}, {a, 1 - 2 * a, a, wa}, {1 - 2 * a, a, a, wa},
                             {b, b, 1 - 2 * b, wb}, {b, 1 - 2 * b, b, wb}, {1 - 2 * b, b, b, wb}};
  }();
  return rule;
}

Eigen::VectorXd triangleRule(const AreaFunction& f, const Vec3& p0, const Vec3& p1, const Vec3& p2, int size) {
  const double area = 0.5 * (p1 - p0).cross(p2 - p0).norm();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(size);
  for (const Rule& r : radonRule()) sum += r.weight * f(r.a * p0 + r.b * p1 + r.c * p2);
  return area * sum;
}

Eigen::VectorXd adaptive(const AreaFunction& f, const Vec3& p0, const Vec3& p1, const Vec3& p2, const Eigen::VectorXd& whole,
                         double tolerance, int size, int depth) {
  const Vec3 m01 = 0.5 * (p0 + p1), m12 = 0.5 * (p1 + p2), m20 = 0.5 * (p2 + p0);
  const Eigen::VectorXd parts[4] = {triangleRule(f, p0, m01, m20, size), triangleRule(f, m01, p1, m12, size),
                                    triangleRule(f, m20, m12, p2, size), triangleRule(f, m01, m12, m20, size)};
  const Eigen::VectorXd sum = parts[0] + parts[1] + parts[2] + parts[3];
  if ((sum - whole).cwiseAbs().maxCoeff() <= tolerance) return sum;
  if (depth > 16) throw std::runtime_error("integratePolygon: no convergence");
  return adaptive(f, p0, m01, m20, parts[0], tolerance / 4, size, depth + 1) +
         adaptive(f, m01, p1, m12, parts[1], tolerance / 4, size, depth + 1) +
         adaptive(f, m20, m12, p2, parts[2], tolerance / 4, size, depth + 1) +
         adaptive(f, m01, m12, m20, parts[3], tolerance / 4, size, depth + 1);
}

}  // namespace

Eigen::VectorXd integratePolygon(const AreaFunction& f, const std::vector<Vec3>& polygon, double tolerance, int size) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(size);
  const int triangles = int(polygon.size()) - 2;
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    const Eigen::VectorXd whole = triangleRule(f, polygon[0], polygon[i], polygon[i + 1], size);
    sum += adaptive(f, polygon[0], polygon[i], polygon[i + 1], whole, tolerance / triangles, size, 0);
  }
  return sum;
}

}  // namespace vdbappear::test
