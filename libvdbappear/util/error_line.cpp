#include "libvdbappear/util/error_line.h"

#include <fmt/format.h>

#include <algorithm>

namespace vdbappear {

std::string errorLine(std::string_view what, std::size_t max_chars) {
  std::string line;
  line.reserve(std::min(what.size(), 2 * max_chars));
  std::size_t cut = 0;  // characters dropped from the middle
  const std::size_t head = max_chars * 3 / 4, tail = max_chars / 4;
  for (std::size_t i = 0; i < what.size(); ++i) {
    if (line.size() == head && what.size() - i > tail + 1) {  // skip to the last `tail` characters
      const std::size_t resume = what.size() - tail;
      cut = resume - i;
      i = resume;
    }
    const unsigned char c = static_cast<unsigned char>(what[i]);
    const char shown = c < 0x20 || c == 0x7f ? ' ' : char(c);
    if (shown == ' ' && !line.empty() && line.back() == ' ') continue;
    line += shown;
  }
  if (cut == 0) return line;
  return line.substr(0, head) + fmt::format(" [... {} characters cut ...] ", cut) + line.substr(head);
}

}  // namespace vdbappear
