#!/usr/bin/env python3
"""vdb_render speed: paths per second and time to a fixed relative noise, on the twill (coloured, and
all white), the cloud, a thin HG sphere under a sky and a sun, and the cloud over a ground plane under
a point light, side by side with Blender Cycles' CPU path tracer on the same VDB and scene.

Noise is measured the same way for both renderers: two renders with different seeds, A and B;
the per-pixel noise of one render is RMS(A - B) / sqrt(2), relative to the image mean. Noise falls
as 1/sqrt(spp), so the time to reach a relative noise EPS is  t(spp) * (noise / EPS)^2.
vdb_render's time is its whole process (start-up, reading the medium, writing the image: what a
user waits for, issue 19); its render time alone is reported beside it. Cycles' time excludes its
scene sync: it is rendered at two sample counts and the per-sample time is their difference.

Blender (Debian's blender 3.4) and python3-openvdb are installed with apt when missing and
--no-blender is not given; they are never build or test dependencies.
Cycles interpolates the albedo grid on its own, which mixes the empty voxels' albedo into a fibre's edge,
and it samples Vec3 grids at other points than float grids; vdb_render weights albedo by density. So
Cycles gets premultiplied float grids sigma_s_r, _g, _b = rho * albedo (scripts/premultiply_albedo.py)
and uses sigma_s / rho as albedo: the same medium. On the coloured twill it also renders the albedo grid
as given, for reference. vdb_render also renders each medium with --strategy mis (--before), the
estimator of lights before issue 19's changes, so that the gain of the default shows in the same run.
Results: bench-out/render_report.md and .json.
Usage: scripts/bench_render.py [--build build] [--out bench-out] [--spp 32] [--blender-spp 16]
       [--eps 0.02] [--res 256] [--no-blender] [--media twill,twill-white,cloud,thin,point-ground]
       [--before mis|none] [--step-rate 1.0]
"""
import argparse
import json
import math
import os
import pathlib
import shutil
import subprocess
import sys
import time

from debian_packages import apt_install, ensure_blender

SCENE = ["--env", "0.3", "--sun", "1,0.6,-1.2,3"]
THIN_SCENE = ["--env", "1", "--sun", "0.51,0.65,-0.565,3"]   # issue 19's thin sphere: a sky of 1 and a sun
POINT_SCENE = ["--env", "0.1", "--point-light", "1.2,-1.5,1.6,20"]  # irradiance about 3 at the cloud
SCENES = {"thin": THIN_SCENE, "point-ground": POINT_SCENE}
GROUND = {"point-ground"}  # media rendered over vdb_render's --ground (albedo 0.5 at the bottom of the bounds)
MEDIA = {
    # name: (vdb_make_medium arguments, view, vdb_render flags for the shared scene, note)
    "twill": (["twill", "--res", "256"], "+z", ["--no-sggx"],
              "Cycles has no SGGX: both render the twill's density with S = I (vdb_render --no-sggx), "
              "isotropic; the row 'vdb_render SGGX' is the real medium, for reference. 'albedo grid as given': "
              "Cycles interpolating the albedo grid itself, a different medium at fibre edges"),
    "twill-white": (["twill", "--res", "256", "--warp-albedo", "1", "--weft-albedo", "1"], "+z", ["--no-sggx"],
                    "the twill with white yarns (per-fibre albedo 0.92 to 1): many more scattering events"),
    "cloud": (["cloud", "--res", "256"], "-y", [], "HG g = 0.9, albedo 0.98: the same scene in both renderers"),
    "thin": (["sphere", "--res", "64", "--density", "1", "--variation", "0.99", "--phase", "hg", "--g", "0.5",
              "--albedo", "0.9", "--size", "2"], "-y", [],
             "a thin heterogeneous sphere (optical depth of a few units, HG g = 0.5, albedo 0.9) under a sky of 1 "
             "and a sun of 3: few collisions, light that arrives after one bounce"),
    "point-ground": (["cloud", "--res", "128"], "-y", ["--ground"],
                     "the cloud (128^3) over a diffuse ground (albedo 0.5) under a point light of intensity 20 "
                     "and a sky of 0.1: shadows on the ground, light from a point"),
}


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, text=True, capture_output=True, **kw)


def ensure_pyopenvdb():
    """Debian's python3-openvdb, for scripts/premultiply_albedo.py (benchmark only)."""
    if subprocess.run(["/usr/bin/python3", "-c", "import pyopenvdb, numpy"], capture_output=True).returncode != 0:
        apt_install(["python3-openvdb", "python3-numpy"], "benchmark only")
    return True


def cycles_medium(vdb, out, name):
    """The medium as Cycles gets it: with premultiplied grids sigma_s_r, _g, _b, so that Cycles interpolates
    density-weighted albedo as vdb_render does (scripts/premultiply_albedo.py)."""
    dst = out / f"{name}_256_cycles.vdb"
    if not dst.exists():
        run(["/usr/bin/python3", str(pathlib.Path(__file__).with_name("premultiply_albedo.py")), str(vdb), str(dst)])
    return dst


def compare(bin_dir, a, b):
    out = run([str(bin_dir / "vdb_image_compare"), str(a), str(b), "--report", "-"]).stdout
    return json.loads(out)


def noise_of(bin_dir, a, b):
    c = compare(bin_dir, a, b)
    mean = (c["mean_reference"] + c["mean_test"]) / 2
    return c["rmse"] / math.sqrt(2) / mean, mean


def bench_vdb_render(bin_dir, out, name, vdb, view, flags, label, args):
    reports, whole = [], []
    for seed in (1, 2):
        exr = out / f"{name}_{label}_{seed}.exr"
        start = time.monotonic()
        run([str(bin_dir / "vdb_render"), str(vdb), "-o", str(exr), "--view", view, "--res", f"{args.res}",
             "--spp", str(args.spp), "--seed", str(seed), "--interp", "trilinear", "--report", str(exr) + ".json"]
            + flags + SCENES.get(name, SCENE))
        whole.append(time.monotonic() - start)
        reports.append(json.loads(pathlib.Path(str(exr) + ".json").read_text()))
    noise, mean = noise_of(bin_dir, out / f"{name}_{label}_1.exr", out / f"{name}_{label}_2.exr")
    seconds = sum(whole) / 2
    return {"renderer": "vdb_render" + label[len("vdb_render"):].replace("_", " "), "spp": args.spp, "seconds": seconds,
            "render_seconds": sum(r["seconds"] for r in reports) / 2, "paths_per_second":
            sum(r["paths_per_second"] for r in reports) / 2, "relative_noise": noise, "mean": mean,
            "time_to_eps": seconds * (noise / args.eps) ** 2, "camera": reports[0]["camera"],
            "bounds": reports[0]["bounds"], "scattering_events": reports[0]["mean_scattering_events"]}


def ground_plane(bounds):
    """vdb_render's --ground as a square for Cycles (render/scene_description.cpp, groundPlane)."""
    lo, hi = bounds
    extent = math.dist(lo, hi)
    return [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2], 100 * max(1.0, extent)]


def bench_cycles(bin_dir, out, name, vdb, vdb_render_row, args, label="cycles", note=""):
    camera = vdb_render_row["camera"]
    extra = SCENES.get(name, SCENE)
    if name in GROUND:
        extra = extra + ["--ground-plane", ",".join(map(str, ground_plane(vdb_render_row["bounds"])))]
    script = pathlib.Path(__file__).with_name("blender_scene.py")

    def render(spp, seed, exr):
        cmd = ["blender", "-b", "-noaudio", "--factory-startup", "--python-exit-code", "1", "-P", str(script), "--",
               "--vdb", str(vdb), "--out", str(exr), "--res", str(args.res), "--spp", str(spp), "--seed", str(seed),
               "--camera-pos", ",".join(map(str, camera["position"])),
               "--camera-target", ",".join(map(str, camera["target"])),
               "--camera-up", ",".join(map(str, camera["up"])), "--fov", str(camera["fov"]),
               "--threads", str(os.cpu_count()), "--openvdb-voxel-centres", "--force",
               "--step-rate", str(args.step_rate)] + extra
        lines = run(cmd).stdout.splitlines()
        return json.loads(next(line for line in lines if line.startswith("{")))

    small = max(1, args.blender_spp // 8)
    r1 = render(args.blender_spp, 1, out / f"{name}_{label}_1.exr")
    r2 = render(args.blender_spp, 2, out / f"{name}_{label}_2.exr")
    r0 = render(small, 3, out / f"{name}_{label}_small.exr")
    wall = (r1["seconds"] + r2["seconds"]) / 2
    per_sample = (wall - r0["seconds"]) / (args.blender_spp - small)
    seconds = per_sample * args.blender_spp  # path tracing only, sync excluded
    noise, mean = noise_of(bin_dir, out / f"{name}_{label}_1.exr", out / f"{name}_{label}_2.exr")
    agreement = image_agreement([out / f"{name}_vdb_render_{s}.exr" for s in (1, 2)] +
                                [out / f"{name}_{label}_{s}.exr" for s in (1, 2)])
    pixels = args.res * args.res
    return {"renderer": "Cycles " + r1["blender"] + note, "spp": args.blender_spp, "seconds": seconds, "wall_seconds": wall,
            "paths_per_second": pixels * args.blender_spp / seconds, "relative_noise": noise, "mean": mean,
            "time_to_eps": seconds * (noise / args.eps) ** 2, "agreement": agreement}


def image_agreement(exrs):
    """Per-pixel agreement of vdb_render's two renders with Cycles' two (scripts/image_agreement.py)."""
    script = pathlib.Path(__file__).with_name("image_agreement.py")
    lines = run(["blender", "-b", "-noaudio", "--factory-startup", "--python-exit-code", "1", "-P", str(script),
                 "--"] + [str(pathlib.Path(p).resolve()) for p in exrs]).stdout.splitlines()
    return json.loads(next(line for line in lines if line.startswith("{")))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default="build")
    p.add_argument("--out", default="bench-out")
    p.add_argument("--spp", type=int, default=32)
    p.add_argument("--blender-spp", type=int, default=16)
    p.add_argument("--eps", type=float, default=0.02, help="target relative noise per pixel")
    p.add_argument("--res", type=int, default=256)
    p.add_argument("--no-blender", action="store_true")
    p.add_argument("--step-rate", type=float, default=1.0,
                   help="Cycles' volume step rate (blender_scene.py; default 1.0, its own default: one voxel per "
                        "step; smaller is finer ray marching, less of its bias, slower)")
    p.add_argument("--media", default="twill,twill-white,cloud,thin,point-ground")
    p.add_argument("--before", default="mis", help="vdb_render --strategy of a row to compare the default with "
                   "(the estimator before issue 19's changes); 'none' for no such row")
    args = p.parse_args()
    bin_dir = pathlib.Path(args.build) / "bin"
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    blender = not args.no_blender and ensure_blender() and ensure_pyopenvdb()
    results = {}
    for name in args.media.split(","):
        make_args, view, flags, note = MEDIA[name]
        vdb = out / f"{name}_256.vdb"
        if not vdb.exists():
            run([str(bin_dir / "vdb_make_medium")] + make_args + ["-o", str(vdb)])
        print(f"bench: {name}: vdb_render", file=sys.stderr)
        rows = [bench_vdb_render(bin_dir, out, name, vdb, view, flags, "vdb_render", args)]
        if blender:
            print(f"bench: {name}: Cycles", file=sys.stderr)
            rows.append(bench_cycles(bin_dir, out, name, cycles_medium(vdb, out, name), rows[0], args))
            if name == "twill":  # Cycles' own reading of the albedo grid, for reference: a different medium
                rows.append(bench_cycles(bin_dir, out, name, vdb, rows[0], args, "cycles_plain",
                                         ", albedo grid as given"))
        if args.before != "none":
            print(f"bench: {name}: vdb_render --strategy {args.before}", file=sys.stderr)
            rows.append(bench_vdb_render(bin_dir, out, name, vdb, view, flags + ["--strategy", args.before],
                                         f"vdb_render_--strategy_{args.before}", args))
        if flags and name == "twill":
            rows.append(bench_vdb_render(bin_dir, out, name, vdb, view, [], "vdb_render_SGGX", args))
        results[name] = {"note": note, "rows": rows}

    lines = [f"# vdb_render speed ({args.res}x{args.res}, relative noise target {args.eps:.0%}, "
             f"{os.cpu_count()} cores)\n",
             "| medium | renderer | spp | seconds (vdb_render: whole process; Cycles: path tracing) | paths/s | relative noise | time to target | image mean |",
             "|---|---|---:|---:|---:|---:|---:|---:|"]
    for name, r in results.items():
        for row in r["rows"]:
            lines.append(f"| {name} | {row['renderer']} | {row['spp']} | {row['seconds']:.2f} | "
                         f"{row['paths_per_second']:.3g} | {row['relative_noise']:.3f} | {row['time_to_eps']:.1f} s | "
                         f"{row['mean']:.4f} |")
    lines.append("")
    for name, r in results.items():
        rows = r["rows"]
        lines.append(f"- {name}: {r['note']}.")
        for before in (row for row in rows if "--strategy" in row["renderer"]):
            lines.append(f"  vdb_render against {before['renderer']}: {before['time_to_eps'] / rows[0]['time_to_eps']:.2f}x "
                         f"less time to the same noise, {rows[0]['paths_per_second'] / before['paths_per_second']:.2f}x "
                         f"the paths per second, {before['relative_noise'] ** 2 / rows[0]['relative_noise'] ** 2:.2f}x "
                         f"less variance at the same spp.")
        for cycles in (row for row in rows if row["renderer"].startswith("Cycles")):
            ratio = cycles["time_to_eps"] / rows[0]["time_to_eps"]
            diff = (cycles["mean"] - rows[0]["mean"]) / rows[0]["mean"]
            agree = cycles["agreement"]
            lines.append(f"  {cycles['renderer']} needs {ratio:.2f}x vdb_render's time to the same noise; its image "
                         f"mean is {diff:+.2%} off vdb_render's. Per pixel: sum D^2 / sum var = "
                         f"{agree['variance_ratio']:.3f} (1 if they agree), {agree['tile']}x{agree['tile']} tiles' "
                         f"z mean {agree['tile_z_mean']:+.2f}, rms {agree['tile_z_rms']:.2f}, "
                         f"{agree['tile_z_over_4']} of {agree['tiles']} beyond 4.")
    text = "\n".join(lines) + "\n"
    (out / "render_report.md").write_text(text)
    (out / "render_report.json").write_text(json.dumps(results, indent=2))
    print(text)


if __name__ == "__main__":
    main()
