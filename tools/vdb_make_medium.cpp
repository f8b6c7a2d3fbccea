// vdb_make_medium: procedural media per docs/medium.md, deterministic under --seed.
#include "tool_main.h"

#include "libvdbappear/io/history.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/medium_summary.h"
#include "libvdbappear/io/phase_table_file.h"
#include "libvdbappear/io/phase_tables.h"
#include "libvdbappear/procedural/cloud_medium.h"
#include "libvdbappear/procedural/exemplar_medium.h"
#include "libvdbappear/procedural/hairy_ball_medium.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/procedural/shape_medium.h"
#include "libvdbappear/procedural/velvet_medium.h"
#include "libvdbappear/procedural/weave_medium.h"
#include "libvdbappear/util/stopwatch.h"
#include "libvdbappear/util/system_memory.h"
#include "libvdbappear/version.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <functional>
#include <optional>
#include <set>
#include <vector>

using namespace vdbappear;

namespace {

constexpr const char* kTool = "vdb_make_medium";

constexpr const char* kExamples = R"(Examples:
  vdb_make_medium --list
  vdb_make_medium twill --res 512 -o twill.vdb
  vdb_make_medium twill --layers 4 --res 2048 --memory 4 -o twill2048.vdb   # larger than memory
  vdb_make_medium twill --pattern satin --warp-albedo 0.9,0.8,0.3 -o satin.vdb
  vdb_make_medium velvet --res 256 -o velvet.vdb
  vdb_make_medium hairy-ball --two-materials -o ball.vdb
  vdb_make_medium cube --density 5 --albedo 0 -o absorber.vdb        # Beer-Lambert
  vdb_make_medium sphere --phase hg --g 0.9 --albedo 1 -o furnace.vdb
  vdb_make_medium cloud --res 256 -o cloud.vdb
  vdb_make_medium exemplars --count 8 --layout 16x16 -o exemplars.vdb
  vdb_make_medium random --res 64 --seed 7 -o - | vdb_sggx_downsample -f 2 - small.vdb
Options that belong to other kinds than KIND are refused. Geometry is in world units and does not
change with --res; docs/media.md describes every kind.)";

// Every flag a kind may read; unset optionals keep the kind's own defaults.
struct Flags {
  std::string kind, output;
  bool list = false, verbose = false;
  std::optional<int> resolution;
  std::uint64_t seed = 1;
  // twill, velvet, exemplars
  std::optional<std::string> pattern;
  std::optional<int> harness, yarns, layers;
  std::optional<double> fiber_density, roughness, twist_pitch;
  std::optional<std::vector<double>> warp_albedo, weft_albedo;
  // velvet
  std::optional<double> pile_height, lean, tilt;
  // hairy-ball
  bool two_materials = false;
  std::optional<double> hair_length;
  // shapes and cloud
  std::optional<double> density, size, thickness, g, variation, coverage;
  std::optional<std::vector<double>> albedo, axis;
  std::optional<std::string> phase;
  std::optional<std::string> phase_table;
  std::optional<double> g_edge;
  // exemplars
  std::optional<int> count;
  std::optional<std::string> layout;
  // random
  std::optional<double> block_fill, voxel_fill;
  // twill, velvet, hairy-ball: media larger than memory
  std::optional<double> memory_gb;
  bool in_core = false;
};

template <typename T>
void take(const std::optional<T>& flag, T& param) {
  if (flag) param = *flag;
}
void take(const std::optional<std::vector<double>>& flag, Vec3& param) {
  if (!flag) return;
  const auto& v = *flag;
  if (v.size() != 1 && v.size() != 3)
    throw std::runtime_error(fmt::format("a colour takes 1 value (grey) or 3 (R,G,B), got {}", v.size()));
  param = v.size() == 1 ? Vec3::Constant(v[0]) : Vec3(v[0], v[1], v[2]);
}

// The kinds made by fillMedium alone may be made in slabs larger than memory (docs/scaling.md §5).
FillMemory fillMemory(const Flags& f) {
  if (f.in_core) return {};
  return {f.memory_gb ? std::uint64_t(*f.memory_gb * 1e9) : defaultMemoryBudget(), f.output};
}

MediumPtr makeTwill(const Flags& f) {
  WeaveParams p;
  take(f.resolution, p.resolution);
  p.seed = f.seed;
  take(f.pattern, p.pattern);
  take(f.harness, p.harness);
  take(f.yarns, p.yarns);
  take(f.layers, p.layers);
  take(f.fiber_density, p.fiber_density);
  take(f.roughness, p.roughness);
  take(f.twist_pitch, p.twist_pitch);
  take(f.warp_albedo, p.warp_albedo);
  take(f.weft_albedo, p.weft_albedo);
  if (f.harness && p.pattern == "plain") throw std::runtime_error("--harness needs --pattern twill or satin");
  p.memory = fillMemory(f);
  return makeWeave(p);
}

MediumPtr makeVelvetKind(const Flags& f) {
  VelvetParams p;
  take(f.resolution, p.resolution);
  p.seed = f.seed;
  take(f.yarns, p.yarns);
  take(f.roughness, p.roughness);
  take(f.pile_height, p.pile_height);
  take(f.lean, p.lean_degrees);
  take(f.tilt, p.tilt_degrees);
  take(f.albedo, p.pile_albedo);
  p.memory = fillMemory(f);
  return makeVelvet(p);
}

MediumPtr makeHairyBallKind(const Flags& f) {
  HairyBallParams p;
  take(f.resolution, p.resolution);
  p.seed = f.seed;
  p.two_materials = f.two_materials;
  take(f.hair_length, p.hair_length);
  take(f.tilt, p.tilt_degrees);
  take(f.roughness, p.roughness);
  p.memory = fillMemory(f);
  return makeHairyBall(p);
}

MediumPtr makeShapeKind(const Flags& f, Shape shape) {
  ShapeParams p;
  p.shape = shape;
  take(f.resolution, p.resolution);
  p.seed = f.seed;
  take(f.size, p.size);
  take(f.thickness, p.thickness);
  take(f.density, p.density);
  take(f.albedo, p.albedo);
  if (f.phase) p.phase = phaseChoiceByName(*f.phase);
  take(f.g, p.g);
  take(f.axis, p.axis);
  take(f.roughness, p.roughness);
  take(f.variation, p.variation);
  if (f.g && p.phase != PhaseChoice::Hg) throw std::runtime_error("--g needs --phase hg");
  if (f.phase_table && f.phase) throw std::runtime_error("--phase-table replaces --phase: give one of them");
  if ((f.axis || f.roughness) && p.phase != PhaseChoice::SggxFiber && p.phase != PhaseChoice::SggxSurface)
    throw std::runtime_error("--axis and --roughness need --phase sggx-fiber or sggx-surface");
  MediumPtr medium = makeShape(p);
  if (f.phase_table) setPhaseTables(*medium, {readPhaseTableFile(*f.phase_table)});
  return medium;
}

MediumPtr makeCloudKind(const Flags& f) {
  CloudParams p;
  take(f.resolution, p.resolution);
  p.seed = f.seed;
  take(f.size, p.size);
  take(f.density, p.density);
  take(f.albedo, p.albedo);
  take(f.g, p.g);
  if (f.g_edge) p.g_edge = *f.g_edge;
  take(f.coverage, p.coverage);
  return makeCloud(p);
}

MediumPtr makeExemplarsKind(const Flags& f) {
  ExemplarParams p;
  take(f.resolution, p.resolution);
  p.seed = f.seed;
  take(f.count, p.count);
  take(f.yarns, p.block_yarns);
  take(f.fiber_density, p.fiber_density);
  take(f.roughness, p.roughness);
  int consumed = 0;
  if (f.layout && (std::sscanf(f.layout->c_str(), "%dx%d%n", &p.layout_width, &p.layout_height, &consumed) != 2 ||
                   consumed != int(f.layout->size())))
    throw std::runtime_error(fmt::format("--layout {}: expected WxH, e.g. 8x8", *f.layout));
  if (p.layout_width < 1 || p.layout_height < 1) throw std::runtime_error("--layout: W and H must be >= 1");
  return makeExemplars(p);
}

MediumPtr makeRandomKind(const Flags& f) {
  RandomMediumParams p;
  take(f.resolution, p.extent);
  p.seed = f.seed;
  take(f.block_fill, p.block_fill);
  take(f.voxel_fill, p.voxel_fill);
  return makeRandomMedium(p);
}

struct Kind {
  std::string name, description;
  std::function<MediumPtr(const Flags&)> make;
};

const std::vector<Kind>& kinds() {
  static const std::vector<Kind> all{
      {"twill", "woven fabric of twisted fibers, twill/plain/satin, two-coloured warp and weft (Fig. 9)", makeTwill},
      {"velvet", "dense upright pile fibers over a plain-weave base", makeVelvetKind},
      {"hairy-ball", "fur strands on a sphere, colour gradient (Fig. 18) or two materials (Fig. 11)", makeHairyBallKind},
      {"cube", "homogeneous or smoothly varying cube; isotropic, HG or SGGX phase",
       [](const Flags& f) { return makeShapeKind(f, Shape::Cube); }},
      {"sphere", "homogeneous or smoothly varying sphere; isotropic, HG or SGGX phase",
       [](const Flags& f) { return makeShapeKind(f, Shape::Sphere); }},
      {"slab", "homogeneous or smoothly varying slab (thin along z); isotropic, HG or SGGX phase",
       [](const Flags& f) { return makeShapeKind(f, Shape::Slab); }},
      {"cloud", "smooth heterogeneous smoke, dense and forward scattering (HG g 0.9)", makeCloudKind},
      {"exemplars", "N woven exemplar blocks side by side plus an exemplar_layout grid (modularity, §7)",
       makeExemplarsKind},
      {"random", "random sparse test medium: RGB albedo, random SPD S, zero densities", makeRandomKind},
  };
  return all;
}

// Flags that only some kinds read; given with another kind, they are refused.
struct KindFlag {
  const CLI::Option* option;
  std::set<std::string> kinds;
};

class FlagRegistry {
 public:
  explicit FlagRegistry(CLI::App& app) : app_(app) {}

  template <typename T>
  CLI::Option* add(const std::string& name, T& target, const std::string& help, std::set<std::string> kinds) {
    CLI::Option* option = app_.add_option(name, target, fmt::format("{} [{}]", help, fmt::join(kinds, ", ")));
    option->group(kinds.size() == 1 ? *kinds.begin() + " options" : "Options of several kinds");
    flags_.push_back({option, std::move(kinds)});
    return option;
  }
  CLI::Option* addFlag(const std::string& name, bool& target, const std::string& help, std::set<std::string> kinds) {
    CLI::Option* option = app_.add_flag(name, target, fmt::format("{} [{}]", help, fmt::join(kinds, ", ")));
    option->group(kinds.size() == 1 ? *kinds.begin() + " options" : "Options of several kinds");
    flags_.push_back({option, std::move(kinds)});
    return option;
  }

  void checkKind(const std::string& kind) const {
    for (const KindFlag& flag : flags_)
      if (flag.option->count() > 0 && !flag.kinds.count(kind))
        throw std::runtime_error(fmt::format("{} does not apply to kind '{}' (only to {})", flag.option->get_name(),
                                             kind, fmt::join(flag.kinds, ", ")));
  }

 private:
  CLI::App& app_;
  std::vector<KindFlag> flags_;
};

void addKindFlags(FlagRegistry& r, Flags& f) {
  const std::set<std::string> shapes{"cube", "sphere", "slab"};
  auto with = [](std::set<std::string> a, std::initializer_list<std::string> b) {
    a.insert(b);
    return a;
  };
  r.add("--pattern", f.pattern, "weave pattern: plain, twill or satin (default twill)", {"twill"})
      ->check(CLI::IsMember(WeavePattern::names()));
  r.add("--harness", f.harness, "pattern repeat: twill >= 3 (default 4), satin >= 5 (default 5)", {"twill"});
  r.add("--yarns", f.yarns, "yarns per side (exemplars: per block side, a multiple of 4; default 4)",
        {"twill", "velvet", "exemplars"})->check(CLI::Range(1, 1024));
  r.add("--layers", f.layers, "fabric layers stacked along z, one world unit apart (default 1)", {"twill"})
      ->check(CLI::Range(1, 1024));
  r.add("--fiber-density", f.fiber_density, "rho inside a fiber, 1/world unit (default 40)", {"twill", "exemplars"})
      ->check(CLI::PositiveNumber);
  r.add("--roughness", f.roughness,
        "SGGX roughness in (0,1] (twill 0.1, velvet 0.15, hairy-ball 0.2, shapes 0.3)",
        with(shapes, {"twill", "velvet", "hairy-ball", "exemplars"}))->check(CLI::Range(1e-3, 1.0));
  r.add("--twist-pitch", f.twist_pitch, "world units per turn of the fibers about the yarn (default 4)", {"twill"})
      ->check(CLI::PositiveNumber);
  r.add("--warp-albedo", f.warp_albedo, "warp colour R,G,B (default 0.85,0.3,0.45: pink)", {"twill"})
      ->delimiter(',')->expected(1, 3)->check(CLI::Range(0.0, 1.0));
  r.add("--weft-albedo", f.weft_albedo, "weft colour R,G,B (default 0.85,0.75,0.25: yellow)", {"twill"})
      ->delimiter(',')->expected(1, 3)->check(CLI::Range(0.0, 1.0));
  r.add("--pile-height", f.pile_height, "pile tip height above the base mid-plane (default 1)", {"velvet"})
      ->check(CLI::PositiveNumber);
  r.add("--lean", f.lean, "common lean of the pile toward +x, degrees (default 10)", {"velvet"})
      ->check(CLI::Range(0.0, 60.0));
  r.add("--tilt", f.tilt, "random tilt of each fiber, degrees (velvet 8, hairy-ball 25)", {"velvet", "hairy-ball"})
      ->check(CLI::Range(0.0, 60.0));
  r.addFlag("--two-materials", f.two_materials, "two fur materials, +x and -x hemispheres (Fig. 11)", {"hairy-ball"});
  r.add("--hair-length", f.hair_length, "strand length, ball radius 1 (default 0.6)", {"hairy-ball"})
      ->check(CLI::PositiveNumber);
  r.add("--density", f.density, "rho, 1/world unit (shapes 10; cloud: peak, 40)", with(shapes, {"cloud"}))
      ->check(CLI::NonNegativeNumber);
  r.add("--albedo", f.albedo, "albedo R[,G,B] (shapes 0.8, cloud 0.98; velvet: pile colour)",
        with(shapes, {"cloud", "velvet"}))->delimiter(',')->expected(1, 3)->check(CLI::Range(0.0, 1.0));
  r.add("--size", f.size, "world size: cube edge, sphere diameter, slab width (1); cloud diameter (2)",
        with(shapes, {"cloud"}))->check(CLI::PositiveNumber);
  r.add("--thickness", f.thickness, "slab thickness along z, world units (default 0.25)", {"slab"})
      ->check(CLI::PositiveNumber);
  r.add("--phase", f.phase, "isotropic, hg, sggx-fiber or sggx-surface (default isotropic)", shapes)
      ->check(CLI::IsMember(phaseChoiceNames()));
  r.add("--phase-table", f.phase_table,
        "a tabulated phase function for every voxel (phase_table): JSON or numbers on bins ascending in mu, as "
        "vdb_similarity --table reads; excludes --phase", shapes);
  r.add("--g", f.g, "HG asymmetry in (-1,1) (shapes with --phase hg: 0; cloud: 0.9)", with(shapes, {"cloud"}))
      ->check(CLI::Range(-0.999, 0.999));
  r.add("--axis", f.axis, "SGGX fiber tangent or surface normal X,Y,Z (default 0,0,1)", shapes)
      ->delimiter(',')->expected(3);
  r.add("--variation", f.variation, "smooth density variation amplitude in [0,1) (default 0)", shapes)
      ->check(CLI::Range(0.0, 0.999));
  r.add("--g-edge", f.g_edge, "per-voxel g (an hg_g grid): this at the thin edge, rising with density to --g at the peak", {"cloud"})
      ->check(CLI::Range(-0.999, 0.999));
  r.add("--coverage", f.coverage, "share of the sphere that holds smoke (default 0.5)", {"cloud"})
      ->check(CLI::Range(0.01, 1.0));
  r.add("--count", f.count, "number of exemplars N (default 6)", {"exemplars"})->check(CLI::Range(1, 4096));
  r.add("--layout", f.layout, "blocks of the synthesized sheet, WxH (default 8x8)", {"exemplars"});
  r.add("--memory", f.memory_gb,
        "GB: memory budget; past a quarter of it the medium is made in slabs that wait on scratch files in OUT's "
        "folder (default: a quarter of the machine's memory, at most 4)", {"twill", "velvet", "hairy-ball"})
      ->check(CLI::PositiveNumber);
  r.addFlag("--in-core", f.in_core, "make the whole medium in memory, however large (the same file)",
            {"twill", "velvet", "hairy-ball"});
  r.add("--block-fill", f.block_fill, "fraction of 8^3 blocks occupied (default 0.5)", {"random"})
      ->check(CLI::Range(0.0, 1.0));
  r.add("--voxel-fill", f.voxel_fill, "fraction of voxels active in an occupied block (default 0.6)", {"random"})
      ->check(CLI::Range(0.0, 1.0));
}

int make(const Flags& flags, const FlagRegistry& registry, const std::string& history) {
  if (flags.list) {
    for (const Kind& kind : kinds()) fmt::print("{:<11} {}\n", kind.name, kind.description);
    return 0;
  }
  const auto kind = std::find_if(kinds().begin(), kinds().end(), [&](const Kind& k) { return k.name == flags.kind; });
  if (flags.kind.empty()) throw std::runtime_error("no KIND given (see --list)");
  if (kind == kinds().end()) throw std::runtime_error(fmt::format("unknown kind '{}' (see --list)", flags.kind));
  registry.checkKind(flags.kind);
  if (flags.output.empty()) throw std::runtime_error("no output: give -o OUT (- for stdout)");
  checkWritable(flags.output);
  Stopwatch clock;
  const MediumPtr medium = kind->make(flags);
  const double make_seconds = clock.lap();
  writeMedium(*medium, flags.output, history);
  if (flags.verbose) {
    const MediumSummary s = summarize(*medium);
    fmt::print(stderr, "{}: {}: {} active voxels, {:.1f} MB of grids, made in {:.2f} s, written in {:.2f} s\n", kTool,
               flags.kind, s.active_voxels, s.memory_bytes / 1e6, make_seconds, clock.lap());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Writes procedural media (density, albedo, SGGX or HG) for tests, demos and benchmarks.", kTool);
  app.footer(kExamples);
  app.set_version_flag("--version", kVersion);
  Flags flags;
  app.add_option("KIND", flags.kind, "kind of medium (see --list)");
  app.add_option("-o,--output", flags.output, "output medium (.vdb); - writes a VDB stream to stdout");
  app.add_flag("--list", flags.list, "list the kinds and exit");
  app.add_option("--res", flags.resolution,
                 "voxels along the largest side (default 128; cube, sphere, slab 64; exemplars: per block, 64)")
      ->check(CLI::Range(4, 4096));
  app.add_option("--seed", flags.seed, "random seed: same seed, same medium (shapes: the phase of --variation)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag("-v,--verbose", flags.verbose, "print voxel counts and timings to stderr");
  FlagRegistry registry(app);
  addKindFlags(registry, flags);
  tool::ThreadLimit threads(app);

  const std::string history = historyLine(kTool, argc, argv);
  return tool::run(app, argc, argv, [&] {
    threads.apply();
    return make(flags, registry, history);
  });
}
