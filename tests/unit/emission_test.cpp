// Emitting media (docs/medium.md §3b): the path tracer against closed forms under both conventions,
// the downsampler against a direct average of the children, and the reader's checks.
#include "libvdbappear/downsample/naive_downsample.h"
#include "libvdbappear/io/emission_convention.h"
#include "libvdbappear/io/grid_mapping.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_info.h"
#include "libvdbappear/math/constants.h"
#include "libvdbappear/medium/blackbody.h"
#include "libvdbappear/medium/emission_light.h"
#include "libvdbappear/preview/projection_preview.h"
#include "libvdbappear/procedural/random_medium.h"

#include "support/medium_testing.h"
#include "support/render_testing.h"
#include "support/temp_dir.h"
#include "support/test_random.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

namespace vdbappear {
namespace {

using nlohmann::json;
using openvdb::Coord;
using openvdb::Vec3s;

// An emission grid over the box, value e, with the medium's transform.
openvdb::Vec3SGrid::Ptr emissionOver(const Medium& medium, const openvdb::CoordBBox& box, const Rgb& e) {
  auto grid = test::namedGridLike<openvdb::Vec3SGrid>(medium, grid_names::kEmission, Vec3s(0.0f));
  grid->denseFill(box, Vec3s(float(e[0]), float(e[1]), float(e[2])), true);
  return grid;
}

void setConvention(Medium& medium, EmissionConvention convention) {
  medium.metadata.insertMeta(metadata_names::kEmissionConvention, openvdb::StringMetadata(emissionConventionName(convention)));
}

const char* name(Interpolation interp) { return interp == Interpolation::kNearest ? "nearest" : "trilinear"; }

// An emitting, absorbing cube of optical depth tau = 2 seen straight down, without lights, along
// camera rays only (no scattering): cycles L = E / sigma_t (1 - exp(-tau)); pbrt L = (1 - albedo) Le
// (1 - exp(-tau)), the Le (1 - exp(-tau)) where nothing scatters. Under trilinear lookups E
// and sigma_t ramp together at the faces, so the closed form holds there too.
TEST(Emission, EmittingAbsorbingCubeMatchesItsClosedForm) {
  const Rgb e(0.5, 1.0, 1.5);
  const double sigma_t = 2.0, tau = 2.0;
  for (const EmissionConvention convention : {EmissionConvention::kCycles, EmissionConvention::kPbrt})
    for (const float albedo : {0.0f, 0.25f})
      for (const Interpolation interp : {Interpolation::kNearest, Interpolation::kTrilinear}) {
        auto medium = test::cube(8, 1.0, float(sigma_t), albedo);
        medium->other_grids.push_back(emissionOver(*medium, openvdb::CoordBBox(Coord(0), Coord(7)), e));
        setConvention(*medium, convention);
        RenderSettings settings = test::small(4, 4000);
        settings.path.max_depth = 0;
        const test::Render r = test::renderStraightDown(medium, json::array(), settings, std::nullopt, interp);
        const Rgb expected = convention == EmissionConvention::kCycles ? Rgb(e / sigma_t * (1 - std::exp(-tau)))
                                                                       : Rgb((1 - albedo) * e * (1 - std::exp(-tau)));
        test::expectImage(r, expected,
                          fmt::format("{}, albedo {}, {}", emissionConventionName(convention), albedo, name(interp)));
      }
}

// Emission where the density is 0 (cycles) is added along the ray whatever the medium: in the white
// furnace (sky 1) the sky plus E times the length crossed, 1 + 8 h E. Delta tracking meets it only
// because the majorant is raised over emitting voxels (medium/majorant_grid.h); the density is one
// voxel far away, off every ray.
TEST(Emission, EmissionWithoutDensityAddsItsLineIntegral) {
  const double h = 1.0 / 8, E = 0.25;
  for (const Interpolation interp : {Interpolation::kNearest, Interpolation::kTrilinear}) {
    auto medium = test::cube(1, h, 1.0f, 1.0f);  // voxel (0,0,0)
    medium->density->tree().clear();
    medium->density->tree().setValueOn(Coord(40, 40, 40), 1.0f);
    medium->other_grids.push_back(emissionOver(*medium, openvdb::CoordBBox(Coord(0), Coord(7)), Rgb::Constant(E)));
    const test::Render r = test::renderStraightDown(medium, json::array({{{"type", "env"}, {"radiance", 1.0}}}),
                                                    test::small(4, 4000), Vec3::Constant(3.5 * h), interp);
    test::expectImage(r, 1 + 8 * h * E, name(interp));
  }
}

// Emitted light scatters like any other, so it is scored along every ray of a path, not only the
// camera's: a glowing cube of albedo 0.9 (cycles, E = 1, sigma_t = 4) gives E / sigma_t (1 - exp(-4))
// along camera rays alone, and much more with every bounce (deep inside, radiance nears
// E / sigma_a = 2.5).
TEST(Emission, ScatteredEmissionAddsToTheCameraRaysEmission) {
  auto medium = test::cube(8, 1.0, 4.0f, 0.9f);
  medium->other_grids.push_back(emissionOver(*medium, openvdb::CoordBBox(Coord(0), Coord(7)), Rgb::Constant(1.0)));
  RenderSettings direct = test::small(4, 2000);
  direct.path.max_depth = 0;
  const test::Render camera_only = test::renderStraightDown(medium, json::array(), direct);
  const test::Render every_bounce = test::renderStraightDown(medium, json::array(), test::small(4, 2000));
  test::expectImage(camera_only, 1.0 / 4 * (1 - std::exp(-4.0)), "camera rays");
  EXPECT_GT(every_bounce.mean, camera_only.mean * 1.5);  // albedo 0.9: most emitted light scatters out
}

// A blackbody_temperature grid over the voxels (x, y) in [-2, 10]^2, z in [0, 7], at kelvin(z).
openvdb::FloatGrid::Ptr temperatureRamp(const Medium& medium, double (*kelvin)(int)) {
  auto grid = test::namedGridLike<openvdb::FloatGrid>(medium, grid_names::kBlackbodyTemperature, 0.0f);
  for (int z = 0; z < 8; ++z)
    grid->denseFill(openvdb::CoordBBox(Coord(-2, -2, z), Coord(10, 10, z)), float(kelvin(z)), true);
  return grid;
}

// Blackbody light (docs/medium.md §3b) is made from the interpolated temperature, as Cycles makes
// it: straight down through a temperature ramp (1500 K to 3600 K over 8 voxels, 0 K beyond), without
// density or lights, trilinear lookups give h times the integral of B(T(z)) with T interpolated
// between voxel centres, nearest lookups h sum B(T_k). Negative control: the integral of the
// interpolated per-voxel light, what an emission grid made of each voxel's light would give, is
// far off (B grows as T^4: over the half voxels where T falls to 0 K it is 5/2 times larger).
TEST(Emission, BlackbodyLightIsThatOfTheInterpolatedTemperature) {
  const double h = 1.0 / 8;
  double (*kelvin)(int) = [](int z) { return z < 0 || z > 7 ? 0.0 : 1500.0 + 300.0 * z; };
  const BlackbodyTable table;
  PrincipledBlackbody settings;
  settings.kelvin = 1;
  auto B = [&](double T) { return principledBlackbodyEmission(T, settings, table); };
  Rgb nearest = Rgb::Zero(), trilinear = Rgb::Zero(), interpolated_light = Rgb::Zero();
  for (int z = 0; z < 8; ++z) nearest += h * B(kelvin(z));
  const int n = 64;  // Simpson's rule over each voxel-to-voxel segment
  for (int z = -1; z < 8; ++z)
    for (int i = 0; i <= n; ++i) {
      const double f = double(i) / n, w = (i == 0 || i == n ? 1 : i % 2 ? 4 : 2) * h / (3 * n);
      trilinear += w * B((1 - f) * kelvin(z) + f * kelvin(z + 1));
      interpolated_light += w * ((1 - f) * B(kelvin(z)) + f * B(kelvin(z + 1)));
    }
  for (const Interpolation interp : {Interpolation::kNearest, Interpolation::kTrilinear}) {
    auto medium = test::cube(1, h, 1.0f, 1.0f);
    medium->density->tree().clear();
    medium->density->tree().setValueOn(Coord(40, 40, 40), 1.0f);  // off every ray
    medium->other_grids.push_back(temperatureRamp(*medium, kelvin));
    const test::Render r = test::renderStraightDown(medium, json::array(), test::small(4, 4000), Vec3::Constant(3.5 * h), interp);
    test::expectImage(r, interp == Interpolation::kNearest ? nearest : trilinear, name(interp));
    if (interp == Interpolation::kTrilinear)
      EXPECT_GT(std::abs(r.mean - interpolated_light.mean()), 20 * r.error) << "negative control";
  }
}

// Downsampling makes blackbody light into emission (docs/medium.md §3b): the coarse medium has no
// blackbody_temperature, and its emission is the mean of the children's emission plus blackbody
// light (here at Blackbody Intensity 0.5), by brute force.
TEST(Emission, DownsamplingMakesBlackbodyLightIntoEmission) {
  auto fine = test::cube(8, 1.0, 2.0f, 0.5f);
  auto temperature = test::namedGridLike<openvdb::FloatGrid>(*fine, grid_names::kBlackbodyTemperature, 0.0f);
  test::TestRandom random(7);
  for (auto v = openvdb::CoordBBox(Coord(-2), Coord(9)).begin(); v; ++v)
    if (random.uniform() < 0.5) temperature->tree().setValueOn(*v, float(4000 * random.uniform()));
  temperature->insertMeta(metadata_names::kBlackbodyIntensity, openvdb::FloatMetadata(0.5f));
  fine->other_grids.push_back(temperature);
  fine->other_grids.push_back(emissionOver(*fine, openvdb::CoordBBox(Coord(0), Coord(3)), Rgb(0.5, 0.25, 0)));
  const int F = 2;
  const MediumPtr coarse = downsampleNaive(*fine, {F, SggxWeighting::Count}).medium;
  EXPECT_FALSE(findOtherGrid<openvdb::FloatGrid>(*coarse, grid_names::kBlackbodyTemperature));
  const auto coarse_emission = findOtherGrid<openvdb::Vec3SGrid>(*coarse, grid_names::kEmission);
  ASSERT_TRUE(coarse_emission);
  const BlackbodyTable table;
  PrincipledBlackbody settings;
  settings.kelvin = 1;
  settings.intensity = 0.5;
  int checked = 0;
  for (auto v = coarse_emission->cbeginValueOn(); v; ++v, ++checked) {
    Rgb sum = Rgb::Zero();
    const Coord first(v.getCoord().x() * F, v.getCoord().y() * F, v.getCoord().z() * F);
    for (auto c = openvdb::CoordBBox::createCube(first, F).begin(); c; ++c) {
      float T = 0;
      if (temperature->tree().probeValue(*c, T)) sum += principledBlackbodyEmission(T, settings, table);
      if (openvdb::CoordBBox(Coord(0), Coord(3)).isInside(*c)) sum += Rgb(0.5, 0.25, 0);
    }
    const Rgb expected = sum / (F * F * F);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR((*v)[k], expected[k], 1e-5 * (1 + expected[k])) << v.getCoord() << ", channel " << k;
  }
  EXPECT_EQ(checked, 6 * 6 * 6) << "active where a child is, from -1 to 4";
}

// The coarse emission against its children, by brute force (docs/medium.md §3b); under pbrt's
// convention the blue channel, which no child absorbs, takes the density-weighted mean.
TEST(Emission, DownsamplingAveragesTheChildren) {
  for (const EmissionConvention convention : {EmissionConvention::kCycles, EmissionConvention::kPbrt}) {
    RandomMediumParams params;
    params.extent = 24;
    params.seed = 5;
    MediumPtr fine = makeRandomMedium(params);
    setConvention(*fine, convention);
    auto emission = test::namedGridLike<openvdb::Vec3SGrid>(*fine, grid_names::kEmission, Vec3s(0.0f));
    test::TestRandom random(6);
    for (int x = -14; x < 14; ++x)  // beyond the density's box too: emission without density
      for (int y = -14; y < 14; ++y)
        for (int z = -14; z < 14; ++z)
          if (random.uniform() < 0.4)
            emission->tree().setValueOn(Coord(x, y, z), Vec3s(float(random.uniform()), float(random.uniform()),
                                                              float(random.uniform())));
    fine->other_grids.push_back(emission);
    for (auto a = fine->albedo->beginValueOn(); a; ++a) a.setValue(Vec3s((*a)[0], (*a)[1], 1.0f));  // blue: no absorption
    const int F = 3;
    const MediumPtr coarse = downsampleNaive(*fine, {F, SggxWeighting::Count}).medium;
    const auto coarse_emission = findOtherGrid<openvdb::Vec3SGrid>(*coarse, grid_names::kEmission);
    ASSERT_TRUE(coarse_emission) << emissionConventionName(convention);
    EXPECT_EQ(coarse_emission->transform(), coarse->transform());
    int checked = 0;
    for (auto v = coarse_emission->cbeginValueOn(); v; ++v, ++checked) {
      Rgb sum = Rgb::Zero(), absorbed = Rgb::Zero(), absorption = Rgb::Zero(), dense = Rgb::Zero();
      double rho_sum = 0;
      for (auto c = openvdb::CoordBBox::createCube(openvdb::Coord(v.getCoord().x() * F, v.getCoord().y() * F, v.getCoord().z() * F), F).begin(); c; ++c) {
        Vec3s e(0.0f);
        const Rgb Le = emission->tree().probeValue(*c, e) ? Rgb(e[0], e[1], e[2]) : Rgb(Rgb::Zero());
        sum += Le;
        float rho = 0;
        if (!fine->density->tree().probeValue(*c, rho) || !(rho > 0)) continue;
        const Vec3s a = fine->albedo->tree().getValue(*c);
        const Rgb one_minus_a(1 - a[0], 1 - a[1], 1 - a[2]);
        absorbed += rho * one_minus_a * Le;
        absorption += rho * one_minus_a;
        dense += rho * Le;
        rho_sum += rho;
      }
      Rgb expected = sum / (F * F * F);
      if (convention == EmissionConvention::kPbrt)  // density-weighted where no child absorbs (blue here)
        for (int k = 0; k < 3; ++k)
          expected[k] = absorption[k] > 0 ? absorbed[k] / absorption[k] : rho_sum > 0 ? dense[k] / rho_sum : 0.0;
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR((*v)[k], expected[k], 1e-5 * (1 + expected[k]))
            << emissionConventionName(convention) << " at " << v.getCoord() << ", channel " << k;
    }
    EXPECT_GT(checked, 500) << emissionConventionName(convention);
  }
}

// vdb_info and vdb_preview see the emission: its ranges and convention; a flame beside the smoke
// (emission where the density is 0) lies in the preview's frame and glows there. Negative control:
// the same medium with its emission grid at 0 is the background there.
TEST(Emission, InfoAndPreviewShowIt) {
  auto medium = test::cube(8, 1.0, 2.0f, 0.5f);
  medium->other_grids.push_back(emissionOver(*medium, openvdb::CoordBBox(Coord(10, 0, 0), Coord(17, 7, 7)), Rgb(3, 2, 1)));
  const MediumInfo info = describeMedium(*medium, "glow.vdb");
  ASSERT_TRUE(info.emission);
  EXPECT_EQ((*info.emission)[0].max, 3.0);
  EXPECT_EQ((*info.emission)[2].mean, 1.0);
  EXPECT_EQ(info.emission_convention, "cycles");
  PreviewOptions options;
  options.width = 64;
  options.view = Vec3(0, 0, -1);  // straight down: x across the image
  const RgbImage glow = renderPreview(*medium, options);
  auto dark = std::make_shared<Medium>(*medium);
  dark->other_grids = {emissionOver(*medium, openvdb::CoordBBox(Coord(10, 0, 0), Coord(17, 7, 7)), Rgb::Zero())};
  const RgbImage unlit = renderPreview(*dark, options);
  const int x = glow.width * 13 / 18, y = glow.height / 2;  // index x about 13 of the box -0.5 .. 17.5
  EXPECT_NEAR(glow.at(x, y)[0], 0.18 + 3.0 * 8 / 8, 0.05) << "E times the length crossed (8 voxels of 1/8), on the background";
  EXPECT_GT(glow.at(x, y)[0], glow.at(x, y)[2]);
  EXPECT_NEAR(unlit.at(x, y)[0], 0.18, 1e-6);
}

double luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

// The blackbody colour against Blender 3.4 Cycles' Blackbody node (an emission plane rendered at each
// temperature, 2026-11-28), from 2000 K up within 2% per channel; luminance 1 at every temperature
// (Rec.709 weights); redder when cooler. Cycles fits the same curve: below 2000 K the two part more
// (red -2.7% at 1500 K, -6.1% at 1000 K), where a fire's light is 20 to 80 times dimmer than at 3000 K.
TEST(Blackbody, ColourMatchesCyclesAndHasLuminanceOne) {
  const struct {
    double kelvin;
    Rgb cycles;
  } cases[] = {{2000, {2.5201, 0.6469, 0.0204}}, {2500, {2.0676, 0.7693, 0.1394}}, {3000, {1.7708, 0.8443, 0.2722}},
               {4000, {1.4141, 0.9236, 0.5337}}, {6500, {1.0426, 0.9841, 1.0353}}, {12000, {0.8263, 0.9945, 1.5663}}};
  const BlackbodyTable table;
  for (const auto& c : cases) {
    const Rgb colour = blackbodyColour(c.kelvin);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(colour[k], c.cycles[k], 0.02 * c.cycles[k] + 2e-3) << c.kelvin << " K, channel " << k;
    EXPECT_NEAR(luminance(colour), 1.0, 2e-3) << c.kelvin << " K";
    EXPECT_NEAR((table(c.kelvin + 2.5) - blackbodyColour(c.kelvin + 2.5)).abs().maxCoeff(), 0.0, 1e-4) << "table";
  }
  EXPECT_GT(blackbodyColour(1500)[0] / blackbodyColour(1500)[1], 5 * blackbodyColour(6500)[0] / blackbodyColour(6500)[1]);
  EXPECT_EQ(blackbodyColour(20000)[2], blackbodyColour(12000)[2]) << "clamped as Cycles does";
}

// Principled Volume's blackbody light: luminance sigma / pi 1e-6 T^4 (Stefan-Boltzmann) at intensity 1,
// so twice the temperature is 16 times the light; at intensity 0.5 the mix with 1; none at 0 kelvin.
TEST(Blackbody, PrincipledEmissionFollowsStefanBoltzmann) {
  const BlackbodyTable table;
  const double sigma = 5.670373e-8 * 1e-6 / kPi;
  const PrincipledBlackbody fire;  // 1000 K per unit, intensity 1
  const Rgb at3000 = principledBlackbodyEmission(3.0, fire, table), at6000 = principledBlackbodyEmission(6.0, fire, table);
  EXPECT_NEAR(luminance(at3000), sigma * std::pow(3000.0, 4), 3e-3 * luminance(at3000));
  EXPECT_NEAR(luminance(at6000) / luminance(at3000), 16 * luminance(blackbodyColour(6000)) / luminance(blackbodyColour(3000)), 1e-9);
  PrincipledBlackbody half = fire;
  half.intensity = 0.5;
  EXPECT_NEAR(luminance(principledBlackbodyEmission(3.0, half, table)), sigma * (0.5 + 0.5 * std::pow(3000.0, 4)),
              3e-3 * luminance(at3000));
  EXPECT_EQ(principledBlackbodyEmission(0.0, fire, table).maxCoeff(), 0.0);
  EXPECT_EQ(principledBlackbodyEmission(-1.0, fire, table).maxCoeff(), 0.0);
  EXPECT_GE(principledBlackbodyEmission(1.2, fire, table).minCoeff(), 0.0) << "negative blue clamped";
}

// emission=blackbody:GRID[:K[:I]]: parsed and printed back; a temperature grid read as the contract's
// blackbody_temperature (kelvin, its intensity in the grid's metadata), whose light per voxel is
// Principled Volume's; and Blender's preset reads a fire's `temperature` so, with a note. Negative
// controls: a smoke (an empty `flame`) and --from none stay dark.
TEST(Blackbody, TemperatureGridBecomesBlackbodyTemperature) {
  const GridRule rule = parseGridRule("emission=blackbody:temperature:1500:0.5");
  EXPECT_TRUE(rule.blackbody);
  EXPECT_EQ(rule.sources, std::vector<std::string>{"temperature"});
  EXPECT_EQ(rule.kelvin, 1500);
  EXPECT_EQ(rule.intensity, 0.5);
  for (const char* text : {"emission=blackbody:temperature", "emission=blackbody:t:1500", "emission=blackbody:t:1000:0.5"})
    EXPECT_EQ(gridRuleText(parseGridRule(text)), text);
  for (const char* bad : {"emission=blackbody:", "emission=blackbody:t:0", "emission=blackbody:t:1000:2",
                          "emission=blackbody:a,b", "emission=blackbody:t:1:1:1"})
    EXPECT_THROW(parseGridRule(bad), std::invalid_argument) << bad;

  test::TempDir dir;
  const std::string path = dir.path("fire.vdb");
  auto transform = openvdb::math::Transform::createLinearTransform(0.1);
  auto density = openvdb::FloatGrid::create(0.0f), temperature = openvdb::FloatGrid::create(0.0f),
       flame = openvdb::FloatGrid::create(0.0f);
  for (int x = 0; x < 4; ++x) {
    density->tree().setValueOn(Coord(x, 0, 0), 0.5f);
    temperature->tree().setValueOn(Coord(x, 0, 0), 1.5f + 0.5f * x);
  }
  density->setName("density");
  temperature->setName("temperature");
  flame->setName("flame");
  for (auto& grid : {density, temperature, flame}) grid->setTransform(transform);
  test::writeRawVdb(dir.path("smoke.vdb"), {density, temperature, flame});  // heat, but no flame: a smoke
  EXPECT_FALSE(voxelEmission(*readMedium(dir.path("smoke.vdb"))));
  flame->tree().setValueOn(Coord(1, 0, 0), 0.5f);
  test::writeRawVdb(path, {density, temperature, flame});
  const MediumPtr fire = readMedium(path);  // --from auto: a foreign file
  EXPECT_FALSE(findOtherGrid<openvdb::Vec3SGrid>(*fire, grid_names::kEmission));
  const auto kelvin = blackbodyTemperatureGrid(*fire);
  ASSERT_TRUE(kelvin);
  EXPECT_EQ(blackbodyIntensityMetadata(*kelvin), 1.0);
  const auto emission = voxelEmission(*fire);
  ASSERT_TRUE(emission);
  const BlackbodyTable table;
  for (int x = 0; x < 4; ++x) {
    EXPECT_EQ(kelvin->tree().getValue(Coord(x, 0, 0)), 1000 * (1.5f + 0.5f * x));
    const Rgb expected = principledBlackbodyEmission(1.5 + 0.5 * x, PrincipledBlackbody(), table);
    const Vec3s e = emission->tree().getValue(Coord(x, 0, 0));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(e[k], expected[k], 1e-5 * (1 + expected[k])) << x << ", channel " << k;
  }
  GridMapping half;
  addGridRule(half, parseGridRule("emission=blackbody:temperature:1500:0.5"));
  const auto half_kelvin = blackbodyTemperatureGrid(*readMedium(path, half));
  ASSERT_TRUE(half_kelvin);
  EXPECT_EQ(half_kelvin->tree().getValue(Coord(1, 0, 0)), 1500 * 2.0f);
  EXPECT_EQ(blackbodySettings(*half_kelvin).intensity, 0.5);
  ASSERT_EQ(fire->read_notes.size(), 1u);
  EXPECT_NE(fire->read_notes[0].find("Blender's fire (Quick Smoke's Principled Volume: blackbody at 1000 K per unit of "
                                     "'temperature'): read as --grid emission=blackbody:temperature"),
            std::string::npos)
      << fire->read_notes[0];
  GridMapping none;
  none.preset = GridPreset::kNone;
  EXPECT_FALSE(voxelEmission(*readMedium(path, none)));

  // A negative temperature: an error naming the rule, the grid and the voxel when asked for; left
  // out with a note when the preset detected it.
  temperature->tree().setValueOn(Coord(2, 0, 0), -0.5f);
  const std::string cold = dir.path("cold.vdb");
  test::writeRawVdb(cold, {density, temperature, flame});
  GridMapping asked;
  addGridRule(asked, parseGridRule("emission=blackbody:temperature"));
  EXPECT_EQ(test::readMediumError(cold, asked),
            cold + ": --grid emission=blackbody:temperature: grid 'temperature': temperature -0.5 is negative at voxel (2,0,0)");
  const MediumPtr detected = readMedium(cold);
  EXPECT_FALSE(voxelEmission(*detected));
  ASSERT_EQ(detected->read_notes.size(), 1u);
  EXPECT_NE(detected->read_notes[0].find("not read as --grid emission=blackbody:temperature"), std::string::npos)
      << detected->read_notes[0];
  GridMapping houdini;
  houdini.preset = GridPreset::kHoudini;
  EXPECT_FALSE(voxelEmission(*readMedium(path, houdini)));
}

MediumPtr densityCube() { return test::cube(4, 1.0, 1.0f, 0.5f); }

std::string errorOf(const Medium& medium, const openvdb::MetaMap& metadata = {}) {
  test::TempDir dir;
  test::writeRawVdb(dir.path("in.vdb"), test::copyGrids(medium), metadata);
  return test::readMediumError(dir.path("in.vdb"));
}

TEST(Emission, BadEmissionIsRefusedNamingTheGrid) {
  MediumPtr medium = densityCube();
  medium->other_grids.push_back(emissionOver(*medium, openvdb::CoordBBox(Coord(0), Coord(3)), Rgb(0.5, 1.0, 0.0)));
  EXPECT_EQ(errorOf(*medium), "");
  static_cast<openvdb::Vec3SGrid&>(*medium->other_grids.back()).tree().setValueOn(Coord(2, 0, 1), Vec3s(0.5f, -1.0f, 0.0f));
  EXPECT_NE(errorOf(*medium).find("grid 'emission': emission (0.5, -1, 0) is negative at voxel (2,0,1)"), std::string::npos)
      << errorOf(*medium);
  static_cast<openvdb::Vec3SGrid&>(*medium->other_grids.back()).tree().setValueOn(Coord(2, 0, 1), Vec3s(NAN, 0.0f, 0.0f));
  EXPECT_NE(errorOf(*medium).find("grid 'emission': emission (nan, 0, 0) is NaN or infinite at voxel (2,0,1)"), std::string::npos)
      << errorOf(*medium);

  medium = densityCube();
  auto background = test::namedGridLike<openvdb::Vec3SGrid>(*medium, grid_names::kEmission, Vec3s(1.0f));
  medium->other_grids.push_back(background);
  EXPECT_NE(errorOf(*medium).find("grid 'emission': background is (1, 1, 1), expected 0"), std::string::npos) << errorOf(*medium);

  medium = densityCube();  // grey emission is read as RGB, and checked the same way
  auto grey = test::namedGridLike<openvdb::FloatGrid>(*medium, grid_names::kEmission);
  grey->tree().setValueOn(Coord(1, 2, 3), -0.5f);
  medium->other_grids.push_back(grey);
  EXPECT_NE(errorOf(*medium).find("grid 'emission': emission (-0.5, -0.5, -0.5) is negative at voxel (1,2,3)"),
            std::string::npos)
      << errorOf(*medium);

  medium = densityCube();
  medium->other_grids.push_back(test::namedGridLike<openvdb::Int32Grid>(*medium, grid_names::kEmission));
  EXPECT_NE(errorOf(*medium).find("grid 'emission': holds int32 values, expected vec3s"), std::string::npos) << errorOf(*medium);
}

// A blackbody_temperature grid (docs/medium.md §3b) that is negative, not finite, of another type,
// has a background, or an intensity outside [0, 1]: one line naming the grid.
TEST(Emission, BadBlackbodyTemperatureIsRefusedNamingTheGrid) {
  auto withTemperature = [](float value, float background = 0.0f) {
    MediumPtr medium = densityCube();
    auto grid = test::namedGridLike<openvdb::FloatGrid>(*medium, grid_names::kBlackbodyTemperature, background);
    grid->tree().setValueOn(Coord(1, 2, 3), value);
    medium->other_grids.push_back(grid);
    return medium;
  };
  EXPECT_EQ(errorOf(*withTemperature(1500.0f)), "");
  EXPECT_NE(errorOf(*withTemperature(-5.0f)).find("grid 'blackbody_temperature': temperature -5 K is negative at voxel (1,2,3)"),
            std::string::npos)
      << errorOf(*withTemperature(-5.0f));
  EXPECT_NE(errorOf(*withTemperature(NAN)).find("grid 'blackbody_temperature': temperature nan K is not finite"), std::string::npos)
      << errorOf(*withTemperature(NAN));
  EXPECT_NE(errorOf(*withTemperature(1500.0f, 300.0f)).find("grid 'blackbody_temperature': background is 300, expected 0"),
            std::string::npos)
      << errorOf(*withTemperature(1500.0f, 300.0f));
  MediumPtr loud = withTemperature(1500.0f);
  loud->other_grids.back()->insertMeta(metadata_names::kBlackbodyIntensity, openvdb::FloatMetadata(2.0f));
  EXPECT_NE(errorOf(*loud).find("grid 'blackbody_temperature': metadata blackbody_intensity is 2, expected a number in [0, 1]"),
            std::string::npos)
      << errorOf(*loud);
  MediumPtr rgb = densityCube();
  rgb->other_grids.push_back(test::namedGridLike<openvdb::Vec3SGrid>(*rgb, grid_names::kBlackbodyTemperature));
  EXPECT_NE(errorOf(*rgb).find("grid 'blackbody_temperature': holds vec3s values, expected float"), std::string::npos)
      << errorOf(*rgb);
}

TEST(Emission, UnknownConventionIsRefused) {
  const MediumPtr medium = densityCube();
  openvdb::MetaMap metadata;
  metadata.insertMeta(metadata_names::kEmissionConvention, openvdb::StringMetadata("mitsuba"));
  EXPECT_NE(errorOf(*medium, metadata).find("metadata 'emission_convention' = 'mitsuba': expected cycles or pbrt"),
            std::string::npos)
      << errorOf(*medium, metadata);
  openvdb::MetaMap number;
  number.insertMeta(metadata_names::kEmissionConvention, openvdb::Int32Metadata(1));
  EXPECT_NE(errorOf(*medium, number).find("metadata 'emission_convention' is not a string"), std::string::npos);
  openvdb::MetaMap pbrt;
  pbrt.insertMeta(metadata_names::kEmissionConvention, openvdb::StringMetadata("pbrt"));
  EXPECT_EQ(errorOf(*medium, pbrt), "");
}

}  // namespace
}  // namespace vdbappear
