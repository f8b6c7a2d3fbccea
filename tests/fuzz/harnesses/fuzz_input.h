#pragma once
// Support for the libFuzzer harnesses of tests/fuzz/harnesses: the readers of vdbappear take paths
// (what the tools are given), so each input is written to a file of the reader's extension in a
// folder of this process's own, rewritten for every input and removed at exit.

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

namespace vdbappear::fuzz {

// The path of a file holding the input, named `name` (its extension selects the format where the
// reader looks at it).
std::string writeInput(const std::uint8_t* data, std::size_t size, const std::string& name);

// The readers' contract (README, docs/reliability.md): bad input ends in an exception whose message
// names the file. A message that does not is a finding: the harness aborts, libFuzzer keeps the input.
void expectNamed(const std::exception& error, const std::string& path);

// The body of a harness whose reader takes a path: writes the input to `name`, reads it with
// read(path), and checks that what the reader throws names the file.
template <typename Read>
int readInputFile(const std::uint8_t* data, std::size_t size, const std::string& name, Read read) {
  const std::string path = writeInput(data, size, name);
  try {
    read(path);
  } catch (const std::exception& e) {
    expectNamed(e, path);
  }
  return 0;
}

}  // namespace vdbappear::fuzz
