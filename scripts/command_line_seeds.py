#!/usr/bin/env python3
"""Seeds and dictionary of the command-line fuzz harness (tests/fuzz/harnesses/fuzz_command_line.cpp),
from the tools' own --help: every example line of a tool becomes a seed (the tool's name, then one
argument per line; pipes cut, paths reduced to their file names, '-' to a file name, since the
harness skips inputs that leave its sandbox), and every flag that a --help names goes to the
dictionary, alone and after a line break, and with its
tool to command_line_flags.txt, the harness's flag insertions. Run it again when a tool's flags or examples change.

Usage: scripts/command_line_seeds.py [--build build]
"""
import argparse
import hashlib
import pathlib
import re
import shlex
import subprocess

ROOT = pathlib.Path(__file__).resolve().parent.parent
CORPUS = ROOT / "tests" / "fuzz" / "corpus" / "command_line"
DICTIONARY = ROOT / "tests" / "fuzz" / "dictionaries" / "command_line.dict"
FLAGS = ROOT / "tests" / "fuzz" / "dictionaries" / "command_line_flags.txt"


def examples(tool, help_text):
    """The argument lists of the example lines that run `tool` (shell comments and pipes cut)."""
    for line in help_text.splitlines():
        line = re.sub(r"\s(#|\(|  \s*[a-z]).*$", "", line.strip())  # a trailing remark
        for command in re.split(r"\||&&|>", line):
            if not command.strip().startswith(tool + " "):
                continue
            words = shlex.split(command, comments=True)
            if words[0] == tool:
                yield [pathlib.PurePath(w).name if "/" in w else ("stdin.vdb" if w == "-" else w) for w in words[1:]]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    args = parser.parse_args()
    CORPUS.mkdir(parents=True, exist_ok=True)
    flags, tool_flags = set(), []
    for binary in sorted((pathlib.Path(args.build) / "bin").glob("vdb_*")):
        tool = binary.name
        help_text = subprocess.run([binary, "--help"], capture_output=True, text=True, check=True).stdout
        named = sorted(set(re.findall(r"(?<![\w-])(--?[a-zA-Z][\w-]*)", help_text)))
        flags.update(named)
        tool_flags += [f"{tool} {flag}" for flag in named]
        seeds = [[]] + list(examples(tool, help_text))
        for words in seeds:
            text = "\n".join([tool] + words)
            name = f"{tool}-{hashlib.sha1(text.encode()).hexdigest()[:8]}"
            (CORPUS / name).write_text(text)
    # Each flag alone, and as a new argument (after a line break: libFuzzer inserts entries anywhere).
    DICTIONARY.write_text("".join(f'"{f}"\n"\\x0a{f}"\n' for f in sorted(flags)))
    FLAGS.write_text("".join(line + "\n" for line in tool_flags))  # the harness's own mutations
    print(f"{len(list(CORPUS.iterdir()))} seeds in {CORPUS}, {len(flags)} flags in {DICTIONARY}")


if __name__ == "__main__":
    main()
