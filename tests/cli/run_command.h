#pragma once
// Runs a shell command line for command-line tests; captures exit status, stdout and stderr.

#include <string>

namespace vdbappear::test {

struct CommandResult {
  int status = -1;  // exit status, or -1 if the command did not exit normally
  std::string out, err;
};

CommandResult runCommand(const std::string& command_line);

std::string quote(const std::string& word);  // for the shell

}  // namespace vdbappear::test
