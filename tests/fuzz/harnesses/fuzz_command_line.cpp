// libFuzzer harness: every tool's command line. An input is a tool's name on its first line and its
// arguments, one per line after it. Each tool's main is compiled into this harness under another
// name (tests/fuzz/CMakeLists.txt) and called in-process, in a sandbox where no file can be read or
// written: the working directory is a folder that has already been removed, and an input whose
// arguments name a path with '/' (outside the sandbox) or end in '-' (stdin, stdout: "-", "-o-",
// "--output=-") is skipped. So every tool stops at its first read or write, after everything it
// checks of its flags alone: CLI11's parsing, value ranges, combinations, output paths.
//
// Findings: a crash, a sanitizer report, an uncaught exception, an input slower than libFuzzer's
// -timeout, and exit status 0 where a tool needs a file (a tool that says it succeeded without
// reading or writing anything): all but --help, --version, --list and `vdb_similarity --hg G`, which
// prints the altered phase function of one HG to stdout.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

#define VDBAPPEAR_TOOL(name) int name##_main(int, char**);
#include "command_line_tools.inc"
#undef VDBAPPEAR_TOOL

namespace {

struct Tool {
  const char* name;
  int (*main)(int, char**);
};

const Tool kTools[] = {
#define VDBAPPEAR_TOOL(name) {#name, name##_main},
#include "command_line_tools.inc"
#undef VDBAPPEAR_TOOL
};

[[noreturn]] void fail(const char* what) {
  std::perror(what);
  std::abort();
}

// The working directory of every call: a folder removed right after it was made. Relative paths
// resolve in it and fail (ENOENT), even for root, whom permissions would not stop.
struct Sandbox {
  int removed_folder = -1, home = -1;

  Sandbox() {
    const char* tmp = std::getenv("TMPDIR");
    std::string path = std::string(tmp && *tmp ? tmp : "/tmp") + "/vdbappear-fuzz-cli-XXXXXX";
    if (!mkdtemp(path.data())) fail("fuzz_command_line: mkdtemp");
    removed_folder = open(path.c_str(), O_RDONLY | O_DIRECTORY);
    home = open(".", O_RDONLY | O_DIRECTORY);
    if (removed_folder < 0 || home < 0 || rmdir(path.c_str()) != 0) fail("fuzz_command_line: sandbox");
    // No terminal, no pipe: what a tool reads from stdin is empty, what it writes to stdout is dropped.
    const int null = open("/dev/null", O_RDWR);
    if (null < 0 || dup2(null, STDIN_FILENO) < 0 || dup2(null, STDOUT_FILENO) < 0) fail("fuzz_command_line: /dev/null");
    close(null);
  }
};

std::vector<std::string> linesOf(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> lines(1);
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == '\n') lines.emplace_back();
    else lines.back().push_back(char(data[i]));
  }
  return lines;
}

bool leavesTheSandbox(const std::string& argument) {
  return argument.find('/') != std::string::npos || (!argument.empty() && argument.back() == '-');
}

// The runs that need no file: help, the version and vdb_make_medium's list, however CLI11 finds
// them in an argument (a short-flag cluster with h; "-v-version" prints the version), and
// vdb_similarity --hg.
bool needsNoFile(const std::string& tool, const std::vector<std::string>& arguments) {
  return std::any_of(arguments.begin(), arguments.end(), [&](const std::string& a) {
    const bool option = !a.empty() && a[0] == '-', short_cluster = a.size() > 1 && option && a[1] != '-';
    return (option && (a.find("help") != std::string::npos || a.find("version") != std::string::npos ||
                       a.find("list") != std::string::npos)) ||
           (short_cluster && a.find('h') != std::string::npos) || (tool == "vdb_similarity" && a.rfind("--hg", 0) == 0);
  });
}

// Mutations at the level of arguments, which byte mutations rarely make: a tool needs a whole flag
// (and its value) at the start of a line, and only a new flag combination that changes coverage
// would be kept on the way to it. Half the mutations are libFuzzer's own, on the bytes.
struct ToolFlag {
  const char* tool;
  const char* flag;
};
const ToolFlag kFlags[] = {
#include "command_line_flags.inc"
};

const char* const kValues[] = {
    "0", "1", "-1", "2", "3", "0.5", "-0.5", "1e-9", "1e308", "-1e308", "1e-320", "nan", "-nan", "inf", "-inf",
    "2147483647", "2147483648", "-2147483649", "4294967296", "18446744073709551616", "99999999999999999999", "",
    " ", "x", "0x10", "1,2", "0,0,0", "1,1,1", "nan,0,0", "1,2,3,4", "0,0,0,0", "1,1,-1,3", "-1,-1,-1,1,1,1",
    "16x16", "0x0", "16384x16384", "1x99999", "+x", "-y", "+z", "faces", "sh1", "a.vdb", "b.exr", "c.png",
    "d.json", "e.txt", "stack", "split", "assemble", "twill", "cloud", "random", "exemplars", "hg", "mis"};

std::size_t below(std::size_t n, std::mt19937& random) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(random); }

template <typename T, std::size_t N>
const T& pick(const T (&items)[N], std::mt19937& random) {
  return items[below(N, random)];
}

// A flag of `tool` (any tool's if it has none listed).
std::string flagOf(const std::string& tool, std::mt19937& random) {
  std::vector<const char*> flags;
  for (const ToolFlag& f : kFlags)
    if (tool == f.tool) flags.push_back(f.flag);
  return flags.empty() ? pick(kFlags, random).flag : flags[below(flags.size(), random)];
}

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (std::size_t i = 0; i < lines.size(); ++i) text += (i ? "\n" : "") + lines[i];
  return text;
}

}  // namespace

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  std::mt19937 random(seed);
  if (below(2, random) == 0) return LLVMFuzzerMutate(data, size, max_size);
  std::vector<std::string> lines = linesOf(data, size);
  const std::size_t arguments = lines.size() - 1;
  const std::size_t at = 1 + below(arguments + 1, random);  // 1..arguments + 1
  switch (below(6, random)) {
    case 0: lines.insert(lines.begin() + at, flagOf(lines[0], random)); break;
    case 1: lines.insert(lines.begin() + at, {flagOf(lines[0], random), pick(kValues, random)}); break;
    case 2: lines.insert(lines.begin() + at, pick(kValues, random)); break;
    case 3: if (at <= arguments) lines[at] = pick(kValues, random); break;
    case 4: if (at <= arguments) lines.erase(lines.begin() + at); break;
    case 5: lines[0] = pick(kTools, random).name; break;
  }
  const std::string text = joined(lines);
  if (text.size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
  std::copy(text.begin(), text.end(), data);
  return text.size();
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Sandbox sandbox;
  std::vector<std::string> arguments = linesOf(data, size);
  const auto tool = std::find_if(std::begin(kTools), std::end(kTools), [&](const Tool& t) { return arguments[0] == t.name; });
  if (tool == std::end(kTools) || arguments.size() > 64) return 0;
  if (std::any_of(arguments.begin() + 1, arguments.end(), leavesTheSandbox)) return 0;

  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  argv.push_back(nullptr);
  if (fchdir(sandbox.removed_folder) != 0) fail("fuzz_command_line: fchdir");
  const int status = tool->main(int(arguments.size()), argv.data());
  if (fchdir(sandbox.home) != 0) fail("fuzz_command_line: fchdir");

  if (status == 0 && !needsNoFile(tool->name, {arguments.begin() + 1, arguments.end()})) {
    std::fprintf(stderr, "fuzz_command_line: %s ended in success without reading or writing a file\n", tool->name);
    std::abort();
  }
  return 0;
}
