// SGGX distribution and specular microflake phase function: identities of Heitz et al. 2015.
#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/sggx.h"

#include "support/sphere_quadrature.h"
#include "support/test_random.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>

namespace vdbappear {
namespace {

using test::SphereGrid;
using test::TestRandom;

TEST(Sggx, IsotropicFlakesHaveUniformDistributionAndUnitArea) {
  const Sggx sggx(Mat3::Identity());
  TestRandom random(1);
  for (int k = 0; k < 10; ++k) {
    const Vec3 w = random.direction();
    EXPECT_NEAR(sggx.D(w), 1 / kPi, 1e-14);
    EXPECT_NEAR(sggx.sigma(w), 1.0, 1e-14);
  }
}

// Eq. (4) of the downsampling paper evaluated with Eigen's general inverse and determinant, against
// the constructors from a matrix and from the medium's six channels (which invert by cofactors).
TEST(Sggx, DistributionMatchesEquationFourFromMatrixAndChannels) {
  TestRandom random(8);
  for (int k = 0; k < 200; ++k) {
    const Mat3 S = random.spd(k % 2 ? 1e-3 : 0.5);
    const Sggx from_matrix(S), from_channels(sggxDiagonal(S), sggxOffDiagonal(S));
    const Vec3 m = random.direction();
    const double q = m.dot(S.inverse() * m);
    const double D = 1 / (kPi * std::sqrt(S.determinant()) * q * q);
    EXPECT_NEAR(from_matrix.D(m), D, 1e-10 * D);
    EXPECT_EQ(from_channels.D(m), from_matrix.D(m));
    EXPECT_EQ(from_channels.sigma(m), from_matrix.sigma(m));
  }
}

// sigma(w) = integral of D(m) max(0, <w,m>) dm (Heitz's normalisation), by direct quadrature in m.
// The grid's pole is w, so the kink of max(0, .) lies on a cell boundary.
TEST(Sggx, ProjectedAreaIsIntegralOfVisibleDistribution) {
  TestRandom random(2);
  for (int k = 0; k < 12; ++k) {
    const Sggx sggx(random.spd(0.02));
    const Vec3 w = random.direction();
    const SphereGrid grid{Frame::fromNormal(w), 16, 32};
    const double integral = test::integrateSphere([&](const Vec3& m) { return sggx.D(m) * std::max(0.0, w.dot(m)); }, grid);
    EXPECT_NEAR(integral, sggx.sigma(w), 1e-6 * sggx.sigma(w)) << "S =\n" << sggx.S();
  }
}

// The same identity for near-degenerate fibers and flakes, where D is too peaked for a direct rule:
// substitute m = M u / |M u| with M = S^(1/2); the Jacobian dm/du is det(M) / |M u|^3 and the
// integrand becomes smooth in u. D itself is still the function under test.
TEST(Sggx, ProjectedAreaIdentityHoldsForNearDegenerateMatrices) {
  TestRandom random(3);
  std::vector<Mat3> matrices;
  for (double roughness : {0.05, 0.01, 0.003}) {
    matrices.push_back(Sggx::fiberMatrix(random.direction(), roughness));
    matrices.push_back(Sggx::surfaceMatrix(random.direction(), roughness));
  }
  for (int k = 0; k < 4; ++k) matrices.push_back(random.spd(1e-5));
  for (const Mat3& S : matrices) {
    const Sggx sggx(S);
    const Mat3 M = Eigen::SelfAdjointEigenSolver<Mat3>(S).operatorSqrt();
    const double det_M = M.determinant();
    for (int k = 0; k < 3; ++k) {
      const Vec3 w = random.direction();
      auto integrand = [&](const Vec3& u) {
        const Vec3 Mu = M * u;
        const double length = Mu.norm();
        const Vec3 m = Mu / length;
        return sggx.D(m) * std::max(0.0, w.dot(m)) * det_M / (length * length * length);
      };
      const SphereGrid grid{Frame::fromNormal((M * w).normalized()), 8, 16};
      EXPECT_NEAR(test::integrateSphere(integrand, grid), sggx.sigma(w), 1e-6 * sggx.sigma(w)) << "S =\n" << S;
    }
  }
}

// The phase function is normalised: integral of f(wi -> wo) over wo is 1, for every wi.
TEST(Sggx, PhaseFunctionIntegratesToOne) {
  TestRandom random(4);
  std::vector<Mat3> matrices{Mat3::Identity()};
  for (int k = 0; k < 8; ++k) matrices.push_back(random.spd(0.01));
  for (double roughness : {0.3, 0.1, 0.03}) {
    matrices.push_back(Sggx::fiberMatrix(random.direction(), roughness));
    matrices.push_back(Sggx::surfaceMatrix(random.direction(), roughness));
  }
  for (const Mat3& S : matrices) {
    const Sggx sggx(S);
    const Vec3 wi = random.direction();
    const SphereGrid grid{Frame::fromNormal(wi), 48, 96};
    const double integral = test::integrateSphere([&](const Vec3& wo) { return sggx.phase(wi, wo); }, grid);
    EXPECT_NEAR(integral, 1.0, 1e-4) << "S =\n" << S << "\nwi = " << wi.transpose();
  }
}

// f(i -> o) sigma(i) = f(o -> i) sigma(o): both equal D(wh) / 4.
TEST(Sggx, PhaseFunctionIsReciprocalWhenWeightedByProjectedArea) {
  TestRandom random(5);
  for (int k = 0; k < 200; ++k) {
    const Sggx sggx(random.spd(1e-3));
    const Vec3 wi = random.direction(), wo = random.direction();
    const double forward = sggx.phase(wi, wo) * sggx.sigma(wi);
    const double backward = sggx.phase(wo, wi) * sggx.sigma(wo);
    EXPECT_NEAR(forward, backward, 1e-12 * std::max(forward, 1.0));
    EXPECT_GT(forward, 0);
  }
}

TEST(Sggx, SampledDirectionsCarryTheirPhaseValueAsPdf) {
  TestRandom random(6);
  for (int k = 0; k < 500; ++k) {
    const Sggx sggx(random.spd(1e-3));
    const Vec3 wi = random.direction();
    const PhaseSample s = sggx.samplePhase(wi, random.point2());
    EXPECT_NEAR(s.wo.norm(), 1.0, 1e-12);
    EXPECT_NEAR(s.pdf, sggx.phase(wi, s.wo), 1e-12 * s.pdf);
    EXPECT_EQ(s.weight, 1.0);
    const Vec3 m = sggx.sampleVisibleNormal(wi, random.point2());
    EXPECT_GE(m.dot(wi), -1e-12) << "visible normals face wi";
  }
}

TEST(Sggx, FiberMatrixHasTheTangentAsItsSmallestEigenvector) {
  TestRandom random(7);
  for (double roughness : {0.5, 0.1, 0.01}) {
    const Vec3 t = random.direction();
    const Eigen::SelfAdjointEigenSolver<Mat3> eigen(Sggx::fiberMatrix(t, roughness));  // ascending
    EXPECT_NEAR(eigen.eigenvalues()[0], roughness * roughness, 1e-12);
    EXPECT_NEAR(eigen.eigenvalues()[1], 1.0, 1e-12);
    EXPECT_NEAR(eigen.eigenvalues()[2], 1.0, 1e-12);
    EXPECT_NEAR(std::abs(eigen.eigenvectors().col(0).dot(t)), 1.0, 1e-12);
    // Flakes lie along the fiber: the projected area is smallest seen along the tangent.
    const Sggx fiber = Sggx::fromFiberTangent(t, roughness);
    EXPECT_NEAR(fiber.sigma(t), roughness, 1e-12);
  }
}

TEST(Sggx, SurfaceMatrixHasTheNormalAsItsLargestEigenvector) {
  TestRandom random(8);
  for (double roughness : {0.5, 0.1, 0.01}) {
    const Vec3 n = random.direction();
    const Eigen::SelfAdjointEigenSolver<Mat3> eigen(Sggx::surfaceMatrix(n, roughness));
    EXPECT_NEAR(eigen.eigenvalues()[0], roughness * roughness, 1e-12);
    EXPECT_NEAR(eigen.eigenvalues()[2], 1.0, 1e-12);
    EXPECT_NEAR(std::abs(eigen.eigenvectors().col(2).dot(n)), 1.0, 1e-12);
    EXPECT_NEAR(Sggx::fromSurfaceNormal(n, roughness).sigma(n), 1.0, 1e-12);
  }
}

TEST(Sggx, PositiveDefiniteCheckAgreesWithEigenvalues) {
  TestRandom random(9);
  int positive = 0, other = 0;
  for (int k = 0; k < 2000; ++k) {
    Mat3 A;
    for (int i = 0; i < 9; ++i) A(i / 3, i % 3) = 2 * random.uniform() - 1;
    const Mat3 S = (A + A.transpose()) / 2 + (random.uniform() < 0.5 ? 0.8 : 0.0) * Mat3::Identity();
    const bool expected = Eigen::SelfAdjointEigenSolver<Mat3>(S).eigenvalues().minCoeff() > 0;
    const Vec3 diag(S(0, 0), S(1, 1), S(2, 2)), offdiag(S(0, 1), S(0, 2), S(1, 2));
    EXPECT_EQ(isPositiveDefinite(diag, offdiag), expected) << S;
    EXPECT_TRUE(sggxMatrix(diag, offdiag).isApprox(S));
    (expected ? positive : other)++;
  }
  EXPECT_GT(positive, 100);
  EXPECT_GT(other, 100);
  EXPECT_FALSE(isPositiveDefinite(Vec3(NAN, 1, 1), Vec3::Zero()));
  EXPECT_FALSE(isPositiveDefinite(Vec3(INFINITY, 1, 1), Vec3::Zero()));
  EXPECT_FALSE(isPositiveDefinite(Vec3::Zero(), Vec3::Zero()));
}

TEST(Frame, IsOrthonormalAndRightHanded) {
  TestRandom random(10);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 n = k == 0 ? Vec3(0, 0, -1) : random.direction();
    const Frame f = Frame::fromNormal(n);
    EXPECT_NEAR(f.s.norm(), 1, 1e-12);
    EXPECT_NEAR(f.t.norm(), 1, 1e-12);
    EXPECT_NEAR(f.s.dot(f.t), 0, 1e-12);
    EXPECT_NEAR(f.s.dot(n), 0, 1e-12);
    EXPECT_NEAR(f.t.dot(n), 0, 1e-12);
    EXPECT_NEAR(f.s.cross(f.t).dot(n), 1, 1e-12);
    const Vec3 v = random.direction();
    EXPECT_TRUE(f.toWorld(f.toLocal(v)).isApprox(v, 1e-12));
  }
}

}  // namespace
}  // namespace vdbappear
