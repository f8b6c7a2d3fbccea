// vdb_similarity from the command line: one material as JSON (checked against the library's own
// moment computation), tables read back, media in and out, pipes into vdb_render, bad input.
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/io/phase_tables.h"
#include "libvdbappear/similarity/legendre_moments.h"
#include "libvdbappear/similarity/similarity_relation.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace vdbappear {
namespace {

using nlohmann::json;
using test::exists;
using test::kMakeMedium;
using test::kRender;
using test::kSimilarity;
using test::quote;
using test::runCommand;
using test::TempDir;

std::string makeCloud(const TempDir& dir, const std::string& name = "cloud.vdb") {
  const std::string path = dir.path(name);
  const auto r = runCommand(kMakeMedium + " cloud --res 32 -o " + quote(path));
  EXPECT_EQ(r.status, 0) << r.err;
  return path;
}

TEST(SimilarityCli, HelpShowsUsageAndExamples) {
  const auto r = runCommand(kSimilarity + " --help");
  EXPECT_EQ(r.status, 0);
  for (const char* text : {"Usage:", "Examples:", "--hg", "--table", "--alpha", "--max-order", "--support-ratio", "--bins", "--json"})
    EXPECT_NE(r.out.find(text), std::string::npos) << text;
}

// The JSON contract: alpha, order, moments f_0* .. f_N*, support, bins, table; the table's
// moments (recomputed here) match, it is non-negative and normalised.
TEST(SimilarityCli, OneMaterialPrintsTheAlteredPhaseFunctionAsJson) {
  const auto r = runCommand(kSimilarity + " --hg 0.9 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_DOUBLE_EQ(j.at("alpha").get<double>(), 0.3);
  const int order = j.at("order").get<int>();
  EXPECT_EQ(order, 3);
  const auto moments = j.at("moments").get<std::vector<double>>();
  ASSERT_EQ(int(moments.size()), order + 1);
  const auto expected = alteredMoments(henyeyGreensteinMoments(0.9, order), 0.3);
  const auto table = j.at("table").get<std::vector<double>>();
  ASSERT_EQ(int(table.size()), j.at("bins").get<int>());
  EXPECT_EQ(table.size(), 360u);
  const auto got = tableMoments(table, order);
  double integral = 0;
  for (double f : table) {
    EXPECT_GE(f, 0);
    integral += 2 * M_PI * f * 2.0 / double(table.size());
  }
  EXPECT_NEAR(integral, 1.0, 1e-9);
  for (int n = 0; n <= order; ++n) {
    EXPECT_NEAR(moments[n], expected[n], 1e-12) << n;
    EXPECT_NEAR(got[n], expected[n], 1e-5) << n;
  }
  EXPECT_GE(j.at("support").get<double>(), 0.65);
  EXPECT_EQ(j.at("order_rule").get<std::string>(), "distance");  // the default
  EXPECT_EQ(j.at("rejected").size(), 3u);  // orders 5 and 4 (farther than 3) and 2 (no closer)
}

// --order-rule distance (docs/similarity.md §1): the distances of the orders it passed over are in
// the JSON, each no smaller than the chosen one's.
TEST(SimilarityCli, DistanceRuleReportsItsDistances) {
  const auto r = runCommand(kSimilarity + " --hg 0.9 --order-rule distance --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j.at("order_rule").get<std::string>(), "distance");
  EXPECT_EQ(j.at("order").get<int>(), 3);
  const double distance = j.at("distance").get<double>();
  EXPECT_GT(distance, 0);
  ASSERT_EQ(j.at("rejected").size(), 3u);  // 5 and 4 passed over on the way down, 2 stopped the search
  for (const json& rejected : j.at("rejected")) EXPECT_GE(rejected.at("distance").get<double>(), distance);
}

TEST(SimilarityCli, TableFilesInJsonOrTextGiveTheSameResult) {
  TempDir dir;
  const std::vector<double> hg = tabulateHenyeyGreenstein(0.8, 720);
  {
    std::ofstream(dir.path("hg.json")) << json{{"table", hg}}.dump();
    std::ofstream text(dir.path("hg.txt"));
    text << "# HG(0.8) on 720 bins\n";
    text.precision(17);
    for (double f : hg) text << f << "\n";
  }
  std::vector<json> results;
  for (const char* name : {"hg.json", "hg.txt"}) {
    const auto r = runCommand(kSimilarity + " --table " + quote(dir.path(name)) + " --alpha 0.4 --json");
    ASSERT_EQ(r.status, 0) << r.err;
    results.push_back(json::parse(r.out));
  }
  EXPECT_EQ(results[0].at("table"), results[1].at("table"));
  EXPECT_EQ(results[0].at("order"), results[1].at("order"));
  // The output of --json is itself a table file.
  {
    std::ofstream(dir.path("altered.json")) << results[0].dump();
  }
  EXPECT_EQ(runCommand(kSimilarity + " --table " + quote(dir.path("altered.json")) + " --alpha 1 --json").status, 0);
}

TEST(SimilarityCli, MediumIsAlteredAndRendersFromAPipe) {
  TempDir dir;
  const std::string cloud = makeCloud(dir), out = dir.path("altered.vdb"), report = dir.path("report.json");
  const auto r = runCommand(kSimilarity + " " + quote(cloud) + " " + quote(out) + " --report " + quote(report) + " -v");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("removed metadata 'hg_g'"), std::string::npos) << r.err;
  std::ifstream file(report);
  const json j = json::parse(file);
  ASSERT_EQ(j.at("tables").size(), 1u);
  EXPECT_DOUBLE_EQ(j.at("tables")[0].at("alpha").get<double>(), 0.3);
  const MediumPtr in = readMedium(cloud), altered = readMedium(out);
  EXPECT_EQ(readPhaseTables(*altered).size(), 1u);
  EXPECT_NEAR(altered->density->tree().getValue(in->density->cbeginValueOn().getCoord()),
              *in->density->cbeginValueOn() * (1 - 0.98 * 0.7), 1e-4 * *in->density->cbeginValueOn());

  const std::string image = dir.path("fast.exr"), render_report = dir.path("render.json");
  const auto piped = runCommand(kSimilarity + " " + quote(cloud) + " - | " + kRender + " - -o " + quote(image) +
                                " --res 16 --spp 2 --report " + quote(render_report));
  ASSERT_EQ(piped.status, 0) << piped.err;
  std::ifstream rendered(render_report);
  EXPECT_NE(json::parse(rendered).dump().find("tabulated"), std::string::npos);
}

TEST(SimilarityCli, BadInputFailsWithOneLineAndNoOutput) {
  TempDir dir;
  const std::string cloud = makeCloud(dir), out = dir.path("out.vdb");
  const std::string twill = dir.path("twill.vdb");
  ASSERT_EQ(runCommand(kMakeMedium + " twill --yarns 2 --res 32 -o " + quote(twill)).status, 0);
  {
    std::ofstream(dir.path("bad.txt")) << "0.1 0.2 abc\n";
    std::ofstream(dir.path("negative.txt")) << "0.1 -0.2 0.3\n";
  }
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {quote(dir.path("missing.vdb")) + " " + quote(out), "missing.vdb"},
      {quote(twill) + " " + quote(out), "grid 'sggx_diag'"},
      {quote(cloud) + " " + quote(out) + " --alpha 0.01", "alpha 0.01 outside"},
      {quote(cloud) + " " + quote(out) + " --json", "--json is for one material"},
      {quote(cloud), "give a medium IN and an output OUT"},
      {"--hg 0.9 --alpha 0.01", "alpha 0.01 outside"},
      {"--hg 1.5", "--hg"},
      {"--table " + quote(dir.path("bad.txt")), "bad.txt: line 1: 'abc' is not a number"},
      {"--table " + quote(dir.path("negative.txt")), "negative.txt: bin 1"},
      {"--table " + quote(dir.path("none.txt")), "none.txt: cannot open"},
      {"--hg 0.9 --table " + quote(dir.path("negative.txt")), "excludes"},
      {quote(cloud) + " " + quote(out) + " --bins 4", "--bins"},
      {quote(cloud) + " " + quote(out) + " --order-rule closest", "--order-rule"},
  };
  for (const Case& c : cases) {
    const auto r = runCommand(kSimilarity + " " + c.args);
    EXPECT_NE(r.status, 0) << c.args;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(exists(out)) << c.args;
  }
}

}  // namespace
}  // namespace vdbappear
