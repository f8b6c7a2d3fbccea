#include "run_command.h"

#include "support/temp_dir.h"

#include <cstdlib>
#include <sys/wait.h>

namespace vdbappear::test {

std::string quote(const std::string& word) {
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

CommandResult runCommand(const std::string& command_line) {
  TempDir capture;
  const std::string out = capture.path("out"), err = capture.path("err");
  const std::string wrapped = "( " + command_line + " ) >" + quote(out) + " 2>" + quote(err) + " </dev/null";
  const int raw = std::system(wrapped.c_str());
  CommandResult result;
  result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  result.out = readFileBytes(out);
  result.err = readFileBytes(err);
  return result;
}

}  // namespace vdbappear::test
