#pragma once
// Runs a shell command line for command-line tests; captures exit status, stdout and stderr.

#include <algorithm>
#include <filesystem>
#include <string>

namespace vdbappear::test {

struct CommandResult {
  int status = -1;  // exit status, or -1 if the command did not exit normally
  std::string out, err;
};

CommandResult runCommand(const std::string& command_line);

std::string quote(const std::string& word);  // for the shell

// What a command left: whether it wrote `path`; how many lines it printed (one error line per bad input).
inline bool exists(const std::string& path) { return std::filesystem::exists(path); }
inline int lineCount(const std::string& text) { return int(std::count(text.begin(), text.end(), '\n')); }

}  // namespace vdbappear::test
