// io/vdb_record_guard.cpp: OpenVDB 10's readers of a VDB file's headers (grid descriptors,
// metadata, transforms) refuse a stated size beyond the bytes a file or stream holds before they
// allocate it, and read sound files exactly as before. Each damaged file below differs from a sound
// one in the four bytes of one stated size.
#include "libvdbappear/io/medium.h"
#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/procedural/random_medium.h"
#include "libvdbappear/util/error.h"

#include "support/medium_testing.h"
#include "support/little_endian.h"
#include "support/temp_dir.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/math/Transform.h>

#include <cstdint>
#include <fstream>
#include <sstream>

namespace vdbappear {
namespace {

using test::TempDir;

constexpr std::uint32_t kHuge = 0xFFFFFF00u;  // 4 GiB less 256 bytes: what OpenVDB 10 would allocate

using test::littleEndian32;

// A small medium with a string metadata item, as the bytes of its file.
std::string soundMediumBytes(const TempDir& dir) {
  RandomMediumParams params;
  params.extent = 8;
  const MediumPtr medium = makeRandomMedium(params);
  medium->metadata.insertMeta("note", openvdb::StringMetadata("woven by hand"));
  writeMedium(*medium, dir.path("sound.vdb"), "vdb_record_guard_test");
  return test::readFileBytes(dir.path("sound.vdb"));
}

// `bytes` with the size stated just before the first `record` (a string or metadata value of the
// size it states, followed by `followed_by`) replaced by `size`.
std::string withStatedSize(std::string bytes, const std::string& record, std::uint32_t size,
                           const std::string& followed_by = "") {
  const std::size_t at = bytes.find(littleEndian32(std::uint32_t(record.size())) + record + followed_by);
  EXPECT_NE(at, std::string::npos) << "no record '" << record << "' in the file";
  if (at != std::string::npos) bytes.replace(at, 4, littleEndian32(size));
  return bytes;
}

std::string writeBytes(const TempDir& dir, const std::string& name, const std::string& bytes) {
  std::ofstream(dir.path(name), std::ios::binary) << bytes;
  return dir.path(name);
}

// A stream that cannot seek, like a pipe on stdin.
struct PipeBuffer : std::stringbuf {
  explicit PipeBuffer(const std::string& bytes) : std::stringbuf(bytes) {}
  pos_type seekoff(off_type, std::ios_base::seekdir, std::ios_base::openmode) override { return pos_type(off_type(-1)); }
  pos_type seekpos(pos_type, std::ios_base::openmode) override { return pos_type(off_type(-1)); }
};

std::string streamError(const std::string& bytes, bool seekable) {
  PipeBuffer pipe(bytes);
  std::istringstream memory(bytes);
  std::istream piped(&pipe);
  try {
    readMediumStream(seekable ? static_cast<std::istream&>(memory) : piped, "the stream");
  } catch (const MediumError& e) {
    return e.what();
  }
  return "read without error";
}

// The refusal names the source and the size stated, and comes from the check, not from OpenVDB
// after an allocation of that size (whose own messages say neither).
void expectRefused(const std::string& bytes, const std::string& what, const TempDir& dir) {
  const std::string stated = "states " + std::to_string(kHuge) + " bytes";
  const std::string path = writeBytes(dir, "damaged.vdb", bytes);
  const std::string from_file = test::readMediumError(path);
  EXPECT_NE(from_file.find(path), std::string::npos) << what << ": " << from_file;
  EXPECT_NE(from_file.find(stated), std::string::npos) << what << ": " << from_file;
  for (const bool seekable : {true, false}) {
    const std::string from_stream = streamError(bytes, seekable);
    EXPECT_NE(from_stream.find("the stream"), std::string::npos) << what << ": " << from_stream;
    EXPECT_NE(from_stream.find(stated), std::string::npos) << what << (seekable ? "" : " (pipe)") << ": " << from_stream;
  }
}

TEST(VdbRecordGuard, SoundMediaReadAsBefore) {
  TempDir dir;
  const std::string bytes = soundMediumBytes(dir);
  const MediumPtr from_file = readMedium(dir.path("sound.vdb"));
  EXPECT_EQ(from_file->metadata.metaValue<std::string>("note"), "woven by hand");
  for (const bool seekable : {true, false}) EXPECT_EQ(streamError(bytes, seekable), "read without error");
}

TEST(VdbRecordGuard, AGridTypeLongerThanTheFileIsRefused) {
  TempDir dir;
  expectRefused(withStatedSize(soundMediumBytes(dir), "Tree_float_5_4_3", kHuge), "grid type", dir);
}

TEST(VdbRecordGuard, AGridNameLongerThanTheFileIsRefused) {
  TempDir dir;
  // The density grid's name, as its descriptor states it ("density" without a "[0]" suffix).
  expectRefused(withStatedSize(soundMediumBytes(dir), "density", kHuge, littleEndian32(16) + "Tree_float_5_4_3"),
                "grid name", dir);
}

TEST(VdbRecordGuard, MetadataNamesTypesAndValuesLongerThanTheFileAreRefused) {
  TempDir dir;
  const std::string sound = soundMediumBytes(dir);
  expectRefused(withStatedSize(sound, "note", kHuge), "metadata name", dir);
  expectRefused(withStatedSize(sound, "string", kHuge), "metadata type", dir);
  expectRefused(withStatedSize(sound, "woven by hand", kHuge), "string metadata value", dir);
  expectRefused(withStatedSize(sound, "__delayedload", kHuge), "metadata type", dir);
}

TEST(VdbRecordGuard, AMapTypeLongerThanTheFileIsRefused) {
  TempDir dir;
  expectRefused(withStatedSize(soundMediumBytes(dir), "UniformScaleTranslateMap", kHuge), "map type", dir);
}

// A fixed-size value (a vec3s takes 12 bytes) that states another size would leave OpenVDB reading
// the rest of the file out of step with what was checked.
TEST(VdbRecordGuard, AFixedSizeMetadataValueOfAnotherSizeIsRefused) {
  TempDir dir;
  const std::string sound = soundMediumBytes(dir);
  const std::string record = "file_bbox_max" + littleEndian32(5) + "vec3i";
  std::string bytes = sound;
  const std::size_t at = bytes.find(record);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at + record.size(), 4, littleEndian32(1000));
  const std::string error = test::readMediumError(writeBytes(dir, "damaged.vdb", bytes));
  EXPECT_NE(error.find("states 1000 bytes, a vec3i takes 12"), std::string::npos) << error;
}

// DelayedLoadMetadata allocates a byte per leaf it counts, and 8 for its compressed size.
TEST(VdbRecordGuard, DelayedLoadMetadataCountingMoreLeavesThanTheFileHoldsIsRefused) {
  TempDir dir;
  std::string bytes = soundMediumBytes(dir);
  const std::string record = "file_delayed_load" + littleEndian32(13) + "__delayedload";
  const std::size_t at = bytes.find(record);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at + record.size() + 4, 4, littleEndian32(kHuge));  // after the value's size: the leaf count
  const std::string error = test::readMediumError(writeBytes(dir, "damaged.vdb", bytes));
  EXPECT_NE(error.find("counts " + std::to_string(kHuge) + " leaves"), std::string::npos) << error;
}

// io::Stream reserves a descriptor per grid it counts before it reads one: 2^31 asked for 283 GB.
TEST(VdbRecordGuard, AGridCountBeyondTheStreamIsRefusedBeforeAllocation) {
  TempDir dir;
  const std::string sound = soundMediumBytes(dir);
  // The file's last metadata item (names are sorted) is the schema version; the grid count follows.
  const std::string schema = littleEndian32(6) + "schema" + littleEndian32(5) + "int32" + littleEndian32(4);
  const std::size_t at = sound.find(schema);
  ASSERT_NE(at, std::string::npos);
  for (const std::int32_t count : {std::int32_t(0x7FFFFFFF), std::int32_t(-1)}) {
    std::string bytes = sound;
    bytes.replace(at + schema.size() + 4, 4, littleEndian32(std::uint32_t(count)));
    const std::string error = streamError(bytes, /*seekable=*/false);
    EXPECT_NE(error.find("the grid count " + std::to_string(count) + " does not fit"), std::string::npos) << error;
  }
}

// A root node that counts 4 billion tiles in a file of a few KB: OpenVDB went on reading a failed
// stream 4 billion times (52 s); from the metadata on, a short read now throws.
TEST(VdbRecordGuard, ARootCountingMoreTilesThanTheFileHoldsEndsAtTheFirstShortRead) {
  TempDir dir;
  std::string bytes = soundMediumBytes(dir);
  // The density grid's tree after its transform: one buffer, background 0, no tiles (then children).
  const std::string root = littleEndian32(1) + littleEndian32(0) + littleEndian32(0);
  const std::size_t at = bytes.find(root, bytes.find("UniformScaleTranslateMap"));
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at + 8, 4, littleEndian32(kHuge));
  const std::string path = writeBytes(dir, "damaged.vdb", bytes);
  const std::string error = test::readMediumError(path);
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("ends before the data it describes"), std::string::npos) << error;
  for (const bool seekable : {true, false}) {
    const std::string from_stream = streamError(bytes, seekable);
    EXPECT_NE(from_stream.find("ends before the data it describes"), std::string::npos) << from_stream;
  }
}

// A frustum transform names its second map after the box, taper and depth.
TEST(VdbRecordGuard, AFrustumsSecondMapTypeLongerThanTheFileIsRefusedAndASoundOneRead) {
  openvdb::initialize();
  TempDir dir;
  auto grid = openvdb::FloatGrid::create();
  grid->setName("frustum");
  grid->setTransform(openvdb::math::Transform::createFrustumTransform(openvdb::BBoxd({0, 0, 0}, {7, 7, 7}), 0.5, 2.0));
  openvdb::io::File(dir.path("frustum.vdb")).write({grid});
  const std::string sound = test::readFileBytes(dir.path("frustum.vdb"));
  {
    openvdb::io::File file(dir.path("frustum.vdb"));
    file.open(false);
    EXPECT_TRUE(file.readGrid("frustum")->transform() == grid->transform());
  }
  const std::string damaged = withStatedSize(sound, "AffineMap", kHuge);
  openvdb::io::File file(writeBytes(dir, "damaged.vdb", damaged));
  file.open(false);
  try {
    file.readGrid("frustum");
    ADD_FAILURE() << "read without error";
  } catch (const openvdb::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("second map type states " + std::to_string(kHuge) + " bytes"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace vdbappear
