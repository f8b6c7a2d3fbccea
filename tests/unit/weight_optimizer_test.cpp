// The weight optimisation's pieces (optimize/): the parameterisation and its chain rule against
// finite differences, colour-scale normalisation, the effective-albedo limit, the step rules on
// least-squares problems with known solutions, the unbiased two-halves error, the training set's
// framing and lights, the reference cache's refusals, and the whole SGD recovering factors that
// made its own references.
#include "libvdbappear/io/medium.h"
#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/spherical_harmonics.h"
#include "libvdbappear/medium/medium_view.h"
#include "libvdbappear/optimize/lobe_medium.h"
#include "libvdbappear/optimize/reference_cache.h"
#include "libvdbappear/optimize/step_sizes.h"
#include "libvdbappear/optimize/training_error.h"
#include "libvdbappear/optimize/training_set.h"
#include "libvdbappear/optimize/weight_factors.h"
#include "libvdbappear/optimize/weight_optimizer.h"
#include "libvdbappear/render/scene_description.h"
#include "libvdbappear/util/error.h"

#include "support/medium_testing.h"
#include "support/temp_dir.h"
#include "support/test_random.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <fstream>

namespace vdbappear {
namespace {

WeightFactors randomFactors(int K, int m, ColourMode mode, std::uint64_t seed) {
  test::TestRandom random(seed);
  WeightFactors f(K, m, mode);
  std::vector<double> theta = f.parameters();
  for (double& t : theta) t = 0.6 + 0.8 * random.uniform();
  f.setParameters(theta);
  return f;
}

// X(theta) = sum_kjc alpha_kjc scale_kj^c(theta): dX/de_kj^c = alpha_kjc scale_kj^c, and the chain
// rule must give dX/dtheta as central differences do (with colour scales: projected on sum_c = 0).
TEST(WeightFactors, ChainRuleMatchesFiniteDifferences) {
  for (const ColourMode mode : {ColourMode::kGrey, ColourMode::kColourScales, ColourMode::kPerChannel}) {
    const WeightFactors f = randomFactors(2, 3, mode, 7);
    test::TestRandom random(3);
    std::vector<Rgb> alpha(6);
    for (Rgb& a : alpha) a = Rgb(random.uniform(), random.uniform(), random.uniform()) - 0.5;
    const auto X = [&](const WeightFactors& g) {
      const LobeWeightScales s = g.scales();
      double x = 0;
      for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 3; ++j) x += (alpha[k * 3 + j] * s.at(k, j)).sum();
      return x;
    };
    std::vector<Rgb> d(6);
    const LobeWeightScales s = f.scales();
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 3; ++j) d[k * 3 + j] = alpha[k * 3 + j] * s.at(k, j);
    const std::vector<double> analytic = f.chainRule(d);
    std::vector<double> numeric;
    const std::vector<double> theta = f.parameters();
    for (std::size_t p = 0; p < theta.size(); ++p) {
      WeightFactors plus = f, minus = f;
      std::vector<double> t = theta;
      t[p] += 1e-6;
      plus.setParameters(t);
      t[p] -= 2e-6;
      minus.setParameters(t);
      numeric.push_back((X(plus) - X(minus)) / 2e-6);
    }
    if (mode == ColourMode::kColourScales)  // projected on the tangent of prod_j w_kj = 1
      for (int k = 0; k < 2; ++k) {
        double* g_k = &numeric[k * 6];
        double g_n = 0, n_n = 0;
        for (int j = 0; j < 3; ++j) {
          g_n += g_k[j] / f.w(k, j)[0];
          n_n += 1 / (f.w(k, j)[0] * f.w(k, j)[0]);
        }
        for (int j = 0; j < 3; ++j) g_k[j] -= g_n / n_n / f.w(k, j)[0];
      }
    ASSERT_EQ(analytic.size(), numeric.size());
    for (std::size_t p = 0; p < numeric.size(); ++p)
      EXPECT_NEAR(analytic[p], numeric[p], 1e-6) << colourModeName(mode) << " " << f.parameterNames()[p];
  }
}

TEST(WeightFactors, ParametersNamesAndJsonRoundTrip) {
  const WeightFactors f = randomFactors(2, 2, ColourMode::kColourScales, 5);
  EXPECT_EQ(f.parameterCount(), 10);
  EXPECT_EQ(f.parameterNames()[0], "w_0,0");
  EXPECT_EQ(f.parameterNames()[2], "s_0.R");
  EXPECT_EQ(WeightFactors(3, 2, ColourMode::kPerChannel).parameterCount(), 18);
  EXPECT_EQ(WeightFactors(3, 2, ColourMode::kGrey).parameterCount(), 6);
  const WeightFactors g = WeightFactors::fromJson(f.toJson());
  EXPECT_EQ(g.parameters(), f.parameters());
  EXPECT_EQ(g.mode(), f.mode());
  nlohmann::json bad = f.toJson();
  bad["w"][0][1] = {1.0, -1.0, 1.0};
  EXPECT_THROW(WeightFactors::fromJson(bad), std::invalid_argument);
  bad = f.toJson();
  bad["s"].erase(1);
  EXPECT_THROW(WeightFactors::fromJson(bad), std::invalid_argument);
}

// Counts that do not fit the arrays, are negative, fractional or beyond int are refused as
// std::invalid_argument before anything is allocated (found by the checkpoint fuzz harness: a float
// out of int's range went through get<int>(), undefined behaviour).
TEST(WeightFactors, DamagedCountsAreRefusedBeforeAllocation) {
  const nlohmann::json good = WeightFactors(2, 2, ColourMode::kColourScales).toJson();
  ASSERT_NO_THROW(WeightFactors::fromJson(good));
  for (const nlohmann::json& count : {nlohmann::json(-1), nlohmann::json(2000000000), nlohmann::json(1e155),
                                      nlohmann::json(2.5), nlohmann::json("2"), nlohmann::json(std::uint64_t(1) << 40)}) {
    for (const char* key : {"clusters", "lobes"}) {
      nlohmann::json bad = good;
      bad[key] = count;
      EXPECT_THROW(WeightFactors::fromJson(bad), std::invalid_argument) << key << " = " << count.dump();
    }
  }
}

TEST(WeightFactors, NormalisingColourScalesKeepsEveryLobeScale) {
  WeightFactors f = randomFactors(2, 2, ColourMode::kColourScales, 9);
  const LobeWeightScales before = f.scales();
  f.normaliseColourScales();
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(f.w(k, 0)[0] * f.w(k, 1)[0], 1.0, 1e-12);  // geometric mean 1
    for (int j = 0; j < 2; ++j) EXPECT_LT((f.scales().at(k, j) - before.at(k, j)).abs().maxCoeff(), 1e-12);
  }
}

// One cluster of two voxels whose naive weights sum to 0.9 and 0.5 (grey): factors above 1/0.9 are
// brought back to an effective albedo of 1 at the first voxel.
TEST(ConstrainFactors, KeepsTheEffectiveAlbedoAtMostOne) {
  LobeMediumLayout layout;
  layout.clusters = 1;
  layout.lobes = 2;
  layout.naive_weights = {{0.6f, 0.6f, 0.6f, 0.3f, 0.3f, 0.3f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f}};
  WeightFactors f(1, 2, ColourMode::kGrey);
  f.setParameters({1.5, 1.5});
  EXPECT_TRUE(constrainFactors(layout, f));
  EXPECT_NEAR(0.9 * f.w(0, 0)[0], 1.0, 1e-7);  // the weights are floats
  f.setParameters({1.0, 1.0});
  EXPECT_FALSE(constrainFactors(layout, f));
  f.setParameters({1e-5, 1.0});
  constrainFactors(layout, f);
  EXPECT_EQ(f.w(0, 0)[0], kMinFactor);
  // Per channel: only the channel that exceeds is scaled.
  WeightFactors c(1, 2, ColourMode::kPerChannel);
  c.w(0, 0) = Rgb(1.5, 1.0, 1.0);
  c.w(0, 1) = Rgb(1.5, 1.0, 1.0);
  EXPECT_TRUE(constrainFactors(layout, c));
  EXPECT_NEAR(c.w(0, 0)[0] * 0.9, 1.0, 1e-7);
  EXPECT_EQ(c.w(0, 0)[1], 1.0);
}

// Residuals r_i(theta) = J_i . (theta - theta*) fed as the derivatives of Residual: the Newton rule's
// first step (t = 1) lands on theta* exactly; with two identical columns it moves their common
// direction to the optimum and leaves their difference alone.
std::vector<Residual> linearResiduals(const Eigen::MatrixXd& J, const Eigen::VectorXd& offset, const WeightFactors& f) {
  std::vector<Residual> residuals;
  for (int i = 0; i < J.rows(); ++i) {
    Residual r;
    r.value = offset[i];
    r.channel = 0;
    r.derivative.assign(f.parameterCount(), Rgb::Zero());
    // Grey factors at theta = 1: dX/dw = sum_c dX/de^c / w, so put the derivative on channel 0.
    for (int p = 0; p < J.cols(); ++p) r.derivative[p][0] = J(i, p);
    residuals.push_back(r);
  }
  return residuals;
}

TEST(StepSizes, NewtonStepSolvesALinearLeastSquaresProblem) {
  const WeightFactors f(1, 3, ColourMode::kGrey);
  Eigen::MatrixXd J(6, 3);
  J << 1, 0.2, 0, 0.1, 1, 0.3, 0, 0.2, 1, 0.5, 0.1, 0.2, 0.3, 0.6, 0.1, 0.2, 0.1, 0.7;
  const Eigen::Vector3d truth(0.8, 1.1, 0.9), theta(1, 1, 1);
  const Eigen::VectorXd residual = J * (theta - truth);
  const std::vector<Residual> residuals = linearResiduals(J, residual, f);
  const StepSizes steps = tuneStepSizes(residuals, f, StepRule::kNewton, 1.0);
  const Eigen::VectorXd gradient = 2 * J.transpose() * residual;  // dE/dtheta of E = |r|^2
  const std::vector<double> change = steps.update({gradient[0], gradient[1], gradient[2]}, 1);
  for (int p = 0; p < 3; ++p) EXPECT_NEAR(theta[p] - change[p], truth[p], 1e-9) << p;
  // Later steps shrink as (1 + b) / (t + b).
  EXPECT_NEAR(steps.update({gradient[0], gradient[1], gradient[2]}, 3)[0], change[0] / 2, 1e-12);
}

TEST(StepSizes, NewtonLeavesUndeterminedDirectionsAlone) {
  const WeightFactors f(1, 2, ColourMode::kGrey);
  Eigen::MatrixXd J(3, 2);
  J << 1, 1, 0.5, 0.5, 0.2, 0.2;  // both factors act alike: only their sum is determined
  const Eigen::VectorXd residual = J * Eigen::Vector2d(0.1, 0.1);
  const StepSizes steps = tuneStepSizes(linearResiduals(J, residual, f), f, StepRule::kNewton, 1.0);
  const Eigen::VectorXd gradient = 2 * J.transpose() * residual;
  const std::vector<double> change = steps.update({gradient[0], gradient[1]}, 1);
  EXPECT_NEAR(change[0], 0.1, 1e-9);
  EXPECT_NEAR(change[1], 0.1, 1e-9);
  // The diagonal rule: eta = 1/2 (lambda_max = 2) makes its step along the common direction a full
  // Newton step too.
  const StepSizes diagonal = tuneStepSizes(linearResiduals(J, residual, f), f, StepRule::kDiagonal, 1.0);
  EXPECT_NEAR(diagonal.eta, 0.5, 1e-9);
  EXPECT_NEAR(diagonal.update({gradient[0], gradient[1]}, 1)[0], 0.1, 1e-9);
  // A parameter that changes nothing does not move.
  Eigen::MatrixXd K(2, 2);
  K << 1, 0, 0.5, 0;
  const StepSizes partial = tuneStepSizes(linearResiduals(K, Eigen::Vector2d(0.1, 0.05), f), f, StepRule::kNewton, 1.0);
  EXPECT_EQ(partial.update({0.3, 0.7}, 1)[1], 0.0);
}

TEST(StepSizes, JsonRoundTrip) {
  StepSizes s;
  s.A = {1, 2, 3, 4};
  s.b = 2;
  s.eta = 0.5;
  const StepSizes t = StepSizes::fromJson(s.toJson());
  EXPECT_EQ(t.A, s.A);
  EXPECT_EQ(t.b, 2);
  EXPECT_THROW(StepSizes::fromJson({{"rule", "newton"}, {"A", {1, 2, 3}}, {"b", 1}, {"eta", 1}}), std::invalid_argument);
}

// Two half renders A and B of a 2-pixel image, one cluster per pixel: E = sum c^2 dA dB and
// dE/de = sum c^2 (dA gB + dB gA), each channel on its own.
TEST(TrainingError, ProductsTakeOneFactorFromEachHalf) {
  TrainingImage image;
  image.masks = ClusterMasks(2, 2, {1, 0, 0, 1});
  image.reference = {Rgb(1, 2, 3), Rgb(0.5, 0.5, 0.5)};
  image.normalisation = Rgb(2, 1, 0.5);
  RenderResult a, b;
  a.mean = {1.1f, 2.2f, 3.3f, 0.4f, 0.5f, 0.6f};
  b.mean = {1.2f, 1.8f, 3.0f, 0.6f, 0.5f, 0.4f};
  a.gradient_clusters = b.gradient_clusters = 1;
  a.gradient_lobes = b.gradient_lobes = 1;
  a.weight_gradients = {1, 1, 1, 2, 2, 2};
  b.weight_gradients = {3, 3, 3, 4, 4, 4};
  TrainingError error;
  addTrainingImage(image, a, b, &error);
  const Rgb c2(4, 1, 0.25);
  const Rgb da0 = Rgb(1.1, 2.2, 3.3) - image.reference[0], db0 = Rgb(1.2, 1.8, 3.0) - image.reference[0];
  const Rgb da1 = Rgb(0.4, 0.5, 0.6) - image.reference[1], db1 = Rgb(0.6, 0.5, 0.4) - image.reference[1];
  EXPECT_NEAR(error.E, (c2 * da0 * db0).sum() + (c2 * da1 * db1).sum(), 1e-6);
  const Rgb expected = c2 * (da0 * 3 + db0 * 1) + c2 * (da1 * 4 + db1 * 2);
  ASSERT_EQ(error.dE_de.size(), 1u);
  EXPECT_LT((error.dE_de[0] - expected).abs().maxCoeff(), 1e-5);
  EXPECT_EQ(error.residuals.size(), 6u);
  EXPECT_NEAR(error.relative_errors[0][1][0], 0.5 / 0.5 - 1, 1e-6);
}

// The training views frame the box: every corner lies inside the image, and the outline's aspect
// sets the image size.
TEST(TrainingSet, ViewsFrameTheBoxAndLightsAreNonNegative) {
  Aabb box;
  box.extend(Vec3(0, 0, 0));
  box.extend(Vec3(8, 6, 0.6));
  const std::vector<TrainingView> views = boundingBoxViews(box, 100, "faces,corners");
  ASSERT_EQ(views.size(), 14u);
  for (const TrainingView& v : views) {
    EXPECT_EQ(std::max(v.width, v.height), 100) << v.name;
    const Vec3 forward = (v.pose.target - v.pose.position).normalized();
    const Vec3 right = forward.cross(v.pose.up).normalized(), up = right.cross(forward);
    const double tan_v = std::tan(v.pose.fov_degrees * kPi / 360), tan_h = tan_v * v.width / v.height;
    for (int c = 0; c < 8; ++c) {
      const Vec3 p(c & 1 ? 8 : 0, c & 2 ? 6 : 0, c & 4 ? 0.6 : 0);
      const Vec3 q = p - v.pose.position;
      const double depth = q.dot(forward);
      EXPECT_GT(depth, 0) << v.name;
      EXPECT_LE(std::abs(q.dot(right)) / depth, tan_h * 1.0001) << v.name;
      EXPECT_LE(std::abs(q.dot(up)) / depth, tan_v * 1.0001) << v.name;
    }
  }
  EXPECT_EQ(boundingBoxViews(box, 100, "upper-corners").size(), 4u);
  EXPECT_THROW(boundingBoxViews(box, 100, "+w"), std::invalid_argument);
  EXPECT_THROW(boundingBoxViews(box, 100, "+z,+z"), std::invalid_argument);
  EXPECT_THROW(trainingLightings("sh7"), std::invalid_argument);
  EXPECT_THROW(trainingLightings("ground"), std::invalid_argument);

  // sh1: four lights, non-negative everywhere, spanning the SH bands 0-1 (their projections on
  // Y_00 .. Y_11 have rank 4).
  const std::vector<TrainingLighting> lightings = trainingLightings("sh1+ground");
  ASSERT_EQ(lightings.size(), 4u);
  Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
  test::TestRandom random(2);
  constexpr int kDirections = 20000;
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(lightings[i].ground);
    SceneDescription description;
    description.lights = lightings[i].lights;
    const RenderScene scene = buildRenderScene(description, nullptr, {});
    for (int n = 0; n < kDirections; ++n) {
      const Vec3 w = random.direction();
      double L = 0;
      for (const auto& light : scene.lights) L += light->radiance(w)[0];
      ASSERT_GE(L, -1e-12) << lightings[i].name;
      const std::vector<double> Y = evalSphericalHarmonics(1, w);
      for (int c = 0; c < 4; ++c) projection(i, c) += L * Y[c] * 4 * kPi / kDirections;
    }
  }
  EXPECT_EQ(Eigen::FullPivLU<Eigen::Matrix4d>(projection).setThreshold(1e-2).rank(), 4);
}

TEST(ReferenceCache, StoresFindsAndRefusesDamagedFiles) {
  test::TempDir dir;
  const ReferenceCache cache(dir.path("cache"));
  EXPECT_FALSE(cache.find("abc"));
  cache.store("abc", {2, 1, {1, 2, 3, 0.5, 4, 5, 6, 1}});
  const auto found = cache.find("abc");
  ASSERT_TRUE(found);
  EXPECT_EQ(found->rgba, (std::vector<float>{1, 2, 3, 0.5, 4, 5, 6, 1}));
  EXPECT_THROW(cache.store("abc", {2, 1, {1, 2, 3}}), std::invalid_argument);
  const std::string path = cache.pathOf("abc");
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const auto rewrite = [&](const std::string& content) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << content;
  };
  rewrite(bytes.substr(0, bytes.size() - 5));  // truncated
  EXPECT_THROW(cache.find("abc"), MediumError);
  std::string other_version = bytes;
  other_version.replace(other_version.find(" 2 ") + 3, 0, "9");  // version 0.1.0 -> 90.1.0
  rewrite(other_version);
  EXPECT_THROW(cache.find("abc"), MediumError);
  std::string corrupt = bytes;
  corrupt[corrupt.size() - 1] ^= 0x55;
  rewrite(corrupt);
  EXPECT_THROW(cache.find("abc"), MediumError);
  EXPECT_FALSE(ReferenceCache("").find("abc"));
  EXPECT_NE(hashText("a"), hashText("b"));
  EXPECT_EQ(hashText("a").size(), 32u);
}

// The SGD recovers factors that made its own references: the 2-cluster, 2-lobe twill rendered with
// known factors per cluster (both lobes alike) and colour scales stands in for the full medium.
TEST(WeightOptimizer, RecoversTheFactorsThatMadeTheReferences) {
  const MediumPtr lobes = test::multiLobeTwill(48, 4, 4, 2, 2);
  const LobeMediumLayout layout = inspectLobeMedium(*lobes);
  const auto view = std::make_shared<MediumView>(lobes, Interpolation::kNearest);
  WeightFactors truth(2, 2, ColourMode::kColourScales);
  for (int j = 0; j < 2; ++j) {
    truth.w(0, j) = Rgb::Constant(0.85);
    truth.w(1, j) = Rgb::Constant(1.05);
  }
  truth.s(0) = Rgb(1.05, 0.95, 1.0);
  truth.s(1) = Rgb(0.97, 1.0, 1.03);
  ASSERT_FALSE(constrainFactors(layout, truth));
  const auto truth_scales = std::make_shared<const LobeWeightScales>(truth.scales());

  TrainingScenes scenes(view, trainingSet(view->worldBounds(), 32, "sh1", "+z,upper-corners"));
  std::vector<TrainingImage> images;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    TrainingImage image;
    image.config = scenes.config(i);
    RenderSettings s;
    s.width = image.config.view.width;
    s.height = image.config.view.height;
    s.spp = 16;
    s.cluster_coverage = true;
    s.path.max_depth = 0;
    image.masks = ClusterMasks(scenes.render(i, s, nullptr));
    s.spp = 256;
    s.cluster_coverage = false;
    s.path.max_depth = -1;
    s.seed = 99;
    const RenderResult reference = scenes.render(i, s, truth_scales);
    image.reference = restrictedMeans(reference.mean, image.masks);
    image.normalisation = foregroundMean(reference.mean, image.masks).max(0.05).inverse();
    images.push_back(image);
  }
  OptimizerSettings settings;
  settings.mode = ColourMode::kColourScales;
  settings.spp = 16;
  settings.max_iterations = 12;
  WeightOptimizer optimizer(scenes, images, layout, settings);
  while (!optimizer.done()) optimizer.iterate();
  const TrainingError final_error = optimizer.evaluate(optimizer.factors(), 0);
  // E's estimate at 16 spp has a noise of about 0.01 here, 2% of the naive E.
  EXPECT_LT(final_error.E, 0.05 * optimizer.history().front().E);
  // The two lobes of a cluster act almost alike, so their sum is what the images determine.
  for (int k = 0; k < 2; ++k) {
    const Rgb found = optimizer.factors().s(k) * (optimizer.factors().w(k, 0) + optimizer.factors().w(k, 1)) / 2;
    const Rgb expected = truth.s(k) * truth.w(k, 0);
    EXPECT_LT((found / expected - 1).abs().maxCoeff(), 0.02) << "cluster " << k << ": " << found.transpose();
    // The balance of the lobes, which the images barely see, stays near its true 1.
    EXPECT_NEAR(optimizer.factors().w(k, 0)[0] / optimizer.factors().w(k, 1)[0], 1.0, 0.1) << "cluster " << k;
  }
}

}  // namespace
}  // namespace vdbappear
