#!/usr/bin/env python3
"""Benchmark vdb_sggx_downsample --factor 2 against OpenVDB's vdb_lod -range 1, in one run.

Makes a 256^3 sparse medium (a 4-layer twill: density, RGB albedo, SGGX), extracts its density
grid, then times, interleaved, N runs of each command and prints the median wall times and their
ratios to vdb_lod's:
  vdb_lod -range 1                        on the density grid alone (the baseline)
  vdb_sggx_downsample -f 2                on the density grid alone (goal: ratio <= 1)
  vdb_sggx_downsample -f 2                on the full medium        (goal: ratio <= 2)
vdb_lod comes from Debian's libopenvdb-tools, installed here if missing (never a build dependency).

Usage: scripts/bench_downsample.py [--build build] [--out bench-out] [--runs 15] [--res 256]
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time


def find_vdb_lod():
    path = shutil.which("vdb_lod") or ("/usr/bin/vdb_lod" if os.path.exists("/usr/bin/vdb_lod") else None)
    if path:
        return path
    print("bench: installing libopenvdb-tools for vdb_lod", file=sys.stderr)
    sudo = [] if os.geteuid() == 0 else ["sudo"]
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    subprocess.run(sudo + ["apt-get", "update", "-qq"], check=True, env=env, stdout=subprocess.DEVNULL)
    subprocess.run(sudo + ["apt-get", "install", "-y", "-qq", "--no-install-recommends", "libopenvdb-tools"],
                   check=True, env=env, stdout=subprocess.DEVNULL)
    return "/usr/bin/vdb_lod"


def wall_time(cmd):
    start = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build", help="CMake build folder holding bin/")
    parser.add_argument("--out", default="bench-out", help="folder for media and the JSON result")
    parser.add_argument("--runs", type=int, default=15, help="timed runs of each command (median reported)")
    parser.add_argument("--res", type=int, default=256, help="medium resolution (voxels per side)")
    args = parser.parse_args()

    bin_dir = os.path.abspath(os.path.join(args.build, "bin"))
    make_medium = os.path.join(bin_dir, "vdb_make_medium")
    downsample = os.path.join(bin_dir, "vdb_sggx_downsample")
    vdb_lod = find_vdb_lod()
    os.makedirs(args.out, exist_ok=True)
    full = os.path.join(args.out, f"twill{args.res}.vdb")
    density = os.path.join(args.out, f"twill{args.res}_density.vdb")
    scratch = os.path.join(args.out, "scratch.vdb")

    subprocess.run([make_medium, "twill", "--res", str(args.res), "--layers", "4", "--seed", "1", "-o", full],
                   check=True)
    subprocess.run([vdb_lod, full, density, "-range", "0", "-name", "density", "-p"], check=True)

    commands = {
        "vdb_lod -range 1 (density)": [vdb_lod, density, scratch, "-range", "1"],
        "vdb_sggx_downsample -f 2 (density)": [downsample, "-f", "2", density, scratch],
        "vdb_sggx_downsample -f 2 (full medium)": [downsample, "-f", "2", full, scratch],
    }
    for cmd in commands.values():  # warm the page cache and the binaries
        wall_time(cmd)
    times = {name: [] for name in commands}
    for _ in range(args.runs):
        for name, cmd in commands.items():
            times[name].append(wall_time(cmd))
    os.remove(scratch)

    baseline = statistics.median(times["vdb_lod -range 1 (density)"])
    report = {"resolution": args.res, "runs": args.runs, "medium": full, "cpu_count": os.cpu_count(), "results": {}}
    print(f"{'command':42} {'median s':>9} {'min s':>7} {'ratio':>6}")
    for name, samples in times.items():
        median = statistics.median(samples)
        report["results"][name] = {"median_s": median, "min_s": min(samples), "ratio_to_vdb_lod": median / baseline,
                                   "samples_s": samples}
        print(f"{name:42} {median:9.3f} {min(samples):7.3f} {median / baseline:6.2f}")
    with open(os.path.join(args.out, "bench_downsample.json"), "w") as f:
        json.dump(report, f, indent=2)


if __name__ == "__main__":
    main()
