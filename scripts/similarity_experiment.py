#!/usr/bin/env python3
"""High-order similarity relations (issue 6, §8 of the similarity paper), measured: `make similarity`.

1. Speed-up at equal quality (§8.1, Figs. 6, 7, 10): a dense forward-scattering cloud and cube (HG
   g = 0.9, albedo 0.99), altered by vdb_similarity at several alpha. The original rendered with
   --spp N has a relative RMSE e0 against a reference (the original at --ref-spp); each altered
   medium is rendered at N, N/2, ..., N/16 spp, and its time to equal quality is the shortest render
   time whose RMSE (bias included) is <= e0. Also the mean scattering events per path.
2. Order up to 5 against order 1 (Fig. 9, A and B): phase functions of the HG + backward-lobe family
   of Gkioulekas et al. 2013 that the paper samples, all with the first moment f1 = 0.7563:
   A = 0.9 HG(0.9292) + 0.1 vMF(-5), B = 0.9 HG(0.907) + 0.1 HG(-0.6), and two more reported
   alongside, Eq. 33 (0.9 HG(0.95) + 0.1 vMF(-75)) and 0.9 HG(0.8737) + 0.1 HG(-0.3). In a cube of
   100 mean free paths lit from the side, each is altered with the default (distance) order rule,
   with Algorithm 1's support rule (order up to 5), with the order-1 relation only (--max-order 1)
   and with the support threshold off (--support-ratio 0), at the same alpha, and compared with its
   own reference on 4x4-pixel tile means.
3. Throughput: the default rule for single HG phase functions (ms per QP solve), and whole media
   with a continuous per-voxel g (vdb_make_medium cloud --g-edge: two 256^3 clouds of g 0.7 to 0.95,
   a 128^3 cloud of g -0.9 to 0.9) through vdb_similarity with both order rules, in the same run.
Results: similarity-out/report.md and report.json, images and similarity.png (drawn by
scripts/plot_similarity.py with Debian's python3-matplotlib, installed when missing).
Usage: scripts/similarity_experiment.py [--build build] [--out similarity-out] [--spp 64] [--ref-spp 1024]
"""
import argparse
import json
import math
import pathlib
import subprocess
import time

from debian_packages import run_plot_script

ALPHAS = [0.1, 0.2, 0.3, 0.5]
RENDER = ["--res", "64", "--view", "-y", "--sun", "1,0.5,-1,3", "--env", "0.3", "--seed"]
SIDE_LIT = ["--res", "64", "--view", "-y", "--sun", "1,0,-0.3,3", "--env", "0.1", "--seed"]


def run(cmd):
    return subprocess.run([str(c) for c in cmd], check=True, text=True, capture_output=True)


class Tools:
    def __init__(self, build):
        self.bin = pathlib.Path(build) / "bin"

    def __call__(self, tool, *args):
        return run([self.bin / tool, *args])

    def json(self, tool, *args):
        return json.loads(self(tool, *args).stdout)

    def render(self, medium, image, spp, scene, seed):
        return self.json("vdb_render", medium, "-o", image, "--spp", spp, *scene, seed, "--report", "-")

    def compare(self, reference, image, *flags):
        return self.json("vdb_image_compare", reference, image, *flags, "--report", "-")


def hg_bin_averages(g, bins):
    def cdf(mu):  # integral of 2 pi HG over [-1, mu]
        return (1 - g * g) / (2 * g) * (1 / math.sqrt(1 + g * g - 2 * g * mu) - 1 / (1 + g))
    edges = [-1 + 2 * b / bins for b in range(bins + 1)]
    return [(cdf(edges[b + 1]) - cdf(edges[b])) / (2 * math.pi * (edges[b + 1] - edges[b])) for b in range(bins)]


def speedup(tools, out, spp, ref_spp):
    media = {
        "cloud": ["cloud", "--res", "64", "--g", "0.9", "--albedo", "0.99", "--density", "80"],
        "cube": ["cube", "--res", "32", "--phase", "hg", "--g", "0.9", "--albedo", "0.99", "--density", "60"],
    }
    results = {}
    for name, args in media.items():
        original = out / f"{name}.vdb"
        tools("vdb_make_medium", *args, "-o", original)
        reference = out / f"{name}_reference.exr"
        tools.render(original, reference, ref_spp, RENDER, 1)
        base = tools.render(original, out / f"{name}_original.exr", spp, RENDER, 2)
        e0 = tools.compare(reference, out / f"{name}_original.exr")["relative_rmse"]
        rows = [{"alpha": 1.0, "spp": spp, "seconds": base["seconds"], "relative_rmse": e0,
                 "events_per_path": base["mean_scattering_events"], "seconds_to_quality": base["seconds"], "order": None}]
        for alpha in ALPHAS:
            altered = out / f"{name}_alpha{alpha}.vdb"
            report = out / f"{name}_alpha{alpha}.json"
            tools("vdb_similarity", original, altered, "--alpha", alpha, "--report", report)
            order = json.loads(report.read_text())["tables"][0]["order"]
            levels = []
            for s in [spp // k for k in (1, 2, 4, 8, 16) if spp // k >= 1]:
                image = out / f"{name}_alpha{alpha}_{s}spp.exr"
                r = tools.render(altered, image, s, RENDER, 2)
                levels.append({"spp": s, "seconds": r["seconds"], "events": r["mean_scattering_events"],
                               "relative_rmse": tools.compare(reference, image)["relative_rmse"]})
            reached = [level["seconds"] for level in levels if level["relative_rmse"] <= e0]
            full = levels[0]
            rows.append({"alpha": alpha, "order": order, "spp": spp, "seconds": full["seconds"],
                         "relative_rmse": full["relative_rmse"], "events_per_path": full["events"],
                         "seconds_to_quality": min(reached) if reached else None, "levels": levels})
        for row in rows:
            row["events_ratio"] = row["events_per_path"] / rows[0]["events_per_path"]
            row["speedup"] = rows[0]["seconds"] / row["seconds_to_quality"] if row["seconds_to_quality"] else None
        results[name] = rows
    return results


def vmf_bin_averages(kappa, bins):
    edges = [-1 + 2 * b / bins for b in range(bins + 1)]
    scale = kappa / (4 * math.pi * math.sinh(kappa))
    return [scale * (math.exp(kappa * edges[b + 1]) - math.exp(kappa * edges[b])) / kappa / (edges[b + 1] - edges[b])
            for b in range(bins)]


def mixture(*parts):
    """Bin averages of sum w * lobe on n bins; a lobe is ("hg", g) or ("vmf", kappa)."""
    def table(n):
        lobes = [(w, hg_bin_averages(p, n) if kind == "hg" else vmf_bin_averages(p, n)) for w, kind, p in parts]
        return [sum(w * lobe[b] for w, lobe in lobes) for b in range(n)]
    return table


PHASES = {  # equal first moments, f1 = 0.7563
    "A": ("0.9 HG(0.9292) + 0.1 vMF(-5)", mixture((0.9, "hg", 0.9292), (0.1, "vmf", -5))),
    "B": ("0.9 HG(0.907) + 0.1 HG(-0.6)", mixture((0.9, "hg", 0.907), (0.1, "hg", -0.6))),
    "Eq33": ("0.9 HG(0.95) + 0.1 vMF(-75) (Eq. 33)", mixture((0.9, "hg", 0.95), (0.1, "vmf", -75))),
    "C": ("0.9 HG(0.8737) + 0.1 HG(-0.3)", mixture((0.9, "hg", 0.8737), (0.1, "hg", -0.3))),
}
VARIANTS = {"algorithm1": ["--order-rule", "support"], "order1": ["--max-order", "1"],
            "no_threshold": ["--order-rule", "support", "--support-ratio", "0"], "distance": ["--order-rule", "distance"]}


def equal_first_moments(tools, out, ref_spp):
    cube = ["cube", "--res", "32", "--albedo", "0.99", "--density", "100"]
    originals = {}
    for name, (title, table) in PHASES.items():
        originals[name] = table(4096)
        (out / f"phase_{name}.txt").write_text(f"# {title} on 4096 bins of mu\n" + "\n".join(f"{v:.10g}" for v in originals[name]) + "\n")
    phases = {name: ["--phase-table", out / f"phase_{name}.txt"] for name in PHASES}
    results, tables = {}, {}
    for name, phase in phases.items():
        original = out / f"phase{name}.vdb"
        tools("vdb_make_medium", *cube, *phase, "-o", original)
        reference = out / f"phase{name}_reference.exr"
        tools.render(original, reference, ref_spp, SIDE_LIT, 1)
        one = {}
        for label, flags in VARIANTS.items():
            altered = out / f"phase{name}_{label}.vdb"
            report = out / f"phase{name}_{label}.json"
            tools("vdb_similarity", original, altered, "--report", report, *flags)
            table = json.loads(report.read_text())["tables"][0]
            image = out / f"phase{name}_{label}.exr"
            tools.render(altered, image, ref_spp, SIDE_LIT, 2)
            tiles = tools.compare(reference, image, "--tile", "4")
            one[label] = {"order": table["order"], "alpha": table["alpha"], "support": table["support"],
                          "tile_rmse": tiles["relative_rmse"], "mean_relative_error": tiles["mean_relative_error"],
                          "rmse": tools.compare(reference, image)["relative_rmse"]}
        noise = out / f"phase{name}_noise.exr"
        tools.render(original, noise, ref_spp, SIDE_LIT, 3)
        one["noise_floor_tile_rmse"] = tools.compare(reference, noise, "--tile", "4")["relative_rmse"]
        results[name] = one
        single = ["--table", out / f"phase_{name}.txt"]
        tables[name] = {label: tools.json("vdb_similarity", *single, "--json", *flags)
                        for label, flags in VARIANTS.items() if label != "no_threshold"}
    results["A_vs_B_reference_tile_rmse"] = tools.compare(out / "phaseA_reference.exr", out / "phaseB_reference.exr",
                                                          "--tile", "4")["relative_rmse"]
    results["A_vs_B_order1_tile_rmse"] = tools.compare(out / "phaseA_order1.exr", out / "phaseB_order1.exr",
                                                       "--tile", "4")["relative_rmse"]
    results["A_vs_B_algorithm1_tile_rmse"] = tools.compare(out / "phaseA_algorithm1.exr", out / "phaseB_algorithm1.exr",
                                                           "--tile", "4")["relative_rmse"]
    (out / "phase_tables.json").write_text(json.dumps({"originals": originals, "titles": {n: t for n, (t, _) in PHASES.items()}, **tables}))
    return results


def throughput(tools, out):
    solves = []
    for g in [0.5, 0.8, 0.9, 0.95, 0.99]:
        best = None
        for _ in range(5):
            r = tools.json("vdb_similarity", "--hg", g, "--json")
            count = 1 + len(r["rejected"])
            best = min(best or 1e9, r["seconds"] / count)
        solves.append({"g": g, "order": r["order"], "solves": count, "ms_per_solve": 1e3 * best})
    media = []
    clouds = {f"256^3 cloud, coverage {c}, g 0.7 to 0.95": ["--res", "256", "--g", "0.95", "--g-edge", "0.7", "--coverage", c]
              for c in ["0.5", "1"]}
    clouds["128^3 cloud, g -0.9 to 0.9"] = ["--res", "128", "--g", "0.9", "--g-edge", "-0.9"]
    for name, args in clouds.items():
        medium = out / "throughput_cloud.vdb"
        altered = out / "throughput_cloud_altered.vdb"
        tools("vdb_make_medium", "cloud", *args, "-o", medium)
        runs = {"support": [], "distance": []}
        for _ in range(3):  # the order rules alternately, in the same run; medians of 3
            for rule in runs:
                report = out / f"throughput_{rule}.json"
                start = time.monotonic()
                tools("vdb_similarity", medium, altered, "--report", report, "--order-rule", rule)
                wall = time.monotonic() - start
                r = json.loads(report.read_text())
                runs[rule].append({"medium": name, "rule": rule, "voxels": r["voxels"], "tables": len(r["tables"]),
                                   "moment_bound": r["moment_bound"], "max_moment_error": r["max_moment_error"],
                                   "solves": sum(1 + len(t["rejected"]) for t in r["tables"]),
                                   "seconds": r["seconds"], "wall_seconds": wall})
                report.unlink()
        def median(rule, value):
            return sorted(value(row) for row in runs[rule])[1]
        for rule, rows in runs.items():
            row = dict(rows[0])  # the counts are the same in every run; the times are medians
            row["seconds"] = {part: median(rule, lambda r: r["seconds"][part]) for part in ("read", "alter", "write")}
            row["wall_seconds"] = median(rule, lambda r: r["wall_seconds"])
            row["wall_ratio"] = row["wall_seconds"] / median("support", lambda r: r["wall_seconds"])
            row["alter_ratio"] = row["seconds"]["alter"] / median("support", lambda r: r["seconds"]["alter"])
            media.append(row)
        medium.unlink()
        altered.unlink()
    return {"single": solves, "media": media}


def plot(out):
    png = out / "similarity.png"
    run_plot_script("plot_similarity.py", [out / "report.json", out / "phase_tables.json", png])
    return png


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def markdown(report, spp, ref_spp):
    lines = ["# Similarity relations: measurements (`make similarity`)", "",
             f"## 1. Speed-up at equal quality ({spp} spp original against a {ref_spp} spp reference; 64x64)", ""]
    for name, rows in report["speedup"].items():
        lines += [f"**{name}** (HG g = 0.9, albedo 0.99)", "",
                  "| alpha | order | events/path (ratio) | seconds at equal spp | rel. RMSE at equal spp | seconds to the original's RMSE | speed-up |",
                  "|---|---|---|---|---|---|---|"]
        for r in rows:
            lines.append(f"| {r['alpha']:g}{' (original)' if r['alpha'] == 1 else ''} | {fmt(r['order'], 'd')} | "
                         f"{r['events_per_path']:.2f} ({r['events_ratio']:.2f}) | {r['seconds']:.2f} | "
                         f"{r['relative_rmse']:.4f} | {fmt(r['seconds_to_quality'], '.2f')} | {fmt(r['speedup'], '.1f')} |")
        lines.append("")
    e = report["equal_first_moments"]
    lines += ["## 2. Order up to 5 against order 1 (Fig. 9; f1 = 0.7563 for all; 4x4-pixel tiles)", "",
              "| phase | Algorithm 1 (support rule): order (support), rel. RMSE, bias | order 1: rel. RMSE, bias | "
              "no threshold: order (support), rel. RMSE | distance rule: order (support), rel. RMSE, bias | noise floor |",
              "|---|---|---|---|---|---|"]
    for name, (title, _) in PHASES.items():
        r = e[name]
        a, o, f, d = r["algorithm1"], r["order1"], r["no_threshold"], r["distance"]
        lines.append(f"| {name}: {title} | {a['order']} ({a['support']:.2f}), {a['tile_rmse']:.4f}, {a['mean_relative_error']:+.3f} | "
                     f"{o['tile_rmse']:.4f}, {o['mean_relative_error']:+.3f} | {f['order']} ({f['support']:.2f}), {f['tile_rmse']:.4f} | "
                     f"{d['order']} ({d['support']:.2f}), {d['tile_rmse']:.4f}, {d['mean_relative_error']:+.3f} | "
                     f"{r['noise_floor_tile_rmse']:.4f} |")
    lines += ["", f"A against B (references): {e['A_vs_B_reference_tile_rmse']:.4f}; "
              f"A against B (both order 1): {e['A_vs_B_order1_tile_rmse']:.4f}; "
              f"A against B (both Algorithm 1): {e['A_vs_B_algorithm1_tile_rmse']:.4f}", "",
              "## 3. Throughput", "", "| g | order | QP solves | ms per solve |", "|---|---|---|---|"]
    for s in report["throughput"]["single"]:
        lines.append(f"| {s['g']} | {s['order']} | {s['solves']} | {s['ms_per_solve']:.1f} |")
    lines += ["", "Whole media (median of 3 runs per rule, alternating; ratios against the support rule's medians):", "",
              "| medium | order rule | voxels | tables | QP solves | moment bound | max moment error | read + alter + write (s) | "
              "alter ratio | wall (s) | wall ratio |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for m in report["throughput"]["media"]:
        s = m["seconds"]
        lines.append(f"| {m['medium']} | {m['rule']} | {m['voxels']} | {m['tables']} | {m['solves']} | {m['moment_bound']:.2g} | "
                     f"{m['max_moment_error']:.2g} | {s['read']:.2f} + {s['alter']:.2f} + {s['write']:.2f} | "
                     f"{m['alter_ratio']:.2f} | {m['wall_seconds']:.2f} | {m['wall_ratio']:.2f} |")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="similarity-out")
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--ref-spp", type=int, default=1024)
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tools = Tools(args.build)
    report = {"speedup": speedup(tools, out, args.spp, args.ref_spp),
              "equal_first_moments": equal_first_moments(tools, out, args.ref_spp),
              "throughput": throughput(tools, out)}
    (out / "report.json").write_text(json.dumps(report, indent=2))
    png = plot(out)
    (out / "report.md").write_text(markdown(report, args.spp, args.ref_spp) + f"\n![plots]({png.name})\n")
    print((out / "report.md").read_text())


if __name__ == "__main__":
    main()
