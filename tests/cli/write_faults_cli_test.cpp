// Faults on write (docs/reliability.md §4): a disk that fills up in the middle of a write, a stdout
// that cannot take the stream, two processes writing the same output at once, and SIGINT or SIGTERM
// in the middle of a long render. Each ends with
// the previous file intact or the new one whole, never a partial file, and no temporary left.
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"

#include "cli/run_command.h"
#include "cli/tool_paths.h"
#include "support/medium_testing.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

namespace vdbappear {
namespace {

using test::kMakeMedium;
using test::kRender;
using test::lineCount;
using test::quote;
using test::readFileBytes;
using test::runCommand;
using test::TempDir;

// A full disk, as the tool sees it: the shell's file-size limit (8 KiB) makes every write past it
// fail with EFBIG, with SIGXFSZ ignored (a disk that fills up fails with ENOSPC the same way).
std::string onAFullDisk(const std::string& command) { return "ulimit -f 8; trap '' XFSZ; " + command; }

// Runs `command` with OUT replaced by the path of a file `name` that holds a previous result, on a
// full disk: one error line naming the file, which stays as it was, and nothing else left.
void expectFullDiskKeepsThePreviousFile(const std::string& command, const std::string& name) {
  TempDir dir;
  const std::string out = dir.path(name);
  std::ofstream(out) << "previous result";
  const auto r = runCommand(onAFullDisk(command + " -o " + quote(out)));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find(out), std::string::npos) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_EQ(readFileBytes(out), "previous result");
  EXPECT_EQ(test::listFiles(dir.root()), std::vector<std::string>{name});
}

TEST(WriteFaults, FullDiskLeavesThePreviousMediumAndNoTemporary) {
  expectFullDiskKeepsThePreviousFile(kMakeMedium + " random --res 40", "out.vdb");
}

// The image must outgrow 8 KiB even compressed: a noisy one, the ground lit by the sky through light
// sampling (--strategy mis). Under the default the ground is lit by cosine sampling alone, exact
// there, and the image of two values compresses to less.
TEST(WriteFaults, FullDiskLeavesThePreviousImageAndNoTemporary) {
  expectFullDiskKeepsThePreviousFile(
      kRender + " --env 1 --ground --camera-pos 0,-3,2 --camera-target 0,0,0 --res 64 --spp 1 --strategy mis",
      "out.exr");
}

TEST(WriteFaults, StdoutThatCannotTakeTheStreamIsAnError) {
  const auto r = runCommand(kMakeMedium + " random --res 40 -o - > /dev/full");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("stdout"), std::string::npos) << r.err;
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
}

// Two writers of one output: each renames its own whole temporary, so the file is one of the two.
TEST(WriteFaults, TwoWritersOfOneOutputLeaveOneWholeFile) {
  TempDir dir;
  const std::string out = dir.path("out.vdb");
  const std::string make = kMakeMedium + " random --res 48 -o " + quote(out) + " --seed ";
  const auto r = runCommand(make + "1 & " + make + "2 & wait");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(test::listFiles(dir.root()), std::vector<std::string>{"out.vdb"});
  const MediumPtr written = readMedium(out);
  const MediumPtr one = test::randomMedium(48, 1), two = test::randomMedium(48, 2);
  EXPECT_TRUE(test::gridsMatch(*one->density, *written->density, 0) ||
              test::gridsMatch(*two->density, *written->density, 0));
}

// SIGINT or SIGTERM two seconds into a render of some minutes (GNU timeout sends it; a shell's
// background job would ignore SIGINT): the process ends by the signal, as a shell reports it
// (128 + the signal's number), the previous image stays and nothing else is left behind.
void expectInterruptedRenderKeepsThePreviousImage(const std::string& signal, int shell_status) {
  TempDir dir;
  const std::string out = dir.path("out.exr");
  std::ofstream(out) << "previous result";
  const auto r = runCommand("timeout --preserve-status -s " + signal + " 2 " + kRender +
                            " --env 1 --ground --camera-pos 0,-3,2 --camera-target 0,0,0 --res 256 --spp 100000 -o " +
                            quote(out));
  EXPECT_EQ(r.status, shell_status) << r.err;
  EXPECT_EQ(readFileBytes(out), "previous result");
  EXPECT_EQ(test::listFiles(dir.root()), std::vector<std::string>{"out.exr"});
}

TEST(WriteFaults, SigintInTheMiddleOfARenderLeavesThePreviousImageAndNoTemporary) {
  expectInterruptedRenderKeepsThePreviousImage("INT", 128 + 2);
}

TEST(WriteFaults, SigtermInTheMiddleOfARenderLeavesThePreviousImageAndNoTemporary) {
  expectInterruptedRenderKeepsThePreviousImage("TERM", 128 + 15);
}

}  // namespace
}  // namespace vdbappear
