#!/usr/bin/env python3
"""SH light grids (issue 7, dissertation ch. 5), measured: `make lightgrid`.

1. Scaling (Fig. 5.8): build/bin/sh_lightgrid_bench (Google Benchmark). An 8^3 grid is evaluated for
   1, 8, 64 and 512 triangle lights (a rectangle cut into triangles), and 1M points are interpolated
   from it. The baseline, in the same run, is the analytic SH of every light at each point.
2. Interpolation along a line (Fig. 5.4): coefficient (l, m) = (7, 2) under a square light, along x.
   The reference is analytic at 2000 points; the interpolants use 10 grid nodes (Hermite, trilinear,
   Taylor). Points go through vdb_sh_lightgrid --probe-points.
3. Hermite against trilinear and Taylor on an 8^3 grid (Fig. 5.7): coefficient errors at random points
   against the analytic ones, and a diffuse ground lit from the grid against the same lit from a 64^3 grid.
4. Rendering with 512 lights: a diffuse ground, a thick and a thin cloud, under the rectangle cut into 512
   coloured triangles. vdb_render with next-event estimation of every light (a shadow ray per light
   per vertex) is compared with vdb_render --sh-lightgrid (SH, lmax 8; 8 nodes along the cloud's
   longest axis, 16 along the visible ground's; in the clouds shadowed toward the grid's dominant
   direction, and unshadowed), against a reference from next-event estimation at many samples. NEE is also run for the time the grid
   render took (grid evaluation included), and the grid render for the time NEE took (the grid
   evaluated once, for many renders).
5. Adaptive against uniform at equal memory: a square light 0.05 above the box [-1,1]^3, so the
   lighting is steep near the top only. vdb_sh_lightgrid --levels 3 (base 4 nodes) at several
   tolerances against the uniform grids with the cubes of nodes just below and just above; relative
   RMS error of all coefficients at 2000 random points against the analytic values.
Results: lightgrid-out/report.md and report.json, images, lightgrid.png (drawn by
scripts/plot_lightgrid.py with Debian's python3-matplotlib, installed when missing).
Usage: scripts/lightgrid_experiment.py [--build build] [--out lightgrid-out]
"""
import argparse
import json
import pathlib
import random
import subprocess
import time

from debian_packages import run_plot_script

SQUARE = [[-1, -1, 1.5], [1, -1, 1.5], [1, 1, 1.5], [-1, 1, 1.5]]  # counter-clockwise seen from +z: emits up


def run(cmd, **kwargs):
    return subprocess.run([str(c) for c in cmd], check=True, capture_output=True, text=True, **kwargs).stdout


def triangles(n, z=1.5, half=1.0):
    """The square [-half, half]^2 at height z cut into n = 2 k^2 triangles facing down, coloured by position."""
    k = int(round((n / 2) ** 0.5))
    lights = []
    for i in range(k):
        for j in range(k):
            x0, x1 = -half + 2 * half * i / k, -half + 2 * half * (i + 1) / k
            y0, y1 = -half + 2 * half * j / k, -half + 2 * half * (j + 1) / k
            colour = [2 + 2 * i / k, 2.5, 2 + 2 * j / k]
            for tri in ([[x0, y0, z], [x1, y1, z], [x1, y0, z]], [[x0, y0, z], [x0, y1, z], [x1, y1, z]]):
                lights.append({"vertices": tri, "radiance": colour})
    return lights


def scaling(build, out):
    raw = json.loads(run([build / "bin" / "sh_lightgrid_bench", "--benchmark_format=json"]))
    rows = []
    for b in raw["benchmarks"]:
        name = b["name"].split("/")[0].replace("BM_", "")
        rows.append({"benchmark": name, "lights": int(b.get("lights", 0)), "points": int(b.get("points", 0)),
                     "ms": b["real_time"], "nodes": int(b.get("nodes", 0))})
    (out / "bench.json").write_text(json.dumps(raw, indent=2))
    return rows


def line_plot_data(build, out):
    tool = build / "bin" / "vdb_sh_lightgrid"
    lights = out / "square.json"
    lights.write_text(json.dumps({"lights": [{"vertices": SQUARE[::-1], "radiance": 1}]}))
    xs = [-2 + 4 * i / 1999 for i in range(2000)]
    points = out / "line_points.txt"
    points.write_text("".join(f"{x} 0.3 0\n" for x in xs))
    index = 7 * 8 + 2  # (l, m) = (7, 2)

    def probe(*args):
        return [json.loads(line)["coeffs"][index][0] for line in run([tool, *args, "--probe-points", points]).splitlines()]

    grid = out / "line_grid.vdb"
    run([tool, "--lights", lights, "--bbox", "-2,0.3,0,2,0.3,0", "--res", "10", "-o", grid])
    data = {"x": xs, "analytic": probe("--lights", lights)}
    for method in ["hermite", "trilinear", "taylor"]:
        data[method] = probe("--grid", grid, "--interp", method)
    data["nodes"] = [-2 + 4 * i / 9 for i in range(10)]
    data["errors"] = {m: max(abs(a - b) for a, b in zip(data["analytic"], data[m])) for m in ["hermite", "trilinear", "taylor"]}
    (out / "line.json").write_text(json.dumps(data))
    return {"max_abs_error": data["errors"], "max_abs_value": max(abs(v) for v in data["analytic"])}


def interpolation_accuracy(build, out):
    """Fig. 5.7: one rectangular light over a diffuse ground, an 8^3 grid, three interpolants."""
    tool = build / "bin" / "vdb_sh_lightgrid"
    lights = out / "square_down.json"
    lights.write_text(json.dumps({"lights": [{"vertices": SQUARE[::-1], "radiance": 4}]}))
    box = "-2,-2,-2.6,2,2,1.4"  # 8^3 nodes, the top 0.1 below the light: no cell straddles its plane
    rng = random.Random(5)
    points = out / "ground_points.txt"
    points.write_text("".join(f"{rng.uniform(-2, 2)} {rng.uniform(-2, 2)} {rng.uniform(0, 1)}\n" for _ in range(2000)))
    exact = probe_coeffs(tool, points, "--lights", lights)
    grid8, fine = out / "square_grid8.vdb", out / "square_grid64.vdb"
    run([tool, "--lights", lights, "--bbox", box, "--res", "8", "-o", grid8])
    run([tool, "--lights", lights, "--bbox", box, "--res", "64", "-o", fine])
    scene = out / "square_ground_scene.json"
    scene.write_text(json.dumps({"lights": [{"type": "polygon", "vertices": SQUARE[::-1], "radiance": 4}],
                                 "ground": {"height": 0, "albedo": 0.5}, "camera": {"position": [0, -5, 3], "target": [0, 0, 0]}}))
    common = [build / "bin" / "vdb_render", "--scene", scene, "--res", "160", "--spp", "16", "--seed", "1"]
    reference = out / "square_ground_grid64.exr"
    run([*common, "--sh-lightgrid", fine, "-o", reference])
    rows = {}
    for method in ["hermite", "trilinear", "taylor"]:
        image = out / f"square_ground_grid8_{method}.exr"
        run([*common, "--sh-lightgrid", grid8, "--sh-interp", method, "-o", image])
        c = json.loads(run([build / "bin" / "vdb_image_compare", reference, image, "--error-map", out / f"square_ground_{method}_error.png",
                            "--report", "-"]))
        rows[method] = {"coeff_relative_rms": relative_rms(probe_coeffs(tool, points, "--grid", grid8, "--interp", method), exact),
                        "image_relative_rmse": c["relative_rmse"], "image_mean_relative_error": c["mean_relative_error"]}
    return rows


def render_report(build, args):
    return json.loads(run([build / "bin" / "vdb_render", *args, "--report", "-"]))


def compare(build, reference, image, *flags):
    return json.loads(run([build / "bin" / "vdb_image_compare", reference, image, *flags, "--report", "-"]))


def rendering(build, out, ref_spp, spp):
    scene_lights = [{"type": "polygon", **light} for light in triangles(512)]
    # Isotropic scattering: a peaked phase function would pick up the ringing of the lmax 8 lighting.
    # A thick cloud, where the grid's missing shadows show, and a thin one, where they hardly matter.
    clouds = {"cloud": 1, "thin_cloud": 0.1}
    for name, density in clouds.items():
        run([build / "bin" / "vdb_make_medium", "cloud", "--res", "64", "--albedo", "0.9", "--density", density, "--g", "0",
             "-o", out / f"{name}.vdb"])
    # (scene, grid box, grid nodes along its longest axis, image resolution, reference spp, spp):
    # next-event estimation of 512 lights costs 512 shadow rays per vertex, tracked through the medium
    # in the clouds. The clouds' grids cover the medium (vdb_sh_lightgrid --scene); the ground's covers
    # the ground the camera sees, up to the lights (outside its box vdb_render would sample the lights).
    scenes = {"ground": ({"lights": scene_lights, "ground": {"height": 0, "albedo": 0.5},
                          "camera": {"position": [0, -5, 3], "target": [0, 0, 0]}}, "-5,-3,0,5,6,1.4", 16, 96, ref_spp, spp)}
    for name in clouds:
        scenes[name] = ({"medium": str((out / f"{name}.vdb").resolve()), "lights": scene_lights,
                         "camera": {"position": [0, -4, 1], "target": [0, 0, 0]}}, None, 8, 64, ref_spp, spp)
    results = {}
    for name, (scene, bbox, nodes, res, ref_spp, spp) in scenes.items():
        scene_file = out / f"{name}_scene.json"
        scene_file.write_text(json.dumps(scene))
        common = ["--scene", scene_file, "--res", res, "--seed"]
        reference = out / f"{name}_reference.exr"
        ref = render_report(build, [*common, "1", "--spp", ref_spp, "-o", reference])
        grid = out / f"{name}_grid.vdb"
        start = time.perf_counter()
        box = ["--bbox", bbox] if bbox else []
        run([build / "bin" / "vdb_sh_lightgrid", "--scene", scene_file, *box, "--res", nodes, "-o", grid])
        grid_seconds = time.perf_counter() - start
        row = {"reference": {"spp": ref_spp, "seconds": ref["seconds"]}, "grid_seconds": grid_seconds, "grid_nodes_longest_axis": nodes,
               "grid_box": bbox or "the medium's bounds"}
        variants = {"sh_hermite": ["--sh-lightgrid", grid], "sh_trilinear": ["--sh-lightgrid", grid, "--sh-interp", "trilinear"],
                    "nee": []}
        if bbox is None:  # a medium: shadows toward the dominant direction matter
            variants["sh_unshadowed"] = ["--sh-lightgrid", grid, "--sh-unshadowed"]
        for label, extra in variants.items():
            image = out / f"{name}_{label}.exr"
            r = render_report(build, [*common, "2", "--spp", spp, "-o", image, *extra])
            c = compare(build, reference, image)
            row[label] = {"spp": spp, "seconds": r["seconds"], "relative_rmse": c["relative_rmse"],
                          "tile_relative_rmse": compare(build, reference, image, "--tile", "4")["relative_rmse"],
                          "mean_relative_error": c["mean_relative_error"]}
        budget = row["sh_hermite"]["seconds"] + grid_seconds
        image = out / f"{name}_nee_equal_time.exr"
        r = render_report(build, [*common, "3", "--spp", "100000", "--time", f"{budget:.3f}", "-o", image])
        c = compare(build, reference, image)
        row["nee_equal_time"] = {"spp": r["spp"], "seconds": r["seconds"], "relative_rmse": c["relative_rmse"],
                                 "tile_relative_rmse": compare(build, reference, image, "--tile", "4")["relative_rmse"],
                                 "mean_relative_error": c["mean_relative_error"]}
        image = out / f"{name}_sh_equal_time.exr"
        r = render_report(build, [*common, "5", "--spp", "100000", "--time", f"{row['nee']['seconds']:.3f}", "-o", image,
                                  "--sh-lightgrid", grid])
        c = compare(build, reference, image)
        row["sh_equal_time"] = {"spp": r["spp"], "seconds": r["seconds"], "relative_rmse": c["relative_rmse"],
                                "tile_relative_rmse": compare(build, reference, image, "--tile", "4")["relative_rmse"],
                                "mean_relative_error": c["mean_relative_error"]}
        noise = out / f"{name}_reference_seed4.exr"
        render_report(build, [*common, "4", "--spp", ref_spp, "-o", noise])
        row["noise_floor"] = {"relative_rmse": compare(build, reference, noise)["relative_rmse"],
                              "tile_relative_rmse": compare(build, reference, noise, "--tile", "4")["relative_rmse"]}
        results[name] = row
    return results


def probe_coeffs(tool, points, *args):
    """The RGB coefficients at every point of a points file (vdb_sh_lightgrid --probe-points)."""
    return [json.loads(line)["coeffs"] for line in run([tool, *args, "--probe-points", points]).splitlines()]


def relative_rms(values, exact):
    """RMS difference of all coefficients of all points, relative to the RMS of the exact ones."""
    norm = sum(c * c for point in exact for rgb in point for c in rgb)
    return (sum((a - b) ** 2 for p, q in zip(values, exact) for u, v in zip(p, q) for a, b in zip(u, v)) / norm) ** 0.5


def adaptive_vs_uniform(build, out):
    tool = build / "bin" / "vdb_sh_lightgrid"
    lights = out / "near.json"
    lights.write_text(json.dumps({"lights": [{"vertices": [[-0.5, -0.5, 1.05], [-0.5, 0.5, 1.05], [0.5, 0.5, 1.05], [0.5, -0.5, 1.05]]}]}))
    rng = random.Random(11)
    points = out / "random_points.txt"
    points.write_text("".join(f"{rng.uniform(-1, 1)} {rng.uniform(-1, 1)} {rng.uniform(-1, 1)}\n" for _ in range(2000)))

    def coeffs(*args):
        return probe_coeffs(tool, points, *args)

    exact = coeffs("--lights", lights)

    def error(values):
        return relative_rms(values, exact)

    def uniform_error(res):
        uniform = out / f"uniform_{res}.vdb"
        run([tool, "--lights", lights, "--bbox", "-1,-1,-1,1,1,1", "--res", res, "-o", uniform])
        return error(coeffs("--grid", uniform))

    rows = []
    for tolerance in [0.2, 0.1, 0.05, 0.02, 0.01]:
        grid, report = out / f"adaptive_{tolerance}.vdb", out / f"adaptive_{tolerance}.json"
        run([tool, "--lights", lights, "--bbox", "-1,-1,-1,1,1,1", "--res", "4", "--levels", "3", "--tolerance", tolerance,
             "-o", grid, "--report", report])
        nodes = json.loads(report.read_text())["nodes"]
        res = 2
        while res ** 3 < nodes:
            res += 1
        rows.append({"tolerance": tolerance, "adaptive_nodes": nodes, "adaptive_error": error(coeffs("--grid", grid)),
                     "below_nodes": (res - 1) ** 3, "below_error": uniform_error(res - 1),
                     "above_nodes": res ** 3, "above_error": uniform_error(res)})
    return rows


def markdown(report):
    lines = ["# SH light grids: measurements (`make lightgrid`)", "", "## 1. Scaling (8^3 grid, lmax 8; Google Benchmark)", "",
             "| lights | evaluate the grid (ms) | interpolate 1M points, Hermite (ms) | trilinear (ms) | analytic, per point (ms) |",
             "|---|---|---|---|---|"]
    by = {}
    for r in report["scaling"]:
        if r["benchmark"] != "ZonalFactorisation":
            by.setdefault(r["lights"], {})[r["benchmark"]] = r
    def cell(b, name, spec):
        return format(b[name]["ms"], spec) if name in b else "-"
    for lights in sorted(by):
        b = by[lights]
        per_point = format(b["AnalyticPerPoint"]["ms"] / b["AnalyticPerPoint"]["points"], ".4f") if "AnalyticPerPoint" in b else "-"
        lines.append(f"| {lights} | {cell(b, 'EvaluateGrid', '.1f')} | {cell(b, 'InterpolateHermite', '.0f')} | "
                     f"{cell(b, 'InterpolateTrilinear', '.0f')} | {per_point} |")
    zh = [r["ms"] for r in report["scaling"] if r["benchmark"] == "ZonalFactorisation"]
    if zh:
        lines += ["", f"The ZH factorisation's lobe search (once per run, lmax 8): {zh[0]:.1f} ms, not included above."]
    line = report["line"]
    lines += ["", "## 2. Coefficient (7, 2) along a line, 10 nodes (Fig. 5.4)", "",
              f"Largest |error| over 2000 points (largest |value| {line['max_abs_value']:.4f}): " +
              ", ".join(f"{m} {e:.5f}" for m, e in line["max_abs_error"].items()), "",
              "## 3. Hermite, trilinear and Taylor on an 8^3 grid (Fig. 5.7)", "",
              "One square light (2 x 2, radiance 4) 1.5 above a diffuse ground; an 8^3 grid over [-2,2]^2 x [-2.6,1.4]. "
              "Coefficients: relative RMS error of all 81 x 3 at 2000 random points of [-2,2]^2 x [0,1], against the "
              "analytic values. Images (160x160, 16 spp): relative RMSE against the same scene lit from a 64^3 grid.", "",
              "| interpolation | coefficients: rel. RMS error (x Hermite) | image: rel. RMSE (x Hermite) | image: mean error |",
              "|---|---|---|---|"]
    inter = report["interpolation"]
    for method, r in inter.items():
        lines.append(f"| {method} | {r['coeff_relative_rms']:.5f} ({r['coeff_relative_rms'] / inter['hermite']['coeff_relative_rms']:.1f}) | "
                     f"{r['image_relative_rmse']:.5f} ({r['image_relative_rmse'] / inter['hermite']['image_relative_rmse']:.1f}) | "
                     f"{r['image_mean_relative_error']:+.5f} |")
    lines += ["", "## 4. Rendering with 512 lights (ground 96x96, clouds 64x64: density 1 and 0.1, isotropic, albedo 0.9)", "",
              "Errors against the reference: per pixel, and on 4x4-pixel tile means (less Monte Carlo noise). The noise "
              "floor is a second reference with another seed.", "",
              "| scene | method | spp | seconds | rel. RMSE | rel. RMSE, tiles | mean error |", "|---|---|---|---|---|---|---|"]
    for name, row in report["rendering"].items():
        lines.append(f"| {name} | reference: NEE of every light | {row['reference']['spp']} | {row['reference']['seconds']:.1f} | - | - | - |")
        noise = row["noise_floor"]
        lines.append(f"| {name} | (noise floor: the reference again, another seed) | {row['reference']['spp']} | - | "
                     f"{noise['relative_rmse']:.4f} | {noise['tile_relative_rmse']:.4f} | - |")
        for label, title in [("nee", "NEE of every light"), ("sh_hermite", "SH grid, Hermite"), ("sh_unshadowed", "SH grid, Hermite, unshadowed"),
                             ("sh_trilinear", "SH grid, trilinear"), ("nee_equal_time", "NEE, same time as SH (grid included)"),
                             ("sh_equal_time", "SH grid, Hermite, same time as NEE (grid excluded: evaluated once)")]:
            if label not in row:
                continue
            r = row[label]
            lines.append(f"| {name} | {title} | {r['spp']} | {r['seconds']:.2f} | {r['relative_rmse']:.4f} | "
                         f"{r['tile_relative_rmse']:.4f} | {r['mean_relative_error']:+.4f} |")
        lines.append(f"| {name} | (grid evaluation, 512 lights; {row['grid_nodes_longest_axis']} nodes along the longest axis of "
                     f"{row['grid_box']}) | - | {row['grid_seconds']:.2f} | - | - | - |")
    lines += ["", "## 5. Adaptive against uniform at equal memory (square light 0.05 above the box; 2000 points)", "",
              "| tolerance | adaptive: nodes, rel. RMS error | uniform below: nodes, error (ratio) | uniform above: nodes, error (ratio) |",
              "|---|---|---|---|"]
    for r in report["adaptive"]:
        a = r["adaptive_error"]
        lines.append(f"| {r['tolerance']} | {r['adaptive_nodes']}, {a:.4f} | {r['below_nodes']}, {r['below_error']:.4f} "
                     f"({r['below_error'] / a:.2f}) | {r['above_nodes']}, {r['above_error']:.4f} ({r['above_error'] / a:.2f}) |")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="lightgrid-out")
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--ref-spp", type=int, default=256)
    args = parser.parse_args()
    build, out = pathlib.Path(args.build), pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    report = {"scaling": scaling(build, out), "line": line_plot_data(build, out), "interpolation": interpolation_accuracy(build, out),
              "rendering": rendering(build, out, args.ref_spp, args.spp), "adaptive": adaptive_vs_uniform(build, out)}
    (out / "report.json").write_text(json.dumps(report, indent=2))
    run_plot_script("plot_lightgrid.py", [out / "report.json", out / "line.json", out / "lightgrid.png"])
    (out / "report.md").write_text(markdown(report) + "\n![plots](lightgrid.png)\n")
    print((out / "report.md").read_text())


if __name__ == "__main__":
    main()
