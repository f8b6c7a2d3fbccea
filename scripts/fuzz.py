#!/usr/bin/env python3
"""Coverage-guided fuzzing of every reader of outside bytes with the libFuzzer harnesses of
tests/fuzz/harnesses (docs/reliability.md §5), built by `make test-sanitize` (clang, AddressSanitizer
and UndefinedBehaviorSanitizer) into build-sanitize/fuzz/.

Each harness fuzzes for --seconds with a working corpus OUT/corpus/NAME that starts from its seeds
(tests/fuzz/corpus/NAME; grids/golden for the media) and keeps what found new coverage; findings
(crashes, leaks, inputs slower than --timeout seconds, more than --memory-mb) land in
OUT/findings/NAME/. A finding worth keeping goes, after its fix, to tests/fuzz/corpus/NAME (the
harness replays its corpus in make test-sanitize) and, when a tool should refuse it, to
tests/fuzz/regressions/ (make test). Writes OUT/report.md and OUT/report.json: per harness, the
executions, the corpus size, the coverage (edges and features) and the findings.

Usage: scripts/fuzz.py [--build build-sanitize] [--out fuzz-out] [--seconds 600] [--parallel 2]
       [--timeout 1] [--memory-mb 2048] [--rss-mb 2048] [--harnesses medium_file,scene,...]

--memory-mb bounds each allocation; --rss-mb the whole process, which also holds what OpenVDB 10
leaks of a partial tree each time reading a grid throws (docs/reliability.md §3): over thousands of
damaged media in one process that passes 2 GB, so the media harnesses are run with more.
"""
import argparse
import json
import os
import pathlib
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

ROOT = pathlib.Path(__file__).resolve().parent.parent
HARNESSES = ["medium_file", "medium_stream", "scene", "light_list", "phase_table", "sh_light_grid", "mesh",
             "environment_map", "reference_cache", "checkpoint", "command_line"]
# The command-line harness: its flags as a dictionary; the tools' error lines (one per input) kept
# out of its log (libFuzzer's own output and sanitizer reports still reach it).
EXTRA = {"command_line": [f"-dict={ROOT / 'tests' / 'fuzz' / 'dictionaries' / 'command_line.dict'}", "-close_fd_mask=2"]}
# libFuzzer's status line: "#1234 REDUCE cov: 456 ft: 789 corp: 12/34Kb ..."
STATUS = re.compile(r"^#(\d+)\s+\S+\s+cov: (\d+) ft: (\d+) corp: (\d+)/")


def seeds_of(name):
    return ROOT / "grids" / "golden" if name.startswith("medium_") else ROOT / "tests" / "fuzz" / "corpus" / name


def fuzz(name, args):
    binary = pathlib.Path(args.build) / "fuzz" / f"fuzz_{name}"
    if not binary.exists():
        sys.exit(f"fuzz.py: {binary}: no such harness (build it with make test-sanitize)")
    out = pathlib.Path(args.out).resolve()  # the command-line harness runs tools in a removed folder
    corpus, findings = out / "corpus" / name, out / "findings" / name
    corpus.mkdir(parents=True, exist_ok=True)
    findings.mkdir(parents=True, exist_ok=True)
    log = out / f"{name}.log"
    command = [str(binary), str(corpus), str(seeds_of(name)), f"-max_total_time={args.seconds}",
               f"-timeout={args.timeout}", f"-rss_limit_mb={args.rss_mb or args.memory_mb}", f"-malloc_limit_mb={args.memory_mb}",
               f"-artifact_prefix={findings}/", "-print_final_stats=1", "-detect_leaks=1"] + EXTRA.get(name, [])
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1:abort_on_error=0", UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1",
               LSAN_OPTIONS=f"suppressions={ROOT / 'tests' / 'lsan.supp'}:print_suppressions=0")
    start = time.monotonic()
    with open(log, "w") as stream:
        rc = subprocess.run(command, stdout=stream, stderr=subprocess.STDOUT, env=env).returncode
    seconds = round(time.monotonic() - start)  # less than --seconds when it stopped at a finding
    executions = coverage = features = corpus_size = 0
    for line in log.read_text(errors="replace").splitlines():
        status = STATUS.match(line)
        if status:
            executions, coverage, features, corpus_size = map(int, status.groups())
        elif line.startswith("stat::number_of_executed_units:"):
            executions = int(line.split(":")[-1])
    found = sorted(p.name for p in findings.iterdir())
    return {"harness": name, "seconds": seconds, "executions": executions, "corpus": corpus_size,
            "edges": coverage, "features": features, "findings": found, "exit": rc, "log": str(log)}


def report(results, out):
    (out / "report.json").write_text(json.dumps(results, indent=1) + "\n")
    lines = ["| harness | seconds | executions | corpus | edges | features | findings |", "|---|---:|---:|---:|---:|---:|---|"]
    for r in results:
        lines.append(f"| {r['harness']} | {r['seconds']} | {r['executions']} | {r['corpus']} | {r['edges']} | "
                     f"{r['features']} | {', '.join(r['findings']) or 'none'} |")
    (out / "report.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build-sanitize")
    parser.add_argument("--out", default="fuzz-out")
    parser.add_argument("--seconds", type=int, default=600, help="fuzzing time per harness")
    parser.add_argument("--parallel", type=int, default=2, help="harnesses fuzzed at once (one core each)")
    parser.add_argument("--timeout", type=int, default=1, help="seconds an input may take")
    parser.add_argument("--memory-mb", type=int, default=2048, help="bytes one allocation may take, in MB")
    parser.add_argument("--rss-mb", type=int, default=0, help="the process's memory, in MB (default: --memory-mb)")
    parser.add_argument("--harnesses", default=",".join(HARNESSES))
    args = parser.parse_args()
    names = [n for n in args.harnesses.split(",") if n]
    unknown = [n for n in names if n not in HARNESSES]
    if unknown:
        sys.exit(f"fuzz.py: unknown harness {', '.join(unknown)} (known: {', '.join(HARNESSES)})")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with ThreadPoolExecutor(max_workers=args.parallel) as pool:
        results = list(pool.map(lambda n: fuzz(n, args), names))
    report(results, out)
    return 1 if any(r["findings"] for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())
