// vdb_displacement_prefilter: a displacement map over a microfacet BRDF to a coarser map plus the
// prefiltered SVBRDF that keeps its shadowing, masking and interreflection (chapter 4 of the
// dissertation, §4.4-4.7; docs/displacement.md).
#include "tool_main.h"

#include "libvdbappear/image/height_map_file.h"
#include "libvdbappear/io/history.h"
#include "libvdbappear/prefilter/prefiltered_surface_file.h"
#include "libvdbappear/prefilter/scaling_factorization.h"
#include "libvdbappear/render/scene_description.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/util/stopwatch.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_displacement_prefilter";

constexpr const char* kExamples = R"(Examples:
  vdb_displacement_prefilter relief.exr relief_8x.json --factor 8
  vdb_displacement_prefilter twill.exr twill_16x.json -f 16 --brdf '{"roughness": 0.2, "diffuse": [0.6, 0.1, 0.1]}'
  vdb_displacement_prefilter bumps.exr bumps_8x.json --size 0.1 --height-scale 0.01 --scaling shadowing
  vdb_displacement_prefilter noise.exr quick.json -f 8 --paths 256 --angular-resolution 9 --pairs 500 -v
  vdb_displacement_prefilter bumps.exr ball_16x.json -f 16 --stretch 0.7,0.45,0.25   # tiles over a sphere
  vdb_displacement_prefilter twill.exr twill_8x.json -f 8 --periodic   # for a surface tiled by the map

IN is a height map (docs/displacement.md §1): (n + 1)^2 pixels, the heights in its first channel.
OUT.json is a manifest; OUT.height.exr (h_low), OUT.lobes.exr (six vMF lobes per coarse cell),
OUT.T.exr and OUT.S.exr (the scaling function T(x) S(wi, wo), Eq. 4.21) are written beside it,
and OUT.stretchK.T.exr and OUT.stretchK.S.exr for each --stretch (docs/displacement.md §6).
The defaults are the chapter's sampling rates (§4.7.1); they take minutes to hours on a 1K map.)";

struct Options {
  std::string input, output, report, brdf = "{}";
  std::vector<std::string> stretches;
  double size = 1, height_scale = 1;
  int paths = 2500;
  DisplacementPrefilterSettings settings;
  bool verbose = false;
};

// The map in world units (--size, --height-scale), with a factor that divides it.
HeightField readHeightMapFor(const Options& o) {
  HeightField field = readHeightMap(o.input, o.size, o.height_scale);
  if (field.cellsX() % o.settings.factor != 0 || field.cellsY() % o.settings.factor != 0)
    throw MediumError(fmt::format("{}: the factor {} does not divide the map's {} x {} cells (a map of (n + 1) x "
                                  "(m + 1) pixels has n x m cells; try n a power of two)",
                                  o.input, o.settings.factor, field.cellsX(), field.cellsY()));
  if (o.settings.edges == TileEdges::Periodic) validateSeamless(field, o.input + " (--periodic)");
  return field;
}

// --stretch's "SX" or "SX:SY": the tile diag(SX, SY) (SY 1 when left out) of surface/tile_stretch.h.
TileStretch parseStretch(const std::string& text) {
  const std::size_t colon = text.find(':');
  double x = 0, y = 1;
  try {
    std::size_t used = 0;
    x = std::stod(text.substr(0, colon), &used);
    if (used != (colon == std::string::npos ? text.size() : colon)) throw std::invalid_argument(text);
    if (colon != std::string::npos) {
      y = std::stod(text.substr(colon + 1), &used);
      if (used != text.size() - colon - 1) throw std::invalid_argument(text);
    }
  } catch (const std::logic_error&) {
    throw std::runtime_error(fmt::format("--stretch: '{}' is not SX or SX:SY (numbers)", text));
  }
  if (!(x > 0 && y > 0 && std::isfinite(x) && std::isfinite(y)))
    throw std::runtime_error(fmt::format("--stretch: '{}': both scales must be positive and finite", text));
  return TileStretch::diagonal(x, y);
}

// Bytes as Table 4.3 counts them: 32-bit floats.
nlohmann::json storage(const HeightField& fine, const PrefilteredSurface& p) {
  std::size_t lobes = 0;
  for (const VmfMixture& d : p.ndfs) lobes = std::max(lobes, d.lobes.size());
  const auto floats = [](std::size_t n) { return 4 * n; };
  return {{"original_height", floats(std::size_t(fine.verticesX()) * fine.verticesY())},
          {"height", floats(std::size_t(p.height.verticesX()) * p.height.verticesY())},
          {"svndf", floats(p.ndfs.size() * lobes * 5)},
          {"T", floats(3 * p.scaling.T.values.size())},
          {"S", floats(3 * p.scaling.S.values.size())},
          {"B", floats(3 * p.scaling.S.relief_slopes.size())},  // the relief term's (0 without)
          {"stretched_tables", floats(3 * p.stretched.size() *
                                      (p.scaling.T.values.size() + p.scaling.S.values.size() +
                                       p.scaling.S.relief_slopes.size()))}};
}

// The range of a table's first channel (min, mean, max): what a user checks first.
nlohmann::json tableRange(const std::vector<Rgb>& values) {
  double lo = 1e300, hi = -1e300, sum = 0;
  for (const Rgb& v : values) {
    lo = std::min(lo, v.minCoeff());
    hi = std::max(hi, v.maxCoeff());
    sum += v.mean();
  }
  return {{"min", lo}, {"mean", sum / double(values.size())}, {"max", hi}};
}

// Quantiles of S's bins' relative standard errors (FactorizedScaling::S_relative_errors): whether
// the sampling rates leave the table's draw within what the image should hold.
nlohmann::json errorQuantiles(std::vector<double> errors) {
  if (errors.empty()) return nullptr;
  std::sort(errors.begin(), errors.end());
  const auto at = [&](double q) { return errors[std::size_t(q * double(errors.size() - 1))]; };
  return {{"median", at(0.5)}, {"p90", at(0.9)}, {"p99", at(0.99)}, {"max", errors.back()}};
}

// errorQuantiles() for the terminal: "median 2.66%, 90% 5.38%, 99% 11.87%".
std::string errorQuantilesText(const nlohmann::json& q) {
  if (q.is_null()) return "n/a";
  return fmt::format("median {:.2f}%, 90% {:.2f}%, 99% {:.2f}%", 100 * q["median"].get<double>(),
                     100 * q["p90"].get<double>(), 100 * q["p99"].get<double>());
}

int prefilter(const Options& o, const std::string& history) {
  tool::checkOutputs(o.input, o.output, o.report);
  for (const char* part : {"height", "lobes", "T", "S"})
    tool::checkOutputs(o.input, prefilteredPartPath(o.output, part), "");
  DisplacementPrefilterSettings settings = o.settings;
  for (const std::string& text : o.stretches) settings.stretches.push_back(parseStretch(text));
  if (settings.relief_radius > 0) tool::checkOutputs(o.input, prefilteredPartPath(o.output, "B"), "");
  for (std::size_t k = 1; k <= settings.stretches.size(); ++k)
    for (const char* table : {"T", "S", "B"})
      tool::checkOutputs(o.input, prefilteredPartPath(o.output, fmt::format("stretch{}.{}", k, table)), "");
  nlohmann::json brdf;
  try {
    brdf = nlohmann::json::parse(o.brdf);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("--brdf: not a JSON object: {}", e.what()));
  }
  const MicrofacetBrdf base = brdfFromJson(brdf, "--brdf", "brdf");
  Stopwatch clock;
  const HeightField fine = readHeightMapFor(o);
  const double read_seconds = clock.lap();

  settings.samples_per_side = std::max(1, int(std::lround(std::sqrt(double(o.paths)))));
  PrefilteredSurface prefiltered;
  {
    ProgressBar progress("scaling tables", 0);
    prefiltered = prefilterDisplacement(fine, base, settings, &progress);
  }
  const PrefilteredSurfaceFile file{std::move(prefiltered), base,
                                    {o.input, settings.factor, o.size, o.height_scale, settings.scaling}};
  const PrefilteredSurface& p = file.surface;
  const auto& f = settings.factorization;
  const nlohmann::json recorded = {
      {"history", history},
      {"paths_per_estimate", settings.samples_per_side * settings.samples_per_side},
      {"lobes", settings.ndf.lobes},
      {"smoothness_weight", settings.smoothness_weight},
      {"pairs_per_spatial_bin", f.pairs_per_spatial_bin},
      {"positions_per_angular_bin", f.positions_per_angular_bin},
      {"bias_correction", f.jackknife ? "jackknife" : "none"},
      {"shared_positions", f.shared_positions},
      {"table_sampling", kTableSampling},
      {"max_theta_degrees", f.max_theta_degrees},
      {"view_horizon_degrees", f.view_horizon_degrees},
      {"stretches", o.stretches},
      {"base_curvature", settings.base_curvature},
      {"edges", settings.edges == TileEdges::Periodic ? "periodic" : "open"},
      {"relief_radius", settings.relief_radius},
      {"seed", settings.seed},
      {"seconds", {{"read", read_seconds}, {"height", p.seconds.height}, {"ndfs", p.seconds.ndfs}, {"scaling", p.seconds.scaling}}}};
  writePrefilteredSurface(file, o.output, recorded);
  const double write_seconds = clock.lap() - p.seconds.height - p.seconds.ndfs - p.seconds.scaling;
  const nlohmann::json bytes = storage(fine, p);
  nlohmann::json ranges = {{"T", tableRange(p.scaling.T.values)}, {"S", tableRange(p.scaling.S.values)}};
  ranges["S"]["relative_standard_error"] = errorQuantiles(p.scaling.S_relative_errors);
  if (o.verbose)
    fmt::print(stderr,
               "{}: {} -> {}: {} x {} cells -> {} x {} (factor {}), {} lobes per cell, T {}^2, S {}^4{}\n"
               "{}: bytes: original {}, h_low {}, SVNDF {}, T {}, S {}\n"
               "{}: seconds: read {:.2f}, h_low {:.2f}, NDFs {:.2f}, scaling {:.2f}, write {:.2f}\n"
               "{}: T {:.3g} to {:.3g}, S {:.3g} to {:.3g} (mean {:.3g}); S's bins' relative standard error: {}\n",
               kTool, o.input, o.output, fine.cellsX(), fine.cellsY(), p.height.cellsX(), p.height.cellsY(),
               settings.factor, settings.ndf.lobes, f.spatial_resolution, f.angular_resolution,
               f.view_horizon_degrees > 0 ? fmt::format(" and the view's horizon at {} degrees", f.view_horizon_degrees) : "",
               kTool,
               bytes["original_height"].get<std::size_t>(), bytes["height"].get<std::size_t>(),
               bytes["svndf"].get<std::size_t>(), bytes["T"].get<std::size_t>(), bytes["S"].get<std::size_t>(), kTool,
               read_seconds, p.seconds.height, p.seconds.ndfs, p.seconds.scaling, write_seconds, kTool,
               ranges["T"]["min"].get<double>(), ranges["T"]["max"].get<double>(), ranges["S"]["min"].get<double>(),
               ranges["S"]["max"].get<double>(), ranges["S"]["mean"].get<double>(),
               errorQuantilesText(ranges["S"]["relative_standard_error"]));
  if (!o.report.empty())
    tool::writeJsonReport(o.report, {{"tool", kTool},
                                     {"version", kVersion},
                                     {"input", o.input},
                                     {"output", o.output},
                                     {"factor", settings.factor},
                                     {"cells", {fine.cellsX(), fine.cellsY()}},
                                     {"bytes", bytes},
                                     {"scaling", ranges},
                                     {"settings", recorded}});
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Prefilters a displacement map over a microfacet BRDF (dissertation ch. 4): a map F times coarser "
               "per side plus six vMF lobes per coarse cell and a factorised scaling function for shadowing, "
               "masking and interreflection.",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  Options o;
  DisplacementPrefilterSettings& s = o.settings;
  app.add_option("IN", o.input, "height map (EXR or any image; first channel)")->required();
  app.add_option("OUT", o.output, "output manifest (.json); its images are written beside it")
      ->required()
      ->check([](const std::string& path) {
        return path.size() > 5 && path.substr(path.size() - 5) == ".json" ? "" : "OUT must end in .json";
      });
  app.add_option("-f,--factor", s.factor, "coarse cell side in fine cells; divides the map's cells (Table 4.3: 8 to 64)")
      ->check(CLI::Range(2, 4096))
      ->capture_default_str();
  app.add_option("--size", o.size, "world width of the map, as the scene's \"size\"")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--height-scale", o.height_scale, "the map's heights times this are world units")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--brdf", o.brdf, "base micro-BRDF f_orig as JSON: {\"distribution\": \"ggx\"|\"beckmann\", \"roughness\", "
                                   "\"specular\", \"diffuse\"} (defaults ggx, 0.3, 0.04, 0)");
  const std::map<std::string, ScalingKind> kinds{{"interreflection", ScalingKind::Interreflection},
                                                 {"shadowing", ScalingKind::Shadowing}};
  app.add_option("--scaling", s.scaling, "interreflection (R_ir, Eq. 4.20) or shadowing (R, Eq. 4.12: masking and shadowing only)")
      ->transform(CLI::CheckedTransformer(kinds, CLI::ignore_case))
      ->default_str("interreflection");
  app.add_option("--lobes", s.ndf.lobes, "vMF lobes per coarse cell")->check(CLI::Range(1, 16))->capture_default_str();
  app.add_option("--smoothness", s.smoothness_weight, "w of Eq. 4.10")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--paths", o.paths, "paths (base positions in one coarse cell) per effective-BRDF estimate; rounded to a square")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--spatial-resolution", s.factorization.spatial_resolution, "M: T has M x M bins")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_option("--angular-resolution", s.factorization.angular_resolution, "N: S has N^2 x N^2 bins")
      ->check(CLI::Range(1, 32))
      ->capture_default_str();
  app.add_option("--pairs", s.factorization.pairs_per_spatial_bin, "direction pairs per T bin")
      ->check(CLI::Range(1, 10000000))
      ->capture_default_str();
  app.add_option("--positions", s.factorization.positions_per_angular_bin,
                 "stratified positions (coarse cells) per S bin, each with --paths paths; S's bins are ratios "
                 "over them, which few bias bright (docs/displacement.md §9)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  const std::map<std::string, bool> corrections{{"jackknife", true}, {"none", false}};
  app.add_option("--bias-correction", s.factorization.jackknife,
                 "of S's bins, ratios over --positions: none, or jackknife (removes their O(1/n) bias, "
                 "docs/displacement.md §9)")
      ->transform(CLI::CheckedTransformer(corrections, CLI::ignore_case))
      ->default_str("none");
  app.add_flag("--shared-positions", s.factorization.shared_positions,
               "S's bins of one view over the same positions and paths for every light direction: the tables "
               "in less time, their noise alike along the light direction (docs/displacement.md §6)");
  app.add_option("--max-theta", s.factorization.max_theta_degrees,
                 "polar angle (degrees) beyond which R is evaluated at this angle (footnote 5)")
      ->check(CLI::Range(1.0, 89.0))
      ->capture_default_str();
  app.add_option("--view-horizon", s.factorization.view_horizon_degrees,
                 "S also at views on the horizon, R evaluated at this polar angle (degrees), read beyond S's "
                 "outermost bins (83 degrees at N = 15) instead of their values; 0: none (docs/displacement.md §6)")
      ->check(CLI::Range(0.0, 89.9))
      ->capture_default_str();
  app.add_option("--stretch", o.stretches,
                 "also the scaling tables of the tile stretched to SX (along x) by SY (along y), for each "
                 "SX[:SY] given (SY 1): what a sphere's tiles are toward its poles (SX its cosine of latitude); "
                 "vdb_render reads the nearest two (docs/displacement.md §6)")
      ->delimiter(',');
  app.add_option("--base-curvature", s.base_curvature,
                 "make the tables over a convex base of this curvature (1 / world units; a sphere of radius r: "
                 "1 / r), whose bumps shadow and mask less at grazing angles; 0: a plane (docs/displacement.md §6)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag_function(
      "--periodic", [&s](std::int64_t) { s.edges = TileEdges::Periodic; },
      "make the tables over the map as one tile among its copies, whose rays leave across one edge and come back "
      "across the opposite one (as vdb_render lays tiles out); the map must tile seamlessly. Default: the map "
      "alone, its edges open, as the chapter (docs/displacement.md §6, \"Tables over a periodic tile\")");
  app.add_option("--relief-radius", s.relief_radius,
                 "also fit R's relief term, R = T(x) [S + B z(x)] with z how far each of h_low's cells stands "
                 "above the (2 R + 1)^2 cells about it, which R depends on at grazing views (a curved base's "
                 "rim); 0: the chapter's T S (docs/displacement.md §6, \"The relief term\")")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--seed", s.seed, "random seed (same output for any thread count)")->capture_default_str();
  app.add_flag("-v,--verbose", o.verbose, "print sizes, bytes per part and timings to stderr");
  app.add_option("--report", o.report, "write a JSON report (bytes per part, timings) to this file");
  tool::ThreadLimit threads(app);

  const std::string history = historyLine(kTool, argc, argv);
  return tool::run(app, argc, argv, [&] {
    threads.apply();
    s.factorization.seed = s.seed;
    s.ndf.seed = s.seed;
    return prefilter(o, history);
  });
}
