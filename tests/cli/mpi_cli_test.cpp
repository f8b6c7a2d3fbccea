// vdb_render and vdb_optimize_weights under mpirun (built when CMake finds MPI; docs/scaling.md):
// images and weight trajectories bit-identical at 1 and 2 ranks, to the process started without
// mpirun and to the tools built without MPI, whatever the thread count; a checkpoint written at 2 ranks resumes at 1; and the failures
// (a rank that cannot read the medium, a rank that dies, a flag error, stdin) end the job with one
// error line, a non-zero status and the previous output intact.
#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

namespace vdbappear {
namespace {

using test::kLobeCluster;
using test::kMakeMedium;
using test::kOptimize;
using test::kOptimizeWithoutMpi;
using test::kRender;
using test::kRenderWithoutMpi;
using test::quote;
using test::runCommand;
using test::TempDir;

// Open MPI refuses root without the two settings (CI runs as root); more ranks than cores are
// allowed; -q keeps mpirun's own banners out of stderr; containers may forbid the shared-memory
// transport's single-copy mechanism (process_vm_readv), which these small messages do not need.
// In sanitizer builds the ranks keep AddressSanitizer and UBSan but not LeakSanitizer: Open MPI 4.1
// leaves what MPI_Init allocates unfreed, much of it in plugins unloaded by MPI_Finalize, whose
// frames LeakSanitizer can then name by no module that a suppression could match.
std::string mpirun(int ranks) {
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none "
         "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\" " +
         quote(MPIEXEC) + " -q --oversubscribe -n " + std::to_string(ranks) + " ";
}

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

int errorLines(const std::string& err, const std::string& tool) {
  std::istringstream in(err);
  int n = 0;
  for (std::string line; std::getline(in, line);) n += line.rfind(tool + ": error", 0) == 0;
  return n;
}

// A two-coloured twill and its 2-lobe, 2-cluster reduction at factor 4 (lobe weights and clusters:
// every AOV of vdb_render, and a medium vdb_optimize_weights takes).
struct Media {
  TempDir dir;
  std::string full = dir.path("twill.vdb"), lobes = dir.path("lobes.vdb");
  Media() {
    EXPECT_EQ(runCommand(kMakeMedium + " twill --yarns 2 --res 32 -o " + quote(full)).status, 0);
    EXPECT_EQ(runCommand(kLobeCluster + " -f 4 --lobes 2 --clusters 2 " + quote(full) + " " + quote(lobes)).status, 0);
  }
};

// The image and every AOV, gradient images included, identical to the byte: built without MPI,
// without mpirun, and at 1 and 2 ranks with 1 and 2 threads each.
TEST(MpiCli, RenderIsBitIdenticalAtEveryRankAndThreadCount) {
  const Media m;
  const std::string args = " --res 40x24 --spp 6 --seed 7 --view -x --sun 1,1,-1,2 --aov alpha,variance,cluster,dweights ";
  const std::string without_mpi = m.dir.path("without_mpi.exr"), solo = m.dir.path("solo.exr");
  ASSERT_EQ(runCommand(kRenderWithoutMpi + " " + quote(m.lobes) + args + "-o " + quote(without_mpi)).status, 0);
  const std::string expected = bytesOf(without_mpi);
  ASSERT_GT(expected.size(), 1000u);
  ASSERT_EQ(runCommand(kRender + " " + quote(m.lobes) + args + "-o " + quote(solo)).status, 0);
  EXPECT_TRUE(bytesOf(solo) == expected) << "without mpirun";
  for (const auto& [ranks, threads] : {std::pair{1, 2}, std::pair{2, 1}, std::pair{2, 2}}) {
    const std::string name = "r" + std::to_string(ranks) + "t" + std::to_string(threads);
    const std::string out = m.dir.path(name + ".exr"), report = m.dir.path(name + ".json");
    const auto r = runCommand(mpirun(ranks) + kRender + " " + quote(m.lobes) + args + "-j " + std::to_string(threads) +
                              " -o " + quote(out) + " --report " + quote(report));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(bytesOf(out) == expected) << ranks << " ranks, " << threads << " threads";
    if (ranks == 1) continue;
    // Both ranks took tiles, and their paths add up to the image's.
    std::ifstream in(report);
    const auto j = nlohmann::json::parse(in);
    ASSERT_EQ(j["ranks"].size(), 2u);
    EXPECT_GT(j["ranks"][0]["paths"].get<std::uint64_t>(), 0u);
    EXPECT_GT(j["ranks"][1]["paths"].get<std::uint64_t>(), 0u);
    EXPECT_EQ(j["ranks"][0]["paths"].get<std::uint64_t>() + j["ranks"][1]["paths"].get<std::uint64_t>(), 40u * 24u * 6u);
  }
}

// Negative control: the comparison above sees a change of one sample's worth (another seed).
TEST(MpiCli, AnotherSeedIsAnotherImage) {
  const Media m;
  const std::string a = m.dir.path("a.exr"), b = m.dir.path("b.exr");
  ASSERT_EQ(runCommand(kRender + " --res 40x24 --spp 6 --seed 7 " + quote(m.full) + " -o " + quote(a)).status, 0);
  ASSERT_EQ(runCommand(mpirun(2) + kRender + " --res 40x24 --spp 6 --seed 8 " + quote(m.full) + " -o " + quote(b)).status, 0);
  EXPECT_FALSE(bytesOf(a) == bytesOf(b));
}

// With --time, the root's clock sets every pass for both ranks: the job ends, and the report counts
// every rank's paths (spp x pixels).
TEST(MpiCli, TimedRenderEndsTogether) {
  const Media m;
  const std::string out = m.dir.path("t.exr"), report = m.dir.path("t.json");
  const auto r = runCommand(mpirun(2) + kRender + " --res 32x16 --time 0.5 --spp 100000 -j 1 " + quote(m.full) + " -o " +
                            quote(out) + " --report " + quote(report));
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(report);
  const auto j = nlohmann::json::parse(in);
  EXPECT_GT(j["spp"].get<int>(), 0);
  EXPECT_LT(j["spp"].get<int>(), 100000);
  EXPECT_EQ(j["paths"].get<std::uint64_t>(), j["spp"].get<std::uint64_t>() * 32 * 16);
}

std::vector<nlohmann::json> logLines(const std::string& path) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

// The weight trajectory (E, gradient, step and factors of every iteration) is the same at 2 ranks as
// without mpirun and as built without MPI; a checkpoint written at 2 ranks resumes at 1 to the same
// end; the reference cache that 2 ranks fill, alone or two jobs at once, serves the next run whole.
TEST(MpiCli, OptimisationTrajectoryIsIdenticalAndResumesAtAnotherRankCount) {
  const Media m;
  const std::string quick = " --resolution 16 --spp 4 --reference-spp 8 --tolerance 0 ";
  const auto run = [&](const std::string& launcher, const std::string& name, const std::string& extra,
                       const std::string& tool = kOptimize) {
    const std::string out = m.dir.path(name + ".vdb");
    const auto r = runCommand(launcher + tool + quick + extra + " --log " + quote(m.dir.path(name + ".jsonl")) + " " +
                              quote(m.full) + " " + quote(m.lobes) + " " + quote(out));
    EXPECT_EQ(r.status, 0) << name << ": " << r.err;
    return logLines(m.dir.path(name + ".jsonl"));
  };
  const std::string cache = " --cache " + quote(m.dir.path("cache")) + " ";
  const auto solo = run("", "solo", "--iterations 4 --no-cache");
  const auto two = run(mpirun(2), "two", "--iterations 4 -j 1" + cache);
  const auto without_mpi = run("", "without_mpi", "--iterations 4 --no-cache", kOptimizeWithoutMpi);
  ASSERT_EQ(solo.size(), 4u);
  ASSERT_EQ(two.size(), 4u);
  ASSERT_EQ(without_mpi.size(), 4u);
  for (std::size_t t = 0; t < solo.size(); ++t)
    for (const char* key : {"E", "gradient", "step", "factors"}) {
      EXPECT_EQ(solo[t][key], two[t][key]) << "iteration " << t + 1 << ", " << key;
      EXPECT_EQ(solo[t][key], without_mpi[t][key]) << "iteration " << t + 1 << ", " << key;
    }

  const std::string checkpoint = m.dir.path("two.ckpt");
  run(mpirun(2), "first", "--iterations 2 -v --checkpoint " + quote(checkpoint) + cache);
  const auto resumed = run("", "resumed", "--iterations 4 --resume " + quote(checkpoint) + cache);
  ASSERT_EQ(resumed.size(), 4u);
  EXPECT_EQ(resumed.back()["factors"], solo.back()["factors"]);
  EXPECT_EQ(resumed.back()["E"], solo.back()["E"]);

  // Two 2-rank jobs that fill one new cache at the same time: both end well, and every entry is whole
  // (the next run takes them all).
  const std::string shared = " --cache " + quote(m.dir.path("shared-cache")) + " ";
  const auto job = [&](const std::string& name) {
    return mpirun(2) + kOptimize + quick + "--iterations 1 -j 1" + shared + quote(m.full) + " " + quote(m.lobes) + " " +
           quote(m.dir.path(name + ".vdb"));
  };
  const auto both = runCommand("(" + job("a") + ") & a=$!; (" + job("b") + ") & b=$!; wait $a && wait $b");
  ASSERT_EQ(both.status, 0) << both.err;
  const std::string shared_report = m.dir.path("shared.json");
  ASSERT_EQ(runCommand(kOptimize + quick + "--iterations 1" + shared + "--report " + quote(shared_report) + " " + quote(m.full) +
                       " " + quote(m.lobes) + " " + quote(m.dir.path("c.vdb")))
                .status,
            0);
  std::ifstream shared_in(shared_report);
  const auto shared_json = nlohmann::json::parse(shared_in);
  EXPECT_EQ(shared_json["cache_hits"], shared_json["references"]);
  EXPECT_GT(shared_json["references"].get<int>(), 0);

  const std::string report = m.dir.path("again.json");
  const auto again = runCommand(mpirun(2) + kOptimize + quick + "--iterations 1" + cache + "--report " + quote(report) + " " +
                                quote(m.full) + " " + quote(m.lobes) + " " + quote(m.dir.path("again.vdb")));
  ASSERT_EQ(again.status, 0) << again.err;
  std::ifstream in(report);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["cache_hits"], j["references"]);
}

// A rank that cannot read the medium: one error line, from that rank, naming the file; status 1 and
// the previous output as it was.
TEST(MpiCli, ARankThatCannotReadTheMediumEndsTheJobOnce) {
  const Media m;
  const std::string out = m.dir.path("out.exr");
  { std::ofstream(out) << "previous"; }
  const std::string missing = m.dir.path("only-on-rank-0.vdb");
  const std::string script = "if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then m=" + quote(missing) + "; else m=" + quote(m.full) +
                             "; fi; exec " + kRender + " \"$m\" --res 16 --spp 2 -o " + quote(out);
  const auto r = runCommand(mpirun(2) + "sh -c " + quote(script));
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(errorLines(r.err, "vdb_render"), 1) << r.err;
  EXPECT_NE(r.err.find("rank 1 of 2"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("only-on-rank-0.vdb"), std::string::npos) << r.err;
  EXPECT_EQ(bytesOf(out), "previous");
}

// A rank killed in the middle of a render ends the whole job; the previous output stays.
TEST(MpiCli, ARankThatDiesEndsTheJob) {
  const Media m;
  const std::string out = m.dir.path("out.exr");
  { std::ofstream(out) << "previous"; }
  const std::string render = kRender + " " + quote(m.full) + " --res 256 --spp 4096 -j 1 -o " + quote(out);
  const std::string script = "if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then " + render +
                             " & p=$!; sleep 1; kill -9 $p; wait $p; exit $?; else exec " + render + "; fi";
  const auto r = runCommand(mpirun(2) + "sh -c " + quote(script));
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(bytesOf(out), "previous");
}

// The same bad flag on every rank: the root alone says so. Bad input agreed by every rank (a
// missing file): one line. stdin reaches one rank only: refused.
TEST(MpiCli, ErrorsOfEveryRankAreReportedOnce) {
  const Media m;
  const auto flag = runCommand(mpirun(2) + kRender + " " + quote(m.full) + " --spp nonsense -o x.exr");
  EXPECT_NE(flag.status, 0);
  std::size_t hints = 0;  // CLI11's message ends with this hint
  for (std::size_t at = flag.err.find("Run with --help"); at != std::string::npos; at = flag.err.find("Run with --help", at + 1)) ++hints;
  EXPECT_EQ(hints, 1u) << flag.err;
  const auto missing = runCommand(mpirun(2) + kRender + " " + quote(m.dir.path("none.vdb")) + " -o " + quote(m.dir.path("o.exr")));
  EXPECT_NE(missing.status, 0);
  EXPECT_EQ(errorLines(missing.err, "vdb_render"), 1) << missing.err;
  EXPECT_FALSE(std::filesystem::exists(m.dir.path("o.exr")));
  const auto stdin_medium = runCommand(kMakeMedium + " cube --res 8 -o - | " + mpirun(2) + kRender + " - -o " + quote(m.dir.path("s.exr")));
  EXPECT_NE(stdin_medium.status, 0);
  EXPECT_NE(stdin_medium.err.find("every rank can read"), std::string::npos) << stdin_medium.err;
  EXPECT_FALSE(std::filesystem::exists(m.dir.path("s.exr")));
  const auto optimize = runCommand(mpirun(2) + kOptimize + " --iterations 1 " + quote(m.dir.path("none.vdb")) + " " +
                                   quote(m.lobes) + " " + quote(m.dir.path("w.vdb")));
  EXPECT_NE(optimize.status, 0);
  EXPECT_EQ(errorLines(optimize.err, "vdb_optimize_weights"), 1) << optimize.err;
  EXPECT_FALSE(std::filesystem::exists(m.dir.path("w.vdb")));
  // A damaged entry of the reference cache, which every rank reads: one line naming it.
  const std::string cache = m.dir.path("cache"), quick = " --resolution 16 --spp 4 --reference-spp 8 --iterations 1 ";
  ASSERT_EQ(runCommand(kOptimize + quick + "--cache " + quote(cache) + " " + quote(m.full) + " " + quote(m.lobes) + " " +
                       quote(m.dir.path("first.vdb")))
                .status,
            0);
  std::string damaged;
  for (const auto& entry : std::filesystem::directory_iterator(cache)) damaged = entry.path().string();
  ASSERT_FALSE(damaged.empty());
  { std::ofstream(damaged, std::ios::trunc) << "vdbappear-reference 1 broken"; }
  const auto cached = runCommand(mpirun(2) + kOptimize + quick + "--cache " + quote(cache) + " " + quote(m.full) + " " +
                                 quote(m.lobes) + " " + quote(m.dir.path("w.vdb")));
  EXPECT_NE(cached.status, 0);
  EXPECT_EQ(errorLines(cached.err, "vdb_optimize_weights"), 1) << cached.err;
  EXPECT_NE(cached.err.find(std::filesystem::path(damaged).filename().string()), std::string::npos) << cached.err;
  EXPECT_FALSE(std::filesystem::exists(m.dir.path("w.vdb")));
}

}  // namespace
}  // namespace vdbappear
