#include "libvdbappear/image/exr_header_check.h"

#include "libvdbappear/util/error.h"

#include <fmt/format.h>

#include <cstdint>
#include <filesystem>
#include <fstream>

namespace vdbappear {

namespace {

// The OpenEXR file layout (openexr.com, "OpenEXR File Layout"): a magic number, a version field
// whose flags say whether names may be long and whether several parts (headers) follow, then each
// header as attributes (name, type name, int32 size, value) ended by an empty name; a multi-part
// file ends its list of headers with one more empty name.
constexpr std::uint32_t kExrMagic = 20000630;
constexpr std::uint32_t kLongNamesFlag = 0x400, kMultiPartFlag = 0x1000;

class HeaderReader {
 public:
  HeaderReader(const std::string& path, std::uint32_t version)
      : path_(path), in_(path, std::ios::binary), size_(std::filesystem::file_size(path)),
        max_name_(version & kLongNamesFlag ? 255 : 31) {
    in_.seekg(8);
    position_ = 8;
  }

  // A name or type name: at most max_name_ characters, then a zero byte.
  std::string name(const char* what) {
    std::string text;
    for (char c; in_.get(c); text.push_back(c)) {
      ++position_;
      if (c == '\0') return text;
      if (text.size() == max_name_) fail(fmt::format("{} longer than {} characters", what, max_name_));
    }
    fail(fmt::format("the file ends inside {}", what));
  }

  void attributeValue(const std::string& attribute) {
    std::int32_t size = 0;
    if (!in_.read(reinterpret_cast<char*>(&size), sizeof size)) fail(fmt::format("the file ends inside attribute '{}'", attribute));
    position_ += sizeof size;
    const std::uint64_t left = size_ - position_;
    if (size < 0 || std::uint64_t(size) > left)
      fail(fmt::format("attribute '{}' states {} bytes, the file holds {} more", attribute, size, left));
    in_.seekg(size, std::ios::cur);
    position_ += std::uint64_t(size);
  }

  bool nextIsEmptyName() {
    const int c = in_.peek();
    if (c == std::char_traits<char>::eof()) fail("the file ends inside a header");
    return c == '\0';
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw MediumError(fmt::format("{}: not a readable OpenEXR file: {}", path_, why));
  }

  std::string path_;
  std::ifstream in_;
  std::uint64_t size_, position_ = 0;
  std::size_t max_name_;
};

// One header: attributes until an empty name.
void checkHeader(HeaderReader& reader) {
  for (std::string attribute = reader.name("an attribute name"); !attribute.empty();
       attribute = reader.name("an attribute name")) {
    reader.name("an attribute's type name");
    reader.attributeValue(attribute);
  }
}

}  // namespace

void checkExrHeaders(const std::string& path) {
  std::uint32_t magic = 0, version = 0;
  {
    std::ifstream in(path, std::ios::binary);
    in.read(reinterpret_cast<char*>(&magic), sizeof magic);
    in.read(reinterpret_cast<char*>(&version), sizeof version);
    if (!in || magic != kExrMagic) return;  // not OpenEXR, or too short for OpenImageIO to take it as such
  }
  HeaderReader reader(path, version);
  checkHeader(reader);
  if (!(version & kMultiPartFlag)) return;
  while (!reader.nextIsEmptyName()) checkHeader(reader);
}

}  // namespace vdbappear
