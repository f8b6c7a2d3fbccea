#!/usr/bin/env python3
"""make bench-scale: time and peak memory against active voxels, in one run (issue 28, docs/scaling.md §5).

For each size N (default 256, 512, 1024 and 1792), the twill `vdb_make_medium twill --layers 4 --seed 1
--res N` is made (its own time and memory measured too), then each command below runs once under
`/usr/bin/time -v` (wall time, maximum resident set size):
  vdb_sggx_downsample -f 2 --in-core        the whole medium read at once (the baseline; up to --whole-max)
  vdb_sggx_downsample -f 2                  in slabs within the default budget
  vdb_lobe_cluster --factor 4 --lobes 2 --clusters 2 --in-core   read whole (the baseline; up to --lobe-whole-max)
  vdb_lobe_cluster --factor 4 --lobes 2 --clusters 2   in slabs within the default budget (up to --lobe-max)
  vdb_render 64x64, 1 spp                   the compact form, read in pieces (up to --render-max: some 31 GB
                                            at 1792^3)
  vdb_render 64x64, 1 spp --full-precision  the float grids, read whole (up to --whole-max)
  vdb_lod -range 1 on the density grid      OpenVDB's own tool, the peer (Debian's libopenvdb-tools; it reads
                                            the grid whole, as does the vdb_lod that cuts the density out:
                                            up to --whole-max)
At every size up to --whole-max, the two forms' images are compared (scripts/image_agreement.py, under
Blender: two renders of each, 96x96 at 16 spp, seeds 1 and 2 for the float grids, 3 and 4 for the compact
form, mean and 8x8 tiles); at the smallest size
the two forms' paths per second (128x128 at 16 spp, three alternating pairs, the median of each).
The 1792^3 twill is the medium of at least 10^9 active voxels that the issue asks for (1.06 billion; a
15.7 GB file made in 27 minutes on 2 cores, at 5.9 GB): read whole it would take some 110 GB, so only
the slab downsample runs at that size. --sizes 256,512,1024 leaves it out. vdb_lobe_cluster in slabs
takes some 16 minutes at 1024^3 (its lobe fits: 7,400 coarse voxels a second on 2 cores), so the
whole run takes about 30 minutes with --sizes 256,512,1024 and about 65 with 1792. Media are made in --out and removed at the end unless --keep.

Writes bench-out/scale.md (a table) and bench-out/scale.png (log-log: seconds and GB against active
voxels), and bench-out/scale.json.
Usage: scripts/bench_scale.py [--build build] [--out bench-out] [--sizes 256,512,1024,1792] [--keep]
       [--whole-max 1024] [--lobe-max 1024] [--lobe-whole-max 512] [--render-max 1024]
"""
import argparse
import json
import os
import pathlib
import re
import subprocess
import sys

from bench_downsample import find_vdb_lod
from bench_render import image_agreement
from debian_packages import run_plot_script


def timed(cmd):
    """(seconds, peak GB) of one run under /usr/bin/time -v."""
    r = subprocess.run(["/usr/bin/time", "-v"] + [str(c) for c in cmd], text=True, capture_output=True)
    if r.returncode != 0:
        sys.exit(f"bench-scale: {' '.join(map(str, cmd))} failed:\n{r.stderr[-2000:]}")
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", r.stderr).group(1)
    seconds = 0.0
    for part in wall.split(":"):
        seconds = seconds * 60 + float(part)
    kbytes = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", r.stderr).group(1))
    return seconds, kbytes * 1024 / 1e9


def render_report(cmd, report):
    """vdb_render's JSON report of one run."""
    subprocess.run([str(c) for c in cmd] + ["--report", str(report)], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    return json.loads(pathlib.Path(report).read_text())


def render_speed(render, medium, work):
    """Median paths per second of the compact form and of the float grids, in alternating pairs."""
    paths = {"compact": [], "full": []}
    for _ in range(3):
        for form, extra in (("compact", []), ("full", ["--full-precision"])):
            r = render_report(render + [medium, "-o", work / "speed.exr", "--res", "128", "--spp", "16"] + extra,
                              work / "speed.json")
            paths[form].append(r["paths_per_second"])
    return {form: sorted(v)[1] for form, v in paths.items()}


def form_agreement(render, medium, work):
    """The compact form's image against the float grids' (scripts/image_agreement.py). Four seeds: the two
    forms' paths with one seed are nearly the same, which would hide their differences in the noise."""
    exrs = []
    for extra, seeds in ((["--full-precision"], (1, 2)), ([], (3, 4))):
        for seed in seeds:
            exr = work / f"agree_{len(exrs)}.exr"
            subprocess.run([str(c) for c in render + [medium, "-o", exr, "--res", "96", "--spp", "16", "--seed", seed]
                            + extra], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            exrs.append(exr)
    agreement = image_agreement(exrs)
    for exr in exrs:
        exr.unlink()
    return agreement


def render_checks(by_res):
    """The issue's points for vdb_render's compact form."""
    out = ["", "## The issue's points (vdb_render, the compact form)", ""]
    if 1024 in by_res and "render" in by_res[1024]:
        s, gb = by_res[1024]["render"]
        out.append(f"- 1024^3: {gb:.2f} GB (at most 8), {s:.0f} s: {'met' if gb <= 8 else 'not met'}")
    for n, r in by_res.items():
        if "agreement" in r:
            a = r["agreement"]
            out.append(f"- {n}^3, compact against float grids: variance ratio {a['variance_ratio']:.3f} (1 if they agree), "
                       f"{a['tile']}x{a['tile']} tiles' z mean {a['tile_z_mean']:+.2f}, rms {a['tile_z_rms']:.2f}, "
                       f"{a['tile_z_over_4']} of {a['tiles']} beyond 4")
        if "render_speed" in r:
            v = r["render_speed"]
            out.append(f"- {n}^3, paths per second: compact {v['compact']:.4g}, float grids {v['full']:.4g} "
                       f"({v['compact'] / v['full']:.2f}x; no lower: {'met' if v['compact'] >= v['full'] else 'not met'})")
    return out if len(out) > 3 else []


def lobe_checks(by_res):
    """The issue's points for vdb_lobe_cluster in slabs."""
    slabs = {n: r["lobe_cluster_slabs"] for n, r in by_res.items() if "lobe_cluster_slabs" in r}
    out = ["", "## The issue's points (vdb_lobe_cluster -f 4 --lobes 2 --clusters 2 in slabs)", ""]
    if 1024 in slabs:
        s, gb = slabs[1024]
        out.append(f"- 1024^3: {gb:.2f} GB (at most 4), {s:.0f} s: {'met' if gb <= 4 else 'not met'}")
    if 512 in slabs and 1024 in slabs:
        ratio = slabs[1024][1] / slabs[512][1]
        out.append(f"- peak at 1024^3 over peak at 512^3: {ratio:.2f}x (at most 1.5x): {'met' if ratio <= 1.5 else 'not met'}")
    return out if len(out) > 3 else []


def checks(rows):
    """The issue's points for the slab downsample and lobe clustering, where this run measured what they need."""
    by_res = {r["res"]: r for r in rows}
    slabs = {n: r["downsample_slabs"] for n, r in by_res.items()}
    ns = {n: slabs[n][0] / by_res[n]["active_voxels"] * 1e9 for n in slabs}
    out = ["", "## The issue's points (downsample -f 2 in slabs)", ""]
    if 1024 in slabs:
        s, gb = slabs[1024]
        out.append(f"- 1024^3: {gb:.2f} GB (at most 4), {s:.1f} s (at most 38): "
                   f"{'met' if gb <= 4 and s <= 38 else 'not met'}")
    if 512 in slabs and 1024 in slabs:
        ratio = slabs[1024][1] / slabs[512][1]
        out.append(f"- peak at 1024^3 over peak at 512^3: {ratio:.2f}x (at most 1.5x): {'met' if ratio <= 1.5 else 'not met'}")
    if 256 in ns and 1024 in ns:
        out.append(f"- time per active voxel: {ns[1024]:.0f} ns at 1024^3, {ns[256]:.0f} ns at 256^3: "
                   f"{'met' if ns[1024] <= ns[256] else 'not met'}")
    for n, r in by_res.items():
        if r["active_voxels"] >= 1e9:
            s, gb = slabs[n]
            out.append(f"- {r['active_voxels'] / 1e9:.2f} billion active voxels ({n}^3, a {r['file_gb']:.1f} GB file): "
                       f"{s:.0f} s, {gb:.2f} GB (at most 6): {'met' if gb <= 6 else 'not met'}")
    return out + lobe_checks(by_res) + render_checks(by_res)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build")
    p.add_argument("--out", default="bench-out")
    p.add_argument("--sizes", default="256,512,1024,1792")
    p.add_argument("--keep", action="store_true", help="keep the media")
    p.add_argument("--whole-max", type=int, default=1024,
                   help="largest size the whole reads run at (the in-core downsample and vdb_lod; 22 GB at 1024)")
    p.add_argument("--lobe-max", type=int, default=1024, help="largest size vdb_lobe_cluster runs at in slabs")
    p.add_argument("--lobe-whole-max", type=int, default=512,
                   help="largest size vdb_lobe_cluster --in-core runs at (3.1 GB at 512)")
    p.add_argument("--render-max", type=int, default=1024,
                   help="largest size vdb_render's compact form runs at (its float grids: up to --whole-max)")
    args = p.parse_args()
    bin_dir = pathlib.Path(args.build).resolve() / "bin"
    out = pathlib.Path(args.out).resolve()
    work = out / "scale"
    work.mkdir(parents=True, exist_ok=True)
    vdb_lod = find_vdb_lod()
    rows = []
    for n in [int(s) for s in args.sizes.split(",")]:
        medium, density, scratch = work / f"twill{n}.vdb", work / f"twill{n}_density.vdb", work / "scratch.vdb"
        report = work / "report.json"
        print(f"bench-scale: {n}^3: making the twill", file=sys.stderr)
        made = timed([bin_dir / "vdb_make_medium", "twill", "--layers", "4", "--seed", "1", "--res", n, "-o", medium])
        row = {"res": n, "file_gb": medium.stat().st_size / 1e9, "make": made}
        print(f"bench-scale: {n}^3: downsampling", file=sys.stderr)
        if n <= args.whole_max:
            row["downsample_in_core"] = timed([bin_dir / "vdb_sggx_downsample", "-f", "2", "--in-core", medium, scratch])
        row["downsample_slabs"] = timed([bin_dir / "vdb_sggx_downsample", "-f", "2", "--report", report, medium, scratch])
        row["active_voxels"] = json.loads(report.read_text())["input"]["active_voxels"]
        if n <= args.whole_max:
            subprocess.run([vdb_lod, medium, density, "-range", "0", "-name", "density"], check=True,
                           stdout=subprocess.DEVNULL)
            row["vdb_lod_density"] = timed([vdb_lod, density, scratch, "-range", "1"])
        lobes = [bin_dir / "vdb_lobe_cluster", "--factor", "4", "--lobes", "2", "--clusters", "2"]
        if n <= args.lobe_whole_max:
            print(f"bench-scale: {n}^3: lobes, whole", file=sys.stderr)
            row["lobe_cluster_in_core"] = timed(lobes + ["--in-core", medium, scratch])
        if n <= args.lobe_max:
            print(f"bench-scale: {n}^3: lobes, in slabs", file=sys.stderr)
            row["lobe_cluster_slabs"] = timed(lobes + [medium, scratch])
        render = [bin_dir / "vdb_render"]
        if n <= args.render_max:
            print(f"bench-scale: {n}^3: rendering", file=sys.stderr)
            row["render"] = timed(render + [medium, "-o", work / "render.exr", "--res", "64x64", "--spp", "1"])
        if n <= args.whole_max:
            row["render_full"] = timed(render + [medium, "-o", work / "render.exr", "--res", "64x64", "--spp", "1",
                                                 "--full-precision"])
            row["agreement"] = form_agreement(render, medium, work)
        if not rows and n <= min(args.render_max, args.whole_max):  # the smallest size, if both forms fit
            row["render_speed"] = render_speed(render, medium, work)
        rows.append(row)
        for path in (scratch, report, density, work / "render.exr", work / "speed.exr", work / "speed.json") + (
                () if args.keep else (medium,)):
            if path.exists():
                path.unlink()

    columns = [("make", "vdb_make_medium"), ("downsample_in_core", "downsample -f 2, whole (--in-core)"),
               ("downsample_slabs", "downsample -f 2, in slabs"), ("vdb_lod_density", "vdb_lod -range 1, density"),
               ("lobe_cluster_in_core", "vdb_lobe_cluster -f 4, whole (--in-core)"),
               ("lobe_cluster_slabs", "vdb_lobe_cluster -f 4, in slabs"), ("render", "vdb_render 64x64, 1 spp (compact)"),
               ("render_full", "vdb_render 64x64, 1 spp (--full-precision)")]
    lines = [f"# Time and peak memory against active voxels ({os.cpu_count()} cores; `/usr/bin/time -v`)\n",
             "Twill `vdb_make_medium twill --layers 4 --seed 1 --res N`. Each cell: wall seconds, peak resident GB.\n",
             "| N | active voxels | file GB | " + " | ".join(title for _, title in columns) + " |",
             "|---:|---:|---:|" + "---:|" * len(columns)]
    for r in rows:
        cells = [f"{r[k][0]:.1f} s, {r[k][1]:.2f} GB" if k in r else "-" for k, _ in columns]
        lines.append(f"| {r['res']} | {r['active_voxels'] / 1e6:.1f} M | {r['file_gb']:.2f} | " + " | ".join(cells) + " |")
    biggest = max(r["active_voxels"] for r in rows) if rows else 0
    missing = [] if biggest >= 1e9 else ["a medium of 10^9 active voxels (give --sizes ...,1792; see --help)"]
    lines += ["", "Not measured: " + "; ".join(missing + [
        f"the whole reads above {args.whole_max}^3 (the in-core downsample and vdb_lod: over this machine's memory)",
        f"vdb_lobe_cluster above {args.lobe_max}^3 in slabs and {args.lobe_whole_max}^3 whole",
        f"vdb_render's compact form above {args.render_max}^3 and its float grids above {args.whole_max}^3"]) + ".",
        "",
              "![time and memory](scale.png)"]
    lines += checks(rows)
    (out / "scale.md").write_text("\n".join(lines) + "\n")
    (out / "scale.json").write_text(json.dumps(rows, indent=2) + "\n")
    run_plot_script("plot_scale.py", [out / "scale.json", out / "scale.png"])
    print(f"bench-scale: wrote {out / 'scale.md'}", file=sys.stderr)


if __name__ == "__main__":
    main()
