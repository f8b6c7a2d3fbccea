#!/usr/bin/env python3
"""Mutation fuzzing of the tools' promise on bad input (docs/reliability.md): every tool, given a
mutated medium, scene file or light list, ends within the time limit with either a clean refusal
(non-zero exit, an error line on stderr, no output file) or a success (exit 0, an output file) --
never a signal, a hang, an out-of-memory kill, a partial output or a modified input.

Mutations of a seed file (grids/golden, the example scene and light list below): bit flips, bytes
set to extreme values, 4- and 8-byte words overwritten with extreme integers, NaN or infinity,
truncation, inserted and deleted runs, a duplicated chunk. The same --seed gives the same inputs.
Each finding is kept in OUT/findings/ as the input, the command and what went wrong; an input
worth keeping for good goes to tests/fuzz/regressions/ (replayed by make test).

Usage: scripts/mutation_fuzz.py [--build build] [--out fuzz-out] [--runs 2000] [--seed 1]
       [--timeout 30] [--memory-gb 2] [--targets preview,render,...]
"""
import argparse
import json
import os
import pathlib
import random
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
GOLDEN = ROOT / "grids" / "golden"

SCENE = {"medium": "medium.vdb", "resolution": [12, 10], "spp": 2, "seed": 3, "max_depth": 4,
         "camera": {"position": [0, -3, 0.5], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 35},
         "lights": [{"type": "env", "radiance": 0.3}, {"type": "sun", "direction": [1, 0.5, -1], "strength": 2},
                    {"type": "point", "position": [1, -1, 2], "intensity": 3},
                    {"type": "quad", "corner": [-1, -1, 2], "edge1": [2, 0, 0], "edge2": [0, 2, 0], "radiance": 1}],
         "ground": {"height": -1, "albedo": 0.5}}

LIGHTS = [{"vertices": [[-1, -1, 2], [1, -1, 2], [1, 1, 2], [-1, 1, 2]], "radiance": 1},
          {"vertices": [[1.5, -1, 0], [1.5, 1, 0], [1.5, 0, 1]], "radiance": [1, 0.5, 0.2], "two_sided": True}]

# name: (kind of input, seed files or None for the generated text, command with IN and OUT)
TARGETS = {
    "preview": ("medium", None, ["vdb_preview", "IN", "-o", "OUT.png", "--width", "32", "-j", "1"]),
    "render": ("medium", None, ["vdb_render", "IN", "-o", "OUT.png", "--res", "12", "--spp", "2", "-j", "1",
                                "--env", "0.5", "--sun", "1,1,-1,2"]),
    "downsample": ("medium", None, ["vdb_sggx_downsample", "IN", "OUT.vdb", "--factor", "2", "-j", "1"]),
    "lobes": ("medium", ["twill24.vdb", "velvet16.vdb", "hairy-ball16.vdb", "twill24_naive2x.vdb"], ["vdb_lobe_cluster", "IN", "OUT.vdb", "--factor", "2", "--lobes", "2",
                               "--clusters", "2", "-j", "1"]),
    "similarity": ("medium", ["cloud16.vdb"], ["vdb_similarity", "IN", "OUT.vdb", "-j", "1"]),
    "stack": ("medium", ["exemplars8.vdb"], ["vdb_exemplar_stack", "stack", "IN", "OUT.vdb"]),
    "scene": ("scene", None, ["vdb_render", "--scene", "IN", "-o", "OUT.png", "-j", "1"]),
    "lights": ("lights", None, ["vdb_sh_lightgrid", "--lights", "IN", "--bbox", "-1,-1,-1,1,1,1", "--res", "3",
                                "--lmax", "2", "-o", "OUT.vdb", "-j", "1"]),
}

EXTREME_BYTES = [0x00, 0xFF, 0x7F, 0x80, 0x01, 0xFE]
EXTREME_WORDS = [struct.pack("<i", v) for v in (0, -1, 1, 2**31 - 1, -2**31, 2**24, 65536)] + \
                [struct.pack("<f", v) for v in (float("nan"), float("inf"), -float("inf"), -1.0, 1e30, 1e-30)]
EXTREME_LONGS = [struct.pack("<q", v) for v in (-1, 2**63 - 1, 2**40, 2**32)] + \
                [struct.pack("<d", v) for v in (float("nan"), float("inf"), -1.0, 1e300)]


def mutate(data, rng):
    """One to four random mutations of the bytes."""
    data = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        if not data:
            data += bytes([rng.randrange(256)])
        op = rng.randrange(8)
        pos = rng.randrange(len(data))
        if op == 0:  # bit flips
            for _ in range(rng.randint(1, 8)):
                p = rng.randrange(len(data))
                data[p] ^= 1 << rng.randrange(8)
        elif op == 1:
            data[pos] = rng.choice(EXTREME_BYTES)
        elif op == 2:
            w = rng.choice(EXTREME_WORDS)
            data[pos:pos + 4] = w
        elif op == 3:
            w = rng.choice(EXTREME_LONGS)
            data[pos:pos + 8] = w
        elif op == 4:  # truncate
            del data[pos:]
        elif op == 5:  # insert random bytes
            data[pos:pos] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 64)))
        elif op == 6:  # delete a run
            del data[pos:pos + rng.randint(1, 256)]
        else:  # duplicate a chunk elsewhere
            a = rng.randrange(len(data))
            chunk = data[a:a + rng.randint(1, 512)]
            data[pos:pos] = chunk
    return bytes(data)


def mutate_json(text, rng):
    """Text inputs: half of the time a structural change to a number or key, else byte mutations."""
    if rng.random() < 0.5:
        return mutate(text.encode(), rng)
    obj = json.loads(text)
    values = ["nan", "1e308", "-1e308", "-1", "0", "1e-320", "2147483648", '"x"', "[]", "{}", "null", "true",
              "[1,2]", "[0,0,0]", "[1e308,1e308,1e308]", "-0"]

    def walk(o, depth=0):
        if isinstance(o, dict) and o:
            k = rng.choice(list(o))
            if rng.random() < 0.3 or depth > 3:
                return k, o
            return walk(o[k], depth + 1) if isinstance(o[k], (dict, list)) and o[k] else (k, o)
        if isinstance(o, list) and o:
            i = rng.randrange(len(o))
            if rng.random() < 0.3 or not isinstance(o[i], (dict, list)) or not o[i]:
                return i, o
            return walk(o[i], depth + 1)
        return None, None

    key, parent = walk(obj)
    if parent is None:
        return mutate(text.encode(), rng)
    marker = "\u0000MUTATED\u0000"
    parent[key] = marker
    out = json.dumps(obj).replace(json.dumps(marker), rng.choice(values))
    return out.encode()


def seeds_for(kind, names):
    if kind == "medium":
        paths = [GOLDEN / n for n in names] if names else sorted(GOLDEN.glob("*.vdb"))
        return [(p.name, p.read_bytes()) for p in paths]
    if kind == "scene":
        return [("scene.json", json.dumps(SCENE, indent=1).encode())]
    return [("lights.json", json.dumps({"lights": LIGHTS}, indent=1).encode())]


def limit_memory(gb):
    def apply():
        limit = int(gb * (1 << 30))
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        os.setsid()
    return apply


def run_case(bin_dir, target, data, kind, work, args):
    """Runs one input; returns the command, None when the promise held (else what went wrong), and
    whether the tool succeeded (exit 0) rather than refused."""
    _, _, template = TARGETS[target]
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    suffix = ".vdb" if kind == "medium" else ".json"
    inp = work / ("input" + suffix)
    inp.write_bytes(data)
    if kind == "scene":  # the scene's medium: an intact golden grid beside it
        shutil.copy(GOLDEN / "cube8.vdb", work / "medium.vdb")
    out_base = work / "out"
    cmd = [str(bin_dir / template[0])] + [str(inp) if a == "IN" else a.replace("OUT", str(out_base))
                                          for a in template[1:]]
    outputs = [pathlib.Path(a) for a in cmd if a.startswith(str(out_base))]
    try:
        p = subprocess.run(cmd, cwd=work, capture_output=True, timeout=args.timeout,
                           preexec_fn=limit_memory(args.memory_gb))
    except subprocess.TimeoutExpired:
        return cmd, f"hang: no exit within {args.timeout} s", False
    except OSError as e:  # the tool itself is missing or being rebuilt: nothing to learn from this run
        sys.exit(f"fuzz: cannot run {cmd[0]}: {e}")
    stderr = p.stderr.decode(errors="replace")
    problem = judge(p.returncode, stderr, inp, data, outputs, work)
    return cmd, problem, p.returncode == 0


def judge(returncode, stderr, inp, data, outputs, work):
    """What broke the promise in one finished run, or None."""
    if returncode < 0:
        return f"signal {signal.Signals(-returncode).name}: {stderr.strip()[-400:]}"
    if inp.read_bytes() != data:
        return "the input file was modified"
    if returncode != 0:
        if any(o.exists() for o in outputs):
            return f"exit {returncode} but an output file exists"
        lines = [l for l in stderr.splitlines() if l.strip()]
        if not lines:
            return f"exit {returncode} with nothing on stderr"
        if any("terminate called" in l or "Aborted" in l or "AddressSanitizer" in l or "runtime error" in l
               for l in lines):
            return f"exit {returncode}: {stderr.strip()[-400:]}"
    elif not all(o.exists() for o in outputs):
        return "exit 0 without an output file"
    leftovers = [f.name for f in work.iterdir() if f.name not in {inp.name, "medium.vdb"} and f not in outputs]
    return f"files left behind: {leftovers}" if leftovers else None


def write_report(out, args, done, seconds, tally, findings):
    report = {"runs_done": done, "runs_asked": args.runs, "seconds": round(seconds, 1), "seed": args.seed,
              "timeout_s": args.timeout, "memory_gb": args.memory_gb, "targets": tally, "findings": findings}
    (out / "report.json").write_text(json.dumps(report, indent=1) + "\n")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build")
    p.add_argument("--out", default="fuzz-out")
    p.add_argument("--runs", type=int, default=2000, help="mutated inputs in all, shared among the targets")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--timeout", type=float, default=30)
    p.add_argument("--memory-gb", type=float, default=2)
    p.add_argument("--targets", default=",".join(TARGETS))
    args = p.parse_args()
    bin_dir = (pathlib.Path(args.build) / "bin").resolve()
    out = pathlib.Path(args.out).resolve()
    findings_dir = out / "findings"
    findings_dir.mkdir(parents=True, exist_ok=True)
    rng = random.Random(args.seed)
    targets = args.targets.split(",")
    tally = {t: {"runs": 0, "refused": 0, "succeeded": 0, "findings": 0} for t in targets}
    findings = []
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="vdbappear-fuzz-") as tmp:
        work = pathlib.Path(tmp) / "case"
        seeds = {target: seeds_for(TARGETS[target][0], TARGETS[target][1]) for target in targets}
        for target in targets:  # the unmutated seeds must succeed, or the fuzzer tests nothing
            for seed_name, seed_data in seeds[target]:
                cmd, problem, succeeded = run_case(bin_dir, target, seed_data, TARGETS[target][0], work, args)
                if problem or not succeeded:
                    sys.exit(f"fuzz: the seed {seed_name} fails {target}: {problem or 'refused'}: {' '.join(cmd)}")
        for i in range(args.runs):
            target = targets[i % len(targets)]
            kind = TARGETS[target][0]
            seed_name, seed_data = rng.choice(seeds[target])
            data = mutate(seed_data, rng) if kind == "medium" else mutate_json(seed_data.decode(), rng)
            cmd, problem, succeeded = run_case(bin_dir, target, data, kind, work, args)
            t = tally[target]
            t["runs"] += 1
            if problem:
                t["findings"] += 1
                name = f"{target}-{i:05d}"
                (findings_dir / (name + (".vdb" if kind == "medium" else ".json"))).write_bytes(data)
                record = {"run": i, "target": target, "seed_file": seed_name, "problem": problem,
                          "command": [c.replace(str(work), "WORK") for c in cmd]}
                (findings_dir / (name + ".txt")).write_text(json.dumps(record, indent=1) + "\n")
                findings.append(record)
                print(f"fuzz: run {i} {target} ({seed_name}): {problem[:200]}", file=sys.stderr)
            elif succeeded:
                t["succeeded"] += 1
            else:
                t["refused"] += 1
            if sys.stderr.isatty():
                print(f"\rfuzz: {i + 1}/{args.runs}, {len(findings)} findings", end="", file=sys.stderr)
            if (i + 1) % 50 == 0 or i + 1 == args.runs:  # a report that survives an interrupted run
                write_report(out, args, i + 1, time.monotonic() - start, tally, findings)
    if sys.stderr.isatty():
        print(file=sys.stderr)
    lines = ["| target | runs | refused | succeeded | findings |", "|---|---:|---:|---:|---:|"]
    for name, t in tally.items():
        lines.append(f"| {name} | {t['runs']} | {t['refused']} | {t['succeeded']} | {t['findings']} |")
    print("\n".join(lines))
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
