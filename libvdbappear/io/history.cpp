#include "libvdbappear/io/history.h"

#include "libvdbappear/version.h"

#include <fmt/format.h>

namespace vdbappear {

std::string shellQuote(const std::string& arg) {
  if (!arg.empty() && arg.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                            "@%+=:,./-_") == std::string::npos)
    return arg;
  std::string quoted = "'";
  for (char c : arg) quoted += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string historyLine(const std::string& tool, int argc, const char* const* argv) {
  std::string line = fmt::format("{} {}:", tool, kVersion);
  for (int i = 0; i < argc; ++i) line += " " + shellQuote(i == 0 ? tool : argv[i]);
  return line;
}

}  // namespace vdbappear
