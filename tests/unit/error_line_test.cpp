// errorLine: what a tool prints of an error is one line of readable length.
#include "libvdbappear/util/error_line.h"

#include <gtest/gtest.h>

#include <string>

namespace vdbappear {
namespace {

TEST(ErrorLine, ShortMessagesPassUnchanged) {
  EXPECT_EQ(errorLine("in.vdb: grid 'density': negative density -1 at voxel (3,0,7)"),
            "in.vdb: grid 'density': negative density -1 at voxel (3,0,7)");
}

TEST(ErrorLine, ControlCharactersAndLineBreaksBecomeOneSpace) {
  EXPECT_EQ(errorLine(std::string("a\nb\r\n\tc\x01") + "d  e"), "a b c d e");
}

// OpenVDB's reader quotes a blank-filled grid type of the length a corrupt file states
// (tests/fuzz/findings): a gigabyte of spaces is one space.
TEST(ErrorLine, LongMessagesKeepTheirStartAndEnd) {
  const std::string blanks = "f.vdb: Grid type " + std::string(10000000, ' ') + "is not registered.";
  EXPECT_EQ(errorLine(blanks), "f.vdb: Grid type is not registered.");

  std::string long_message = "start:";
  for (int i = 0; i < 1000; ++i) long_message += "0123456789";
  long_message += ":end";
  const std::string line = errorLine(long_message, 100);
  EXPECT_EQ(line.rfind("start:", 0), 0u) << line;
  EXPECT_EQ(line.substr(line.size() - 4), ":end") << line;
  EXPECT_NE(line.find("[... 9910 characters cut ...]"), std::string::npos) << line;
  EXPECT_LT(line.size(), 140u) << line;
}

}  // namespace
}  // namespace vdbappear
