// image/exr_header_check.h: every attribute of an OpenEXR header must fit in the file before
// OpenEXR reads it, since OpenEXR allocates what the file states.
#include "libvdbappear/image/exr_header_check.h"
#include "libvdbappear/util/error.h"

#include "support/little_endian.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>

namespace vdbappear {
namespace {

using test::TempDir;

using test::littleEndian32;

// An attribute as the file holds it; `stated` overrides the size it states.
std::string attribute(const std::string& name, const std::string& type, const std::string& value, std::int64_t stated = -1) {
  return name + '\0' + type + '\0' + littleEndian32(std::uint32_t(stated < 0 ? value.size() : stated)) + value;
}

// Magic number, version 2 with `flags`, the headers, then a stand-in for the offsets and pixels.
std::string exrBytes(std::uint32_t flags, const std::string& headers) {
  return littleEndian32(20000630) + littleEndian32(2 | flags) + headers + std::string(64, '\x7f');
}

std::string checkError(const TempDir& dir, const std::string& bytes) {
  const std::string path = dir.path("image.exr");
  std::ofstream(path, std::ios::binary) << bytes;
  try {
    checkExrHeaders(path);
  } catch (const MediumError& e) {
    return e.what();
  }
  return "accepted";
}

const std::string kOwner = attribute("owner", "string", "a render");
const std::string kAspect = attribute("pixelAspectRatio", "float", std::string(4, '\0'));

TEST(ExrHeaderCheck, SoundHeadersAndOtherFormatsPass) {
  TempDir dir;
  EXPECT_EQ(checkError(dir, exrBytes(0, kOwner + kAspect + '\0')), "accepted");
  EXPECT_EQ(checkError(dir, exrBytes(0x1000, kOwner + '\0' + kAspect + '\0' + '\0')), "accepted");  // two parts
  EXPECT_EQ(checkError(dir, "\x89PNG\r\n\x1a\n and the rest of a PNG"), "accepted");
}

TEST(ExrHeaderCheck, AnAttributeStatingMoreThanTheFileHoldsIsRefused) {
  TempDir dir;
  const std::string error = checkError(dir, exrBytes(0, kOwner + attribute("capDate", "string", "x", 1836016384) + '\0'));
  EXPECT_NE(error.find(dir.path("image.exr") + ": not a readable OpenEXR file: attribute 'capDate' states 1836016384 bytes"),
            std::string::npos) << error;
  EXPECT_NE(checkError(dir, exrBytes(0, attribute("owner", "string", "x", 0x80000000u) + '\0')).find("states -2147483648"),
            std::string::npos);
}

TEST(ExrHeaderCheck, TheSecondPartOfAMultiPartFileIsChecked) {
  TempDir dir;
  const std::string bad = attribute("comments", "string", "x", 1 << 30);
  EXPECT_NE(checkError(dir, exrBytes(0x1000, kOwner + '\0' + bad + '\0' + '\0')).find("attribute 'comments'"), std::string::npos);
}

// OpenEXR 3.1 reads names of up to 255 characters whatever the long-names flag says.
TEST(ExrHeaderCheck, NamesEndWithin255CharactersAndAHeaderMustEnd) {
  TempDir dir;
  EXPECT_EQ(checkError(dir, exrBytes(0, attribute(std::string(40, 'n'), "string", "x") + '\0')), "accepted");
  EXPECT_NE(checkError(dir, exrBytes(0, attribute(std::string(300, 'n'), "string", "x") + '\0')).find("longer than 255"),
            std::string::npos);
  const std::string truncated = littleEndian32(20000630) + littleEndian32(2) + kOwner + "pixelAsp";
  EXPECT_NE(checkError(dir, truncated).find("the file ends inside"), std::string::npos);
}

// A fixed-size value is read at its type's size whatever the file states: a float stating 1000
// bytes would leave OpenEXR reading the next attribute from inside this one.
TEST(ExrHeaderCheck, AFixedSizeValueStatingAnotherSizeIsRefused) {
  TempDir dir;
  const std::string error = checkError(dir, exrBytes(0, attribute("pixelAspectRatio", "float", std::string(1000, '\0')) + '\0'));
  EXPECT_NE(error.find("attribute 'pixelAspectRatio' states 1000 bytes, a float takes 4"), std::string::npos) << error;
}

// A channel list is read entry by entry up to an empty name, whatever size it states (found by the
// fuzz harness: a list stating 55 bytes ran on over the next attribute, whose value then stated
// 1.7 GB to OpenEXR while a walk by stated sizes saw a sound header).
TEST(ExrHeaderCheck, AChannelListIsWalkedAsOpenExrReadsIt) {
  TempDir dir;
  const std::string channel = std::string("R") + '\0' + std::string(16, '\x01');
  const std::string sound = attribute("channels", "chlist", channel + '\0');
  EXPECT_EQ(checkError(dir, exrBytes(0, kOwner + sound + kAspect + '\0')), "accepted");
  // States one entry's 18 bytes, holds two entries and the list's end, then a string of 1 GiB.
  const std::string run_on = attribute("channels", "chlist", channel, 18) + "G" + '\0' + std::string(16, '\x01') + '\0' +
                             attribute("comments", "string", "x", 1 << 30);
  const std::string error = checkError(dir, exrBytes(0, run_on + '\0'));
  EXPECT_NE(error.find("attribute 'comments' states 1073741824 bytes"), std::string::npos) << error;
}

}  // namespace
}  // namespace vdbappear
