#!/usr/bin/env python3
"""Multi-lobe SGGX fits (issue 5, §5 and §8.1 of the downsampling paper), measured: `make lobes`.

1. The error against the lobe count m on the twill and the velvet at (4x)^3 (Fig. 16): the
   vdb_lobe_cluster report of each medium, and a plot (lobe_errors.png, drawn by
   scripts/plot_lobe_errors.py with Debian's python3-matplotlib, installed when missing).
   The velvet is also fitted without its random pile tilt (--tilt 0), which isolates the tilt.
2. The twill rendered by vdb_render at full resolution, naive 4x (1 lobe), 4x with 2 lobes and 4x
   with the lobe-count rule, all with naive lobe weights (Eq. 11), from six cameras under one sky and
   sun. Each is compared with the full-resolution render on 8x8-pixel tile means of the fabric
   (vdb_image_compare --foreground --tile 8); a second full-resolution render with another seed
   gives the noise floor of that comparison.
Results: lobes-out/report.md and report.json, images in lobes-out/.
Usage: scripts/lobe_experiment.py [--build build] [--out lobes-out] [--spp 256] [--res 160x120]
"""
import argparse
import json
import math
import pathlib
import subprocess
import sys

from debian_packages import run_plot_script

SKY = ["--env", "0.25", "--sun", "1,0.6,-1.2,3", "--ground"]
CENTRE = (6.0, 6.0, 0.5)  # the 12 x 12 world-unit twill sheet


def camera(azimuth, elevation, distance=15.0):
    a, e = math.radians(azimuth), math.radians(elevation)
    pos = (CENTRE[0] + distance * math.cos(a) * math.cos(e), CENTRE[1] + distance * math.sin(a) * math.cos(e),
           CENTRE[2] + distance * math.sin(e))
    return ["--camera-pos", ",".join(f"{v:.3f}" for v in pos), "--camera-target", ",".join(map(str, CENTRE)),
            "--fov", "50"]


# The sun travels toward +x +y: azimuth 45 looks back toward it (back-lit), 225 has it behind the camera.
VIEWS = {
    "top": camera(-90, 80),
    "az45-backlit": camera(45, 30),
    "az135": camera(135, 30),
    "az225-frontlit": camera(225, 30),
    "az315": camera(315, 30),
    "az45-grazing": camera(45, 12),
}


def run(cmd):
    return subprocess.run([str(c) for c in cmd], check=True, text=True, capture_output=True)


def lobe_fits(bins, out):
    media = {
        "twill": ["twill", "--yarns", "12", "--res", "384", "--seed", "1"],
        "velvet": ["velvet", "--res", "256", "--seed", "1"],
        "velvet-no-tilt": ["velvet", "--res", "256", "--seed", "1", "--tilt", "0"],
    }
    reports = {}
    for name, args in media.items():
        vdb = out / f"{name}.vdb"
        print(f"lobes: vdb_make_medium {' '.join(args)}", file=sys.stderr)
        run([bins / "vdb_make_medium", *args, "-o", vdb])
        report = out / f"{name}_lobes.json"
        print(f"lobes: vdb_lobe_cluster -f 4 {name}", file=sys.stderr)
        run([bins / "vdb_lobe_cluster", "-f", "4", "--report", report, vdb, out / f"{name}_4x_rule.vdb"])
        reports[name] = json.loads(report.read_text())
    return reports


def plot(reports, out):
    png = out / "lobe_errors.png"
    run_plot_script("plot_lobe_errors.py", [png] + [out / f"{name}_lobes.json" for name in reports])
    return png


def renders(bins, out, spp, res):
    twill = out / "twill.vdb"
    media = {"full": twill, "naive-4x": out / "twill_4x_naive.vdb", "2-lobe-4x": out / "twill_4x_2lobes.vdb",
             "rule-4x": out / "twill_4x_rule.vdb"}
    run([bins / "vdb_sggx_downsample", "-f", "4", "--s-weight", "count", twill, media["naive-4x"]])
    run([bins / "vdb_lobe_cluster", "-f", "4", "--lobes", "2", twill, media["2-lobe-4x"]])
    rows = []
    for view, cam in VIEWS.items():
        exr = {}
        for name, vdb in list(media.items()) + [("full-seed2", twill)]:
            exr[name] = out / f"render_{view}_{name}.exr"
            seed = "2" if name == "full-seed2" else "1"
            print(f"lobes: vdb_render {view} {name}", file=sys.stderr)
            run([bins / "vdb_render", vdb, "-o", exr[name], "--res", res, "--spp", str(spp), "--seed", seed,
                 "--aov", "alpha", *SKY, *cam])
        row = {"view": view}
        for name in ("full-seed2", "naive-4x", "2-lobe-4x", "rule-4x"):
            args = [bins / "vdb_image_compare", exr["full"], exr[name], "--foreground", "--tile", "8", "--report", "-"]
            if name != "full-seed2":
                args[3:3] = ["--side-by-side", out / f"compare_{view}_{name}.png", "--range", "0.25"]
            row[name] = json.loads(run(args).stdout)
        rows.append(row)
    return rows


def markdown(reports, png, rows, spp, res):
    lines = ["# Multi-lobe SGGX fits at (4x)^3 (`make lobes`)", "",
             "## Error against the lobe count (Fig. 16)", "",
             "Relative L2 error of the whole medium: sqrt(sum over voxels of the squared fit error / sum of the "
             "squared norm of the children's mean D). 'chosen' is the share of voxels for which the per-voxel "
             "rule of §8.1 picks m; 'rule on the whole medium' applies the same rule to the medium's errors.", "",
             "| medium | voxels | exact with 1 lobe | m = 1 | m = 2 | m = 3 | chosen 1 / 2 / 3 | rule on the whole medium | voxels/s |",
             "|---|---:|---:|---:|---:|---:|---|---:|---:|"]
    for name, r in reports.items():
        errors = [e["relative_l2_error"] for e in r["error_by_lobes"]]
        chosen = " / ".join(f"{100 * e['voxels_fitted_with'] / r['voxels']:.0f}%" for e in r["error_by_lobes"])
        lines.append(f"| {name} | {r['voxels']} | {r['voxels_exact_with_one_lobe']} | "
                     + " | ".join(f"{e:.4f}" for e in errors) + f" | {chosen} | {r['rule_on_whole_medium']} | "
                     f"{r['voxels_per_second']:.0f} |")
    lines += ["", f"![error against lobe count]({png.name})", "",
              f"## The twill rendered ({res}, {spp} spp, naive lobe weights)", "",
              "Relative RMSE of 8x8-pixel tile means over the fabric against the full-resolution render, and the "
              "mean intensity error. 'noise floor': the full-resolution render with another seed.", "",
              "| view | noise floor | naive 4x (1 lobe) | 2 lobes 4x | rule 4x | mean: naive / 2 lobes / rule |",
              "|---|---:|---:|---:|---:|---|"]
    for row in rows:
        rel = {k: 100 * row[k]["relative_rmse"] for k in ("full-seed2", "naive-4x", "2-lobe-4x", "rule-4x")}
        means = " / ".join(f"{100 * row[k]['mean_relative_error']:+.2f}%" for k in ("naive-4x", "2-lobe-4x", "rule-4x"))
        lines.append(f"| {row['view']} | {rel['full-seed2']:.2f}% | {rel['naive-4x']:.2f}% | {rel['2-lobe-4x']:.2f}% | "
                     f"{rel['rule-4x']:.2f}% | {means} |")
    closer = sum(r["2-lobe-4x"]["relative_rmse"] < r["naive-4x"]["relative_rmse"] for r in rows)
    lines += ["", f"2 lobes closer than naive (tile RMSE) in {closer} of {len(rows)} views."]
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="lobes-out")
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--res", default="160x120")
    args = parser.parse_args()
    bins = pathlib.Path(args.build) / "bin"
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    reports = lobe_fits(bins, out)
    png = plot(reports, out)
    rows = renders(bins, out, args.spp, args.res)
    (out / "report.json").write_text(json.dumps({"fits": reports, "renders": rows}, indent=2))
    text = markdown(reports, png, rows, args.spp, args.res)
    (out / "report.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
