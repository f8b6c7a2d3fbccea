// Golden media (grids/golden/): each file made by vdb_make_medium carries its command line in its
// `history` metadata; running that command with this build must give the same grids.
// Tolerance: 1e-6 absolute on albedo, S and ids, 5e-5 on density (values up to 60, float rounding).
#include "libvdbappear/io/medium.h"

#include "cli/run_command.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

namespace vdbappear {
namespace {

using test::quote;
using test::runCommand;

// "vdb_make_medium 0.1.0: vdb_make_medium cube --res 8 -o cube8.vdb" -> the command with this
// build's binary and `output` in place of the recorded output.
std::string replayCommand(const std::string& history, const std::string& output) {
  std::istringstream words(history.substr(history.find(": ") + 2));
  std::string word, command;
  bool first = true, next_is_output = false;
  while (words >> word) {
    if (first) word = quote(VDB_MAKE_MEDIUM);
    else if (next_is_output) word = quote(output);
    next_is_output = word == "-o" || word == "--output";
    command += (first ? "" : " ") + word;
    first = false;
  }
  return command;
}

template <typename GridT>
::testing::AssertionResult sameGrid(const openvdb::GridBase& expected, const openvdb::GridBase& actual, double tol) {
  const auto* a = dynamic_cast<const GridT*>(&expected);
  const auto* b = dynamic_cast<const GridT*>(&actual);
  if (!a || !b) return ::testing::AssertionFailure() << "grid '" << expected.getName() << "': types differ";
  return test::gridsMatch(*a, *b, tol);
}

TEST(GoldenMedia, EveryGeneratedGoldenGridIsReproducedByItsHistoryCommand) {
  test::TempDir dir;
  int replayed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(GOLDEN_DIR)) {
    if (entry.path().extension() != ".vdb") continue;
    const MediumPtr golden = readMedium(entry.path().string());
    std::string history = golden->metadata.metaValue<std::string>(metadata_names::kHistory);
    history = history.substr(history.find_last_of('\n') + 1);  // the last tool that wrote it
    if (history.rfind("vdb_make_medium", 0) != 0) continue;    // made by another tool
    SCOPED_TRACE(entry.path().filename().string() + ": " + history);
    const std::string out = dir.path("replay.vdb");
    const auto r = runCommand(replayCommand(history, out));
    ASSERT_EQ(r.status, 0) << r.err;
    const MediumPtr replay = readMedium(out);
    EXPECT_EQ(replay->transform(), golden->transform());
    EXPECT_EQ(hgGMetadata(replay->metadata), hgGMetadata(golden->metadata));
    const openvdb::GridCPtrVec expected = golden->grids(), actual = replay->grids();
    ASSERT_EQ(actual.size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      ASSERT_EQ(actual[k]->getName(), expected[k]->getName());
      if (expected[k]->isType<openvdb::FloatGrid>())
        EXPECT_TRUE(sameGrid<openvdb::FloatGrid>(*expected[k], *actual[k], 5e-5));
      else if (expected[k]->isType<openvdb::Vec3SGrid>())
        EXPECT_TRUE(sameGrid<openvdb::Vec3SGrid>(*expected[k], *actual[k], 1e-6));
      else
        EXPECT_TRUE(sameGrid<openvdb::Int32Grid>(*expected[k], *actual[k], 0));
    }
    ++replayed;
  }
  EXPECT_GE(replayed, 8) << "one golden medium per kind";
}

}  // namespace
}  // namespace vdbappear
