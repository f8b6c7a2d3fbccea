// vdb_sh_lightgrid: many polygonal area lights prefiltered into a grid of spherical-harmonic
// coefficients and their analytic spatial gradients (Wu 2020, dissertation ch. 5), read back by
// tricubic Hermite interpolation.
#include "tool_main.h"

#include "libvdbappear/io/history.h"
#include "libvdbappear/io/light_list_file.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/sh_light_grid_file.h"
#include "libvdbappear/lightgrid/adaptive_sh_grid.h"
#include "libvdbappear/lightgrid/sh_light_grid.h"
#include "libvdbappear/lightgrid/zonal_factorisation.h"
#include "libvdbappear/math/spherical_harmonics.h"
#include "libvdbappear/medium/medium_view.h"
#include "libvdbappear/render/mesh_file.h"
#include "libvdbappear/render/scene_description.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/progress.h"
#include "libvdbappear/util/stopwatch.h"
#include "libvdbappear/util/system_memory.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <map>
#include <optional>
#include <stdexcept>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_sh_lightgrid";

constexpr const char* kExamples = R"(Examples:
  vdb_sh_lightgrid --lights lights.json --bbox -1,-1,-1,1,1,1 --res 8 -o lightgrid.vdb
  vdb_sh_lightgrid --lights lights.json --medium cloud.vdb --voxel-size 0.25 -o lightgrid.vdb --report r.json
  vdb_sh_lightgrid --scene scene.json -o lightgrid.vdb     the scene's area lights, over its medium
  vdb_render --scene scene.json --sh-lightgrid lightgrid.vdb -o image.exr
  vdb_sh_lightgrid --lights lights.json --bbox -1,-1,-1,1,1,1 --res 4 --levels 3 -o adaptive.vdb   finer near lights
  vdb_sh_lightgrid --lights lights.json --lmax 8 --probe 0,0,0.5 --json      analytic, no grid
  vdb_sh_lightgrid --grid lightgrid.vdb --probe 0,0,0.5 --interp trilinear --json
  vdb_sh_lightgrid --grid lightgrid.vdb --probe-points points.txt > coeffs.jsonl   one JSON line per point

Lights file: {"lights": [{"vertices": [[x,y,z], ...], "radiance": [r,g,b], "two_sided": false}]}.
A light is a planar polygon of uniform radiance; one-sided lights emit toward the side of their
counter-clockwise normal (p1 - p0) x (p2 - p0). The grid holds, at each node, the RGB SH
coefficients L_lm = integral of Y_lm over the lights seen from the node (unshadowed), and their
gradients, computed analytically (Eq. 5.23-5.32). Nodes: --res along the longest axis of the box,
at equal spacing on all axes; with --levels, cells split where the lighting varies fast. docs/sh_lightgrid.md and docs/medium.md §11 describe the file.)";

struct Options {
  std::string lights_file, grid_file, output, report, medium, scene, points_file, interp = "hermite";
  std::optional<std::vector<double>> bbox, probe;
  int lmax = 8, res = 8;
  double voxel_size = 0;
  AdaptiveGridOptions adaptive{0, 0, 0.05, 1u << 20};  // max_level 0: uniform
  bool json = false;
};

const std::map<std::string, CellInterpolation> kInterpolations = {
    {"hermite", CellInterpolation::kHermite}, {"trilinear", CellInterpolation::kTrilinear}, {"taylor", CellInterpolation::kTaylor}};

Vec3 vec3(const std::vector<double>& v, std::size_t first = 0) { return Vec3(v[first], v[first + 1], v[first + 2]); }

nlohmann::json coeffsJson(const std::vector<Vec3>& coeffs) {
  nlohmann::json list = nlohmann::json::array();
  for (const Vec3& c : coeffs) list.push_back({c.x(), c.y(), c.z()});
  return list;
}

nlohmann::json gradientsJson(const std::vector<Mat3>& gradients) {
  nlohmann::json list = nlohmann::json::array();
  for (const Mat3& g : gradients) {
    nlohmann::json rgb = nlohmann::json::array();
    for (int c = 0; c < 3; ++c) rgb.push_back({g(c, 0), g(c, 1), g(c, 2)});
    list.push_back(rgb);
  }
  return list;
}

// The points to probe: --probe X,Y,Z, or --probe-points FILE with one "x y z" (or x,y,z) per line.
std::vector<Vec3> probePoints(const Options& o) {
  if (o.probe) {
    if (!vec3(*o.probe).allFinite()) throw std::invalid_argument("--probe: X,Y,Z must be finite numbers");
    return {vec3(*o.probe)};
  }
  std::ifstream file_stream;
  if (o.points_file != "-") {
    file_stream.open(o.points_file);
    if (!file_stream) throw std::runtime_error(o.points_file + ": cannot open the points file");
  }
  std::istream& in = o.points_file == "-" ? std::cin : file_stream;
  std::vector<Vec3> points;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::replace(line.begin(), line.end(), ',', ' ');
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    std::istringstream words(line);
    Vec3 p;
    std::string extra;
    if (!(words >> p.x() >> p.y() >> p.z()) || (words >> extra) || !p.allFinite())
      throw std::runtime_error(fmt::format("{}: line {}: expected three numbers x y z", o.points_file, number));
    points.push_back(p);
  }
  if (points.empty()) throw std::runtime_error(o.points_file + ": no points");
  return points;
}

// One probe: indented JSON for --probe --json, one line per point for --probe-points, else a summary.
void printProbe(const nlohmann::json& j, const Options& o) {
  if (!o.points_file.empty()) {
    std::cout << j.dump() << "\n";
    return;
  }
  if (o.json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  const auto& c = j["coeffs"][0];
  fmt::print("L_00 = ({:.6g}, {:.6g}, {:.6g}); {} coefficients, --json prints them all\n", c[0].get<double>(),
             c[1].get<double>(), c[2].get<double>(), j["coeffs"].size());
}

nlohmann::json pointJson(const Vec3& x) { return {x.x(), x.y(), x.z()}; }

// Analytic coefficients and gradients.
int probeLights(const Options& o) {
  const std::vector<PolygonLight> lights = readLightList(o.lights_file);
  const ZonalFactorisation zh(o.lmax);
  for (const Vec3& x : probePoints(o)) {
    const ShLighting sh = shLighting(lights, x, zh);
    printProbe({{"lmax", o.lmax}, {"point", pointJson(x)}, {"lights", lights.size()}, {"coeffs", coeffsJson(sh.coeffs)},
                {"gradients", gradientsJson(sh.gradients)}},
               o);
  }
  return 0;
}

// Interpolated coefficients from a grid file.
int probeGrid(const Options& o) {
  const std::shared_ptr<const ShGridLookup> grid = readShLightGrid(o.grid_file);
  for (const Vec3& x : probePoints(o)) {
    const std::vector<Vec3> coeffs = grid->interpolate(x, kInterpolations.at(o.interp));
    printProbe({{"lmax", grid->lmax()}, {"point", pointJson(x)}, {"interpolation", o.interp}, {"coeffs", coeffsJson(coeffs)}}, o);
  }
  return 0;
}

// The bounds of a scene file's medium, or else of its meshes (lights and the ground bound nothing).
Aabb sceneBounds(const SceneDescription& scene, const std::string& scene_file) {
  if (!scene.medium.empty()) return MediumView(readMedium(scene.medium), Interpolation::kNearest).worldBounds();
  Aabb bounds;
  for (const MeshDescription& mesh : scene.meshes)
    for (const Triangle& t : readMesh(mesh.file))
      for (const Vec3& v : t) bounds.extend(v);
  if (bounds.empty()) throw std::invalid_argument(fmt::format("{}: the scene has no medium or mesh to bound the grid: give --bbox", scene_file));
  return bounds;
}

// The grid's box: --bbox, or the bounds of --medium's density, or of the scene (--scene).
void gridBox(const Options& o, const std::optional<SceneDescription>& scene, Vec3* lo, Vec3* hi) {
  if (o.bbox) {
    *lo = vec3(*o.bbox, 0);
    *hi = vec3(*o.bbox, 3);
  } else {
    const Aabb bounds = scene ? sceneBounds(*scene, o.scene) : MediumView(readMedium(o.medium), Interpolation::kNearest).worldBounds();
    if (bounds.empty()) throw std::invalid_argument(fmt::format("{}: the medium has no active voxels: give --bbox", o.scene.empty() ? o.medium : o.scene));
    *lo = bounds.lo;
    *hi = bounds.hi;
  }
  if (!lo->allFinite() || !hi->allFinite()) throw std::invalid_argument("--bbox: the box must be finite");
  if (!((*hi - *lo).array() >= 0).all() || !((*hi - *lo).maxCoeff() > 0))
    throw std::invalid_argument("--bbox: a max is below its min, or the box is a point");
}

// --lights, or the area lights of the scene (--scene).
std::vector<PolygonLight> gridLights(const Options& o, const std::optional<SceneDescription>& scene) {
  if (!o.lights_file.empty()) return readLightList(o.lights_file);
  std::vector<PolygonLight> lights;
  try {
    lights = sceneAreaLights(*scene);
  } catch (const std::runtime_error& e) {
    throw MediumError(fmt::format("{}: {}", o.scene, e.what()));
  }
  if (lights.empty()) throw MediumError(fmt::format("{}: the scene has no area lights (quad, polygon, triangle): give --lights", o.scene));
  return lights;
}

// Memory a node takes while the grid is built and written: its coefficients and gradients in
// double (ShLighting) and, while writing, their float copies in the VDB grids.
double bytesPerNode(int lmax) { return shCount(lmax) * (3 + 9) * (sizeof(double) + sizeof(float)); }

// A grid that cannot fit in memory fails here with a message, not later by the kernel's hand.
void checkGridMemory(double nodes, int lmax) {
  const double needed = nodes * bytesPerNode(lmax), available = physicalMemoryBytes();
  if (available > 0 && needed > available)
    throw std::invalid_argument(fmt::format("the grid needs about {:.1f} GB ({:.0f} nodes at lmax {}), more than this machine's "
                                            "{:.1f} GB: use a coarser --res or --voxel-size, or a lower --lmax",
                                            needed / 1e9, nodes, lmax, available / 1e9));
}

std::shared_ptr<const ShGridLookup> evaluateGrid(const Options& o, const std::vector<PolygonLight>& lights, const Vec3& lo,
                                                 const Vec3& hi, nlohmann::json* report) {
  if (o.adaptive.max_level > 0) {
    AdaptiveGridOptions adaptive = o.adaptive;
    adaptive.base_resolution = o.res;
    // The refinement budget, within half the machine's memory.
    adaptive.max_nodes = std::min<double>(adaptive.max_nodes, std::max(8.0, 0.5 * physicalMemoryBytes() / bytesPerNode(o.lmax)));
    checkGridMemory(std::pow(double(o.res), 3), o.lmax);
    ProgressBar progress("refining the adaptive grid", 0);
    auto grid = std::make_shared<AdaptiveShGrid>(AdaptiveShGrid::build(lights, o.lmax, lo, hi, adaptive, &progress));
    std::vector<std::size_t> cells;
    for (int level = 0; level < grid->levels(); ++level) cells.push_back(grid->cellCount(level));
    (*report)["adaptive"] = {{"levels", o.adaptive.max_level}, {"tolerance", o.adaptive.tolerance}, {"cells_per_level", cells}};
    return grid;
  }
  const ShGridLayout layout = o.voxel_size > 0 ? ShGridLayout::withSpacing(lo, hi, o.voxel_size) : ShGridLayout::covering(lo, hi, o.res);
  checkGridMemory(double(layout.count()), o.lmax);
  ProgressBar progress("evaluating SH at the nodes", layout.count());
  auto grid = std::make_shared<ShLightGrid>(ShLightGrid::evaluate(lights, o.lmax, layout, &progress));
  progress.finish();
  (*report)["nodes_per_axis"] = {layout.nodes.x(), layout.nodes.y(), layout.nodes.z()};
  return grid;
}

int buildGrid(const Options& o, const std::string& history) {
  tool::checkOutputs(o.lights_file.empty() ? o.scene : o.lights_file, o.output, o.report);
  std::optional<SceneDescription> scene;
  if (!o.scene.empty()) scene = readSceneFile(o.scene);  // read once; its errors name the file
  const std::vector<PolygonLight> lights = gridLights(o, scene);
  Vec3 lo, hi;
  gridBox(o, scene, &lo, &hi);
  nlohmann::json report = {{"tool", kTool}, {"version", kVersion}, {"lights", lights.size()}, {"lmax", o.lmax},
                           {"coefficients", shCount(o.lmax)}};
  Stopwatch clock;
  const std::shared_ptr<const ShGridLookup> grid = evaluateGrid(o, lights, lo, hi, &report);
  const double seconds = clock.lap();
  writeShLightGrid(*grid, o.output, history);
  const double write_seconds = clock.lap();
  const ShLattice lattice = grid->lattice();
  fmt::print(stderr, "{}: {} lights on {} nodes ({}, finest spacing {:g}), lmax {}: {:.2f} s\n", kTool, lights.size(),
             grid->nodeCount(), lattice.levels > 0 ? fmt::format("adaptive, {} levels", lattice.levels) : "uniform",
             lattice.spacing, o.lmax, seconds);
  report["nodes"] = grid->nodeCount();
  report["origin"] = {lattice.origin.x(), lattice.origin.y(), lattice.origin.z()};
  report["finest_spacing"] = lattice.spacing;
  report["output"] = {{"path", o.output}, {"bytes", tool::fileSize(o.output)}};
  report["seconds"] = {{"evaluate", seconds}, {"write", write_seconds}};
  if (!o.report.empty()) tool::writeJsonReport(o.report, report);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Polygonal area lights as a grid of spherical-harmonic coefficients and analytic SH gradients "
               "(Wu 2020, ch. 5), read back by tricubic Hermite interpolation.",
               kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  Options o;
  auto* lights = app.add_option("--lights", o.lights_file, "lights file (JSON); - reads stdin");
  app.add_option("--grid", o.grid_file, "probe an existing SH light grid (.vdb) instead of the lights")
                   ->check(CLI::ExistingFile)
                   ->excludes(lights);
  app.add_option("-o,--output", o.output, "output SH light grid (.vdb); - writes a VDB stream to stdout");
  app.add_option("--lmax", o.lmax, "highest SH band")->check(CLI::Range(0, 20))->capture_default_str();
  auto* res = app.add_option("--res", o.res, "nodes along the longest axis of the box")->check(CLI::Range(2, 4096))->capture_default_str();
  auto* voxel_size = app.add_option("--voxel-size", o.voxel_size, "node spacing in world units (instead of --res)")
                         ->check(CLI::PositiveNumber)
                         ->excludes(res);
  app.add_option("--levels", o.adaptive.max_level,
                 "adaptive grid: split cells in eight up to this many times where the error estimate exceeds "
                 "--tolerance (0: uniform grid; --res is then the base resolution)")
      ->check(CLI::Range(0, 8))
      ->excludes(voxel_size)
      ->capture_default_str();
  app.add_option("--tolerance", o.adaptive.tolerance,
                 "adaptive grid: split a cell where Hermite and trilinear differ at its centre by more than this "
                 "times the largest L_00 of the base nodes")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  auto* bbox = app.add_option("--bbox", o.bbox, "box of the grid: xmin,ymin,zmin,xmax,ymax,zmax")->delimiter(',')->expected(6);
  auto* medium = app.add_option("--medium", o.medium, "box of the grid: the bounds of this medium's density")
                     ->check(CLI::ExistingFile)
                     ->excludes(bbox);
  app.add_option("--scene", o.scene,
                 "a vdb_render scene file: its area lights (unless --lights) and its box (the bounds of its medium, or "
                 "of its meshes; unless --bbox)")
      ->check(CLI::ExistingFile)
      ->excludes(medium);
  auto* probe = app.add_option("--probe", o.probe, "print the coefficients at X,Y,Z (analytic with --lights, interpolated with --grid)")
                    ->delimiter(',')
                    ->expected(3);
  app.add_option("--probe-points", o.points_file, "like --probe for every point of FILE (x y z per line; - for stdin): JSON lines")
      ->excludes(probe);
  app.add_option("--interp", o.interp, "with --grid: hermite (Algorithm 4), trilinear or taylor")
      ->check(CLI::IsMember({"hermite", "trilinear", "taylor"}))
      ->capture_default_str();
  app.add_flag("--json", o.json, "probe: print one JSON object {lmax, coeffs, gradients}");
  app.add_option("--report", o.report, "grid: write a JSON report (nodes, timings) to this file");
  tool::ThreadLimit threads(app);

  const std::string history = historyLine(kTool, argc, argv);
  return tool::run(app, argc, argv, [&] {
    threads.apply();
    if (o.probe || !o.points_file.empty()) {
      if (!o.output.empty()) throw std::invalid_argument("--probe prints; it writes no grid (drop -o)");
      if (!o.grid_file.empty()) return probeGrid(o);
      if (o.lights_file.empty()) throw std::invalid_argument("--probe needs --lights FILE or --grid FILE");
      if (o.lights_file == "-" && o.points_file == "-") throw std::invalid_argument("--lights and --probe-points cannot both read stdin");
      return probeLights(o);
    }
    if (o.json) throw std::invalid_argument("--json is for --probe");
    if (o.lights_file.empty() && o.scene.empty()) throw std::invalid_argument("give --lights FILE or --scene FILE (and -o GRID.vdb), or --probe X,Y,Z");
    if (o.output.empty()) throw std::invalid_argument("give -o GRID.vdb for the grid (or --probe X,Y,Z)");
    if (!o.bbox && o.medium.empty() && o.scene.empty()) throw std::invalid_argument("give the grid's box: --bbox, --medium or --scene");
    return buildGrid(o, history);
  });
}
