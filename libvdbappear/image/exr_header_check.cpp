#include "libvdbappear/image/exr_header_check.h"

#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>

namespace vdbappear {

namespace {

// The OpenEXR file layout (openexr.com, "OpenEXR File Layout"): a magic number, a version field
// whose flags say whether several parts (headers) follow, then each header as attributes (name,
// type name, int32 size, value) ended by an empty name; a multi-part file ends its list of headers
// with one more empty name. The walk follows OpenEXR 3.1's own reader (Header::readFrom and each
// attribute's readValueFrom), which reads names of up to 255 characters whatever the flags say,
// and reads what a value's type holds rather than what the size states.
constexpr std::uint32_t kExrMagic = 20000630;
constexpr std::uint32_t kMultiPartFlag = 0x1000;
constexpr std::size_t kMaxNameLength = 255;  // Imf::Name::MAX_LENGTH

// The bytes OpenEXR 3.1 reads for a value of a fixed-size type, whatever its stated size.
std::size_t fixedValueBytes(const std::string& type) {
  static const std::map<std::string, std::size_t> kBytes = {
      {"box2i", 16}, {"box2f", 16}, {"chromaticities", 32}, {"compression", 1}, {"deepImageState", 1},
      {"double", 8}, {"envmap", 1}, {"float", 4}, {"int", 4}, {"keycode", 28}, {"lineOrder", 1},
      {"m33f", 36}, {"m33d", 72}, {"m44f", 64}, {"m44d", 128}, {"rational", 8}, {"tiledesc", 9},
      {"timecode", 8}, {"v2i", 8}, {"v2f", 8}, {"v2d", 16}, {"v3i", 12}, {"v3f", 12}, {"v3d", 24}};
  const auto it = kBytes.find(type);
  return it == kBytes.end() ? 0 : it->second;
}

class HeaderReader {
 public:
  // Reads the magic number and version; isExr() says whether the file is OpenEXR at all.
  explicit HeaderReader(const std::string& path)
      : path_(path), in_(path, std::ios::binary), size_(std::filesystem::file_size(path)) {
    std::uint32_t magic = 0;
    in_.read(reinterpret_cast<char*>(&magic), sizeof magic);
    in_.read(reinterpret_cast<char*>(&version_), sizeof version_);
    is_exr_ = in_ && magic == kExrMagic;  // else not OpenEXR, or too short for OpenImageIO to take it as such
    position_ = 8;
  }

  bool isExr() const { return is_exr_; }
  bool multiPart() const { return version_ & kMultiPartFlag; }

  // A name or type name: at most 255 characters, then a zero byte.
  std::string name(const char* what) {
    std::string text;
    for (char c; in_.get(c); text.push_back(c)) {
      ++position_;
      if (c == '\0') return text;
      if (text.size() == kMaxNameLength) fail(fmt::format("{} longer than {} characters", what, kMaxNameLength));
    }
    fail(fmt::format("the file ends inside {}", what));
  }

  std::int32_t int32(const std::string& what) {
    std::int32_t value = 0;
    if (!in_.read(reinterpret_cast<char*>(&value), sizeof value)) fail(fmt::format("the file ends inside {}", what));
    position_ += sizeof value;
    return value;
  }

  void skip(std::uint64_t bytes, const std::string& what) {
    const std::uint64_t left = size_ - position_;
    if (bytes > left) fail(fmt::format("{} states {} bytes, the file holds {} more", what, bytes, left));
    in_.seekg(std::streamoff(bytes), std::ios::cur);
    position_ += bytes;
  }

  bool nextIsEmptyName() {
    const int c = in_.peek();
    if (c == std::char_traits<char>::eof()) fail("the file ends inside a header");
    return c == '\0';
  }

  [[noreturn]] void fail(const std::string& why) const {
    throw MediumError(fmt::format("{}: not a readable OpenEXR file: {}", path_, why));
  }

 private:
  std::string path_;
  std::ifstream in_;
  std::uint64_t size_, position_ = 0;
  std::uint32_t version_ = 0;
  bool is_exr_ = false;
};

// A channel list as ChannelListAttribute::readValueFrom reads it: entries (a name, then type,
// pLinear, three reserved bytes and two samplings: 16 bytes) until an empty name, whatever size
// the attribute states.
void walkChannelList(HeaderReader& reader, const std::string& attribute) {
  while (!reader.name("a channel name").empty()) reader.skip(16, "channel of attribute '" + attribute + "'");
}

// One attribute's value, as OpenEXR 3.1 reads it: a string, vector, preview or unknown type reads
// (and allocates) the stated size; a fixed-size type reads its own size, which must then be the
// stated one, or OpenEXR would read the rest of the header from another place than this walk.
void walkValue(HeaderReader& reader, const std::string& attribute, const std::string& type) {
  const std::string what = "attribute '" + attribute + "'";
  const std::int32_t size = reader.int32("the size of " + what);
  if (size < 0) reader.fail(fmt::format("{} states {} bytes", what, size));
  if (type == "chlist") return walkChannelList(reader, attribute);
  if (const std::size_t bytes = fixedValueBytes(type)) {
    if (std::size_t(size) != bytes) reader.fail(fmt::format("{} states {} bytes, a {} takes {}", what, size, type, bytes));
    return reader.skip(bytes, what);
  }
  // IDManifestAttribute reads an 8-byte uncompressed size, then size - 4 compressed bytes.
  reader.skip(std::uint64_t(size) + (type == "idmanifest" ? 4 : 0), what);
}

// One header: attributes until an empty name.
void walkHeader(HeaderReader& reader) {
  for (std::string attribute = reader.name("an attribute name"); !attribute.empty();
       attribute = reader.name("an attribute name"))
    walkValue(reader, attribute, reader.name("an attribute's type name"));
}

}  // namespace

void checkExrHeaders(const std::string& path) {
  HeaderReader reader(path);
  if (!reader.isExr()) return;
  walkHeader(reader);
  if (!reader.multiPart()) return;
  while (!reader.nextIsEmptyName()) walkHeader(reader);
}

}  // namespace vdbappear
