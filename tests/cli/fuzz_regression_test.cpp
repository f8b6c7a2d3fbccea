// Replays tests/fuzz/regressions/: every input that once broke a tool goes through every tool that
// reads its kind, and each must end within 30 s with exit 0 (and its output) or exit 1 with an
// error line naming the input (and no output): never a signal, a hang or a partial file.
#include "cli/run_command.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace vdbappear {
namespace {

using test::quote;
using test::runCommand;
using test::TempDir;

namespace fs = std::filesystem;

struct Reader {
  std::string name, command;  // command with IN and OUT placeholders
  bool from_stdin = false;     // reads IN as `-` from stdin: its errors name "stdin"
};

// The tools that read each kind of input, as scripts/mutation_fuzz.py runs them.
std::vector<Reader> readersOf(const std::string& kind) {
  if (kind == "medium")
    return {{"render", quote(VDB_RENDER) + " IN -o OUT.png --res 12 --spp 2 -j 1 --env 0.5 --sun 1,1,-1,2"},
            {"preview", quote(VDB_PREVIEW) + " IN -o OUT.png --width 32 -j 1"},
            {"downsample", quote(VDB_SGGX_DOWNSAMPLE) + " IN OUT.vdb --factor 2 -j 1"},
            {"lobes", quote(VDB_LOBE_CLUSTER) + " IN OUT.vdb --factor 2 --lobes 2 --clusters 2 -j 1"},
            {"similarity", quote(VDB_SIMILARITY) + " IN OUT.vdb -j 1"},
            {"preview from stdin", quote(VDB_PREVIEW) + " - -o OUT.png --width 32 -j 1 < IN", true}};
  if (kind == "scene") return {{"render", quote(VDB_RENDER) + " --scene IN -o OUT.png -j 1"}};
  if (kind == "lights")
    return {{"sh_lightgrid", quote(VDB_SH_LIGHTGRID) + " --lights IN --bbox -1,-1,-1,1,1,1 --res 3 --lmax 2 -o OUT.vdb -j 1"}};
  if (kind == "lightgrid")
    return {{"render", quote(VDB_RENDER) + " medium.vdb -o OUT.png --res 12 --spp 2 -j 1 --env 0.5 --sh-lightgrid IN"}};
  if (kind == "envmap")
    return {{"render", quote(VDB_RENDER) + " medium.vdb -o OUT.png --res 12 --spp 2 -j 1 --env-map IN"},
            {"image_compare", quote(VDB_IMAGE_COMPARE) + " IN IN --error-map OUT.png"}};
  return {};
}

// Scenes, SH light grids and environment maps come with a medium (cube8.vdb of grids/golden,
// copied beside them).
bool needsMedium(const std::string& kind) { return kind == "scene" || kind == "lightgrid" || kind == "envmap"; }

std::string replace(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) s.replace(at, from.size(), to);
  return s;
}

std::vector<fs::path> regressionInputs() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(FUZZ_REGRESSION_DIR))
    if (entry.path().extension() != ".md") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(FuzzRegressions, EveryToolEndsCleanlyOnEveryKeptInput) {
  const std::vector<fs::path> inputs = regressionInputs();
  ASSERT_FALSE(inputs.empty());
  for (const fs::path& input : inputs) {
    const std::string file = input.filename().string(), kind = file.substr(0, file.find('-'));
    const std::vector<Reader> readers = readersOf(kind);
    ASSERT_FALSE(readers.empty()) << file << ": name it medium-, scene-, lights-, lightgrid- or envmap-";
    for (const Reader& reader : readers) {
      TempDir dir;
      const std::string in = dir.path(file), out = dir.path("out");
      fs::copy_file(input, in);
      if (needsMedium(kind)) fs::copy_file(fs::path(GOLDEN_DIR) / "cube8.vdb", dir.path("medium.vdb"));
      const std::string command = replace(replace(reader.command, "IN", quote(in)), "OUT", quote(out));
      const auto r = runCommand("cd " + quote(dir.root().string()) + " && timeout 30 " + command);
      const std::string what = file + " through " + reader.name + ": " + r.err;
      ASSERT_TRUE(r.status == 0 || r.status == 1) << what << " (exit " << r.status << ")";
      std::vector<std::string> left = test::listFiles(dir.root());
      const bool wrote = std::any_of(left.begin(), left.end(), [](const std::string& f) { return f.rfind("out.", 0) == 0; });
      if (r.status == 1) {
        EXPECT_NE(r.err.find(reader.from_stdin ? "stdin" : in), std::string::npos) << what << ": the error names the input";
        EXPECT_FALSE(wrote) << what << ": no output after an error";
      } else {
        EXPECT_TRUE(wrote) << what;
      }
      EXPECT_EQ(left.size(), std::size_t(wrote) + 1 + needsMedium(kind)) << what << ": nothing else left behind";
    }
  }
}

}  // namespace
}  // namespace vdbappear
