#!/usr/bin/env python3
"""make interop: the kept foreign files rendered by vdb_render and by Blender Cycles with the same grids,
lights and camera (issue 26). A newcomer's first act, checked: a Blender smoke under the default lights,
a Blender fire by its own light alone and under the default lights (Cycles' Principled Volume blackbody
against the tools' Blender preset), and a Houdini-convention smoke coloured by its `Cd`.

For each case:
  1. `vdb_info --json FILE` suggests a vdb_render command that frames the medium; its camera is used;
  2. vdb_render renders FILE as any tool reads it (the preset detected from its grids), with
     --interp trilinear (Cycles interpolates trilinearly) and the case's lights;
  3. scripts/blender_scene.py renders the same file in Cycles with vdb_render's camera (from its JSON
     report), the same lights, and the grids the preset read: for a fire, Principled Volume's blackbody
     of `temperature` at 1000 K per unit and intensity 1 (Quick Smoke's fire material); for a `Cd`, the
     premultiplied grids of scripts/premultiply_albedo.py, so that both renderers weight the colour by
     density (vdb_render's trilinear albedo);
  4. vdb_image_compare gives the relative error of the image mean and, over 8 x 8 tiles, the worst
     tile's error relative to that tile (to the image mean where the tile is darker than the mean).
Gates (the issue's): |mean| <= 1.5% and worst 8 x 8 tile <= 5%.

Writes interop-out/report.md with side-by-side images (Cycles | vdb_render | error map, +-10%) and
interop-out/report.json. Needs Debian's blender and, for the Houdini case, python3-openvdb; both are
installed with apt when missing. Not part of make test.
Usage: scripts/interop_experiment.py [--build build] [--out interop-out] [--res 128] [--spp 1024]
       [--blender-spp 1024] [--cases blender-smoke,blender-fire,blender-fire-lit,houdini-smoke]
"""
import argparse
import json
import os
import pathlib
import shlex
import subprocess
import sys
import time

from debian_packages import apt_install, ensure_blender

ROOT = pathlib.Path(__file__).resolve().parent.parent
FIRE = ["--blackbody", "temperature:1000:1"]  # Quick Smoke's fire material: Principled Volume, 1000 K, intensity 1
CASES = {
    # name: (file, lights for both renderers, Cycles-only flags, premultiply this colour grid, what it shows)
    "blender-smoke": ("grids/blender/smoke24.vdb", [], [], None,
                      "Mantaflow smoke, albedo 1, under vdb_render's default lights (a dim sky and a sun)"),
    "blender-fire": ("grids/blender/fire24.vdb", ["--env", "0"], FIRE, None,
                     "Mantaflow fire by its own light alone: Cycles' blackbody of `temperature` against the "
                     "Blender preset's blackbody_temperature"),
    "blender-fire-lit": ("grids/blender/fire24.vdb", [], FIRE, None,
                         "the same fire under the default lights: its light, and the light its smoke scatters"),
    "houdini-smoke": ("grids/houdini/pyro24.vdb", [], [], "Cd",
                      "Houdini's names: `Cd` read as the albedo by the Houdini preset, fire grids not read "
                      "(Houdini's pyro shaders use ramps a file does not carry)"),
}
MEAN_GATE, TILE_GATE, TILE = 0.015, 0.05, 8


def run(cmd):
    return subprocess.run([str(c) for c in cmd], check=True, text=True, capture_output=True)


def blender(script, args):
    out = run(["blender", "-b", "-noaudio", "--factory-startup", "--python-exit-code", "1", "-P",
               ROOT / "scripts" / script, "--"] + args).stdout
    return json.loads(next(line for line in out.splitlines() if line.startswith("{")))


def suggested_camera(bin_dir, vdb):
    """The camera flags of the vdb_render command vdb_info suggests (its other flags are the case's)."""
    info = json.loads(run([bin_dir / "vdb_info", vdb, "--json"]).stdout)
    words = shlex.split(info["render_command"])
    flags = []
    for i, word in enumerate(words):
        if word in ("--camera", "--look-at", "--up", "--fov", "--view"):
            flags += [word, words[i + 1]]
    return flags


def render_vdb(bin_dir, out, name, vdb, lights, args):
    exr = out / f"{name}_vdb_render.exr"
    start = time.monotonic()
    run([bin_dir / "vdb_render", vdb, "-o", exr, "--res", str(args.res), "--spp", str(args.spp), "--seed", "1",
         "--interp", "trilinear", "--report", f"{exr}.json"] + suggested_camera(bin_dir, vdb) + lights)
    report = json.loads(pathlib.Path(f"{exr}.json").read_text())
    return exr, report, time.monotonic() - start


def cycles_file(out, name, vdb, colour):
    if colour is None:
        return vdb
    if subprocess.run(["/usr/bin/python3", "-c", "import pyopenvdb, numpy"], capture_output=True).returncode != 0:
        apt_install(["python3-openvdb", "python3-numpy"], "make interop only")
    dst = out / f"{name}_cycles.vdb"
    run(["/usr/bin/python3", ROOT / "scripts" / "premultiply_albedo.py", vdb, dst, "--albedo", colour])
    return dst


def render_cycles(out, name, vdb, camera, lights, extra, args):
    exr = out / f"{name}_cycles.exr"
    r = blender("blender_scene.py", [
        "--vdb", vdb, "--out", exr, "--res", str(args.res), "--spp", str(args.blender_spp), "--seed", "1",
        "--camera-pos", ",".join(map(str, camera["position"])), "--camera-target", ",".join(map(str, camera["target"])),
        "--camera-up", ",".join(map(str, camera["up"])), "--fov", str(camera["fov"]), "--threads", str(os.cpu_count()),
        "--openvdb-voxel-centres", "--force"] + lights + extra)
    return exr, r


def compare(bin_dir, cycles, vdb_render, side_by_side=None):
    whole = json.loads(run([bin_dir / "vdb_image_compare", cycles, vdb_render, "--report", "-"]).stdout)
    cmd = [bin_dir / "vdb_image_compare", cycles, vdb_render, "--tile", str(TILE), "--report", "-"]
    tiles = json.loads(run(cmd).stdout)
    if side_by_side:
        run([bin_dir / "vdb_image_compare", cycles, vdb_render, "--range", "0.1", "--side-by-side", side_by_side])
    return whole, tiles


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build")
    p.add_argument("--out", default="interop-out")
    p.add_argument("--res", type=int, default=128)
    p.add_argument("--spp", type=int, default=1024, help="vdb_render's samples per pixel")
    p.add_argument("--blender-spp", type=int, default=1024, help="Cycles' samples per pixel")
    p.add_argument("--cases", default=",".join(CASES))
    args = p.parse_args()
    bin_dir = pathlib.Path(args.build).resolve() / "bin"
    out = pathlib.Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    ensure_blender("make interop only")
    rows = []
    for name in args.cases.split(","):
        if name not in CASES:
            sys.exit(f"interop_experiment.py: unknown case '{name}' (cases: {', '.join(CASES)})")
        path, lights, extra, colour, what = CASES[name]
        vdb = ROOT / path
        print(f"interop: {name}: vdb_render", file=sys.stderr)
        ours, report, ours_seconds = render_vdb(bin_dir, out, name, vdb, lights, args)
        print(f"interop: {name}: Cycles", file=sys.stderr)
        theirs, cycles = render_cycles(out, name, cycles_file(out, name, vdb, colour), report["camera"], lights, extra,
                                       args)
        png = out / f"{name}_side_by_side.png"
        whole, tiles = compare(bin_dir, theirs, ours, png)
        rows.append({"case": name, "file": path, "what": what, "vdb_render_flags": lights,
                     "cycles_flags": lights + extra, "mean_cycles": whole["mean_reference"],
                     "mean_vdb_render": whole["mean_test"], "mean_error": whole["mean_relative_error"],
                     "worst_tile_error": tiles["worst_relative_error"], "tile_relative_rmse": tiles["relative_rmse"],
                     "vdb_render_seconds": ours_seconds, "cycles_seconds": cycles["seconds"],
                     "cycles": cycles.get("blender", "?"), "camera": report["camera"], "image": png.name})
        row = rows[-1]
        row["passed"] = abs(row["mean_error"]) <= MEAN_GATE and row["worst_tile_error"] <= TILE_GATE
        print(f"interop: {name}: mean {row['mean_error']:+.2%}, worst {TILE}x{TILE} tile "
              f"{row['worst_tile_error']:.2%}: {'pass' if row['passed'] else 'FAIL'}", file=sys.stderr)

    lines = [f"# vdb_render against Blender Cycles on the kept foreign files\n",
             f"{args.res}x{args.res}; vdb_render {args.spp} spp (`--interp trilinear`), Cycles {args.blender_spp} spp "
             f"(Blender {rows[0]['cycles'] if rows else '?'}, CPU, ray marching at one voxel per step); the camera "
             f"`vdb_info` suggests. Gates: |mean| <= {MEAN_GATE:.1%}, worst {TILE}x{TILE} tile <= {TILE_GATE:.0%} "
             f"(relative to the tile, or to the image mean where the tile is darker).\n",
             "| case | file | lights | Cycles mean | vdb_render mean | mean error | worst 8x8 tile | 8x8 tiles' relative RMSE | gate |",
             "|---|---|---|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        lights = " ".join(r["vdb_render_flags"]) or "default"
        lines.append(f"| {r['case']} | `{r['file']}` | {lights} | {r['mean_cycles']:.5g} | {r['mean_vdb_render']:.5g} | "
                     f"{r['mean_error']:+.2%} | {r['worst_tile_error']:.2%} | {r['tile_relative_rmse']:.2%} | "
                     f"{'pass' if r['passed'] else 'FAIL'} |")
    lines.append("")
    for r in rows:
        lines += [f"## {r['case']}", "", f"{r['what']}. Cycles' flags: `{' '.join(r['cycles_flags']) or '(none)'}`.",
                  "", f"Cycles | vdb_render | error map (blue: vdb_render darker, red: brighter, saturating at 10%)", "",
                  f"![{r['case']}]({r['image']})", ""]
    text = "\n".join(lines) + "\n"
    (out / "report.md").write_text(text)
    (out / "report.json").write_text(json.dumps(rows, indent=2) + "\n")
    print(f"{out / 'report.md'}: {sum(r['passed'] for r in rows)} of {len(rows)} gates pass", file=sys.stderr)


if __name__ == "__main__":
    main()
