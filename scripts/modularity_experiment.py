#!/usr/bin/env python3
"""make modularity: §7 of the downsampling paper with vdb_exemplar_stack, measured.

Six woven exemplars (vdb_make_medium exemplars, blocks of 64 x 64 x 16 voxels) are stacked into one
exemplar volume four times (four random stackings), each reduced by 4 with 2 lobes and 2 clusters
(vdb_lobe_cluster) and optimised once (vdb_optimize_weights, default settings), then split back into
reduced blocks. Two models are assembled from them: A, the block set's own 8 x 8 layout, and B, a
16 x 4 layout with another pattern (layout_16x4.json). Each is judged against its own full-resolution
reference (the same layout assembled from the full blocks) under the held-out lighting of make
optimize (three-quarter view; an environment map, a point light over a ground), next to the naive
reduction (the split of the un-optimised lobes).

- Stacking invariance (Fig. 10): the spread of model A's mean foreground intensity over the four
  stackings, against the Monte Carlo noise of such a mean: the optimiser's (stacking 1 optimised with
  three seeds) and the render's (stacking 1 rendered with three seeds).
- Shared optimisation: A and B against their references: mean error and 8x8-tile relative RMSE,
  naive and optimised, with side-by-side images and error maps.
- Seams: the errors over pixels near block borders against pixels inside blocks (masks from the
  held-out camera and the sheet's mid-plane; vdb_image_compare --mask).
- Instancing: a 64 x 64 layout of blocks 128 voxels on a side, instanced, rendered at 1280x720 with
  its peak memory, and the same blocks in 16 x 16 and 256 x 256 layouts (memory against model size);
  model A built and instanced rendered alike.
- Amortised cost: the stacked pipeline (stack, lobes, optimisation, split, one assemble per model)
  against reducing and optimising each full model on its own (lobes + optimisation of A and of B,
  measured; for 8 models the per-model cost is the mean of the two).

Writes modularity-out/: report.md, report.json, images.
Usage: scripts/modularity_experiment.py [--build build] [--out modularity-out] [--spp 128]
"""
import argparse
import json
import math
import pathlib
import re
import shutil
import subprocess
import sys
import time

import pinhole_pixels
from optimize_experiment import Experiment, add_render_arguments, comparison_pictures

FACTOR, LOBES, CLUSTERS = 4, 2, 2
BLOCK_WORLD = 4.0  # a block of vdb_make_medium exemplars: 4 yarns of 1 world unit
SEAM_BAND, INSIDE_FROM = 0.25, 0.75  # world units from the nearest block border: border pixels, inside pixels


def pixel_rays(camera_flags, width, height):
    """The centre ray of every pixel of vdb_render's camera given by its flags (z up)."""
    flags = dict(zip(camera_flags[::2], camera_flags[1::2]))
    position = [float(v) for v in flags["--camera-pos"].split(",")]
    target = [float(v) for v in flags["--camera-target"].split(",")]
    return pinhole_pixels.pixel_rays(position, target, [0, 0, 1], float(flags["--fov"]), width, height)


def seam_masks(folder, camera_flags, size, plane_z, blocks_x, blocks_y):
    """Pixels whose ray meets the sheet's mid-plane within SEAM_BAND of a block border (between two
    blocks), and pixels farther than INSIDE_FROM from every border: two PFM masks."""
    width, height = (int(v) for v in size.split("x"))
    border, inside = set(), set()
    for x, y, o, d in pixel_rays(camera_flags, width, height):
        if abs(d[2]) < 1e-9:
            continue
        t = (plane_z - o[2]) / d[2]
        px, py = o[0] + t * d[0], o[1] + t * d[1]
        if t <= 0 or not (0 < px < blocks_x * BLOCK_WORLD and 0 < py < blocks_y * BLOCK_WORLD):
            continue
        gx, gy = px / BLOCK_WORLD, py / BLOCK_WORLD
        to_border = BLOCK_WORLD * min(abs(gx - round(gx)) if 0 < round(gx) < blocks_x else 1,
                                      abs(gy - round(gy)) if 0 < round(gy) < blocks_y else 1)
        if to_border < SEAM_BAND:
            border.add((x, y))
        elif to_border > INSIDE_FROM:
            inside.add((x, y))
    masks = {"border": folder / "mask_border.pfm", "inside": folder / "mask_inside.pfm"}
    pinhole_pixels.write_mask_pfm(masks["border"], width, height, border)
    pinhole_pixels.write_mask_pfm(masks["inside"], width, height, inside)
    return masks


class Modularity(Experiment):
    def __init__(self, args):
        super().__init__(args)
        self.stack_flags = args.stack_flags.split()
    def timed(self, name, *args):
        start = time.monotonic()
        self.tool(name, *args)
        return time.monotonic() - start

    def exemplars(self):
        blocks = self.out / "blocks.vdb"
        self.tool("vdb_make_medium", "exemplars", "--count", "6", "--res", "64", "--layout", "8x8", "-o", blocks)
        layout = self.out / "layout_16x4.json"
        rows = [[(3 * i + 5 * j + (i // 4)) % 6 for i in range(16)] for j in range(4)]
        layout.write_text(json.dumps(rows))
        return blocks, layout

    def stacked_pipeline(self, blocks, seed, optimiser_seed=1):
        """stack, lobes, optimisation, split: the reduced blocks (optimised and naive) and the seconds."""
        d = self.out / f"stack_{seed}" if optimiser_seed == 1 else self.out / f"stack_{seed}_seed_{optimiser_seed}"
        d.mkdir(exist_ok=True)
        stacked, lobes, opt = d / "stacked.vdb", d / "lobes.vdb", d / "optimised.vdb"
        seconds = {"stack": self.timed("vdb_exemplar_stack", "stack", "--seed", seed, *self.stack_flags, blocks, stacked)}
        seconds["lobes"] = self.timed("vdb_lobe_cluster", "-f", FACTOR, "--lobes", LOBES, "--clusters", CLUSTERS,
                                      stacked, lobes)
        seconds["optimise"] = self.timed("vdb_optimize_weights", stacked, lobes, opt, "--cache", self.cache,
                                         "--log", d / "run.jsonl", "--report", d / "optimize.json",
                                         "--seed", optimiser_seed, *self.optimize_flags)
        seconds["split"] = self.timed("vdb_exemplar_stack", "split", opt, d / "blocks_opt.vdb")
        self.tool("vdb_exemplar_stack", "split", lobes, d / "blocks_naive.vdb")
        return d / "blocks_opt.vdb", d / "blocks_naive.vdb", seconds

    def assemble(self, blocks, out, layout=None):
        return self.timed("vdb_exemplar_stack", "assemble", *(["--layout", layout] if layout else []), blocks, out)

    def own_optimisation(self, full, name):
        """Reducing and optimising one full model by itself: seconds."""
        d = self.out / f"own_{name}"
        d.mkdir(exist_ok=True)
        t = self.timed("vdb_lobe_cluster", "-f", FACTOR, "--lobes", LOBES, "--clusters", CLUSTERS, full, d / "lobes.vdb")
        t += self.timed("vdb_optimize_weights", full, d / "lobes.vdb", d / "optimised.vdb", "--cache", self.cache,
                        "--report", d / "optimize.json", *self.optimize_flags)
        return t

    def seams(self, name, full, blocks_x, blocks_y):
        """Errors of the naive and optimised model over border pixels against inside pixels."""
        camera = self.camera(full, 250, 40)
        centre, _, _ = self.box(full)
        masks = seam_masks(self.out / name, camera, self.size, centre[2], blocks_x, blocks_y)
        result = {}
        for kind in ("env_map", "point_light"):
            ref = self.out / name / f"full_three-quarter_{kind}.exr"
            for label in ("naive", "optimised"):
                exr = self.out / name / f"{label}_three-quarter_{kind}.exr"
                for region, mask in masks.items():
                    c = json.loads(self.tool("vdb_image_compare", ref, exr, "--foreground", "--mask", mask,
                                             "--report", "-").stdout)
                    result[f"{kind}_{label}_{region}"] = {"mean_error": c["mean_relative_error"],
                                                          "relative_rmse": c["relative_rmse"]}
        return result

    def own_accuracy(self, name, full):
        """The held-out errors of the model optimised on its own (own_optimisation)."""
        own = self.out / f"own_{name}" / "optimised.vdb"
        camera = self.camera(full, 250, 40)
        result = {}
        for kind in ("env_map", "point_light"):
            exr = self.out / name / f"own_three-quarter_{kind}.exr"
            self.render(own, exr, camera, self.lights(full, kind), self.spp)
            result[f"three-quarter_{kind}"] = self.compare(self.out / name / f"full_three-quarter_{kind}.exr", exr)
        return result

    def timed_render(self, model, png, report):
        """vdb_render at 1280x720, 16 spp, under /usr/bin/time -v: (peak resident MB, wall, its report)."""
        timed = subprocess.run(["/usr/bin/time", "-v", self.bin / "vdb_render", model, "-o", png,
                                "--res", "1280x720", "--spp", "16", "--camera-pos", "300,-200,200", "--camera-target",
                                "128,128,0", "--fov", "40", "--sun", "0.3,0.2,-1,3", "--env", "0.3", "--report",
                                report], check=True, text=True, capture_output=True)
        peak_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", timed.stderr).group(1))
        wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", timed.stderr).group(1)
        return peak_kb / 1024, wall, json.loads(pathlib.Path(report).read_text())

    def instancing(self):
        """A 64 x 64 layout of blocks 128 voxels on a side, instanced, rendered at 1280x720: peak memory
        and time (/usr/bin/time -v); the same blocks in 16 x 16 and 256 x 256 layouts (ids (3i + 5j)
        mod 6), for how memory grows with the model; and model A built and instanced, rendered alike."""
        d = self.out / "instancing"
        d.mkdir(exist_ok=True)
        blocks, model = d / "blocks_128.vdb", d / "model_64x64.vdb"
        self.tool("vdb_make_medium", "exemplars", "--count", "6", "--res", "128", "--layout", "64x64", "-o", blocks)
        self.tool("vdb_exemplar_stack", "assemble", "--instanced", blocks, model)
        peak_mb, wall, report = self.timed_render(model, d / "model_64x64.png", d / "render.json")
        growth = []
        for n in (16, 256):
            layout, grown = d / f"layout_{n}x{n}.json", d / f"model_{n}x{n}.vdb"
            layout.write_text(json.dumps([[(3 * i + 5 * j) % 6 for i in range(n)] for j in range(n)]))
            self.tool("vdb_exemplar_stack", "assemble", "--instanced", "--layout", layout, blocks, grown)
            peak, _, r = self.timed_render(grown, d / f"model_{n}x{n}.png", d / f"render_{n}x{n}.json")
            growth.append({"layout": f"{n}x{n}", "model_active_voxels": r["instanced_model_voxels"],
                           "majorant_voxels": r["majorant_voxels"], "peak_rss_mb": peak, "render_seconds": r["seconds"]})
            grown.unlink()
        built, instanced = self.out / "A" / "full.vdb", d / "A_instanced.vdb"
        self.tool("vdb_exemplar_stack", "assemble", "--instanced", self.out / "blocks.vdb", instanced)
        camera = self.camera(built, 250, 40)
        images = []
        for label, vdb in (("built", built), ("instanced", instanced)):
            images.append(d / f"A_{label}.exr")
            self.render(vdb, images[-1], camera, self.lights(built, "env_map"), 16, res="120x90")
        same = json.loads(self.tool("vdb_image_compare", images[0], images[1], "--report", "-").stdout)
        voxels_per_block = 128 * 128 * 32
        return {"layout": "64x64", "block_voxels": [128, 128, 32], "model_cells": 64 * 64 * voxels_per_block,
                "model_active_voxels": report["instanced_model_voxels"], "file_bytes": model.stat().st_size,
                "peak_rss_mb": peak_mb, "wall": wall, "render_seconds": report["seconds"],
                "majorant_voxels": report["majorant_voxels"], "built_vs_instanced_rmse": same["rmse"],
                "built_vs_instanced_mean_error": same["mean_relative_error"], "growth": growth}

    def mean_foreground(self, reference_exr, exr):
        c = json.loads(self.tool("vdb_image_compare", reference_exr, exr, "--foreground", "--report", "-").stdout)
        return c["mean_test"]


def relative_spread(values):
    """Sample standard deviation over the mean."""
    mean = sum(values) / len(values)
    return math.sqrt(sum((x - mean) ** 2 for x in values) / (len(values) - 1)) / mean


def stacking_invariance(m, full_a, by_stacking, by_optimiser_seed):
    """Mean foreground intensity of model A from each stacking (optimiser seed 1) and from stacking 1
    optimised with each optimiser seed, under each held-out light (render seed 1); the spread of each
    set, and the render noise of one mean (stacking 1 rendered with three seeds)."""
    camera = m.camera(full_a, 250, 40)
    result = {}
    for kind in ("env_map", "point_light"):
        light = m.lights(full_a, kind)
        ref = m.out / "A" / f"full_three-quarter_{kind}.exr"

        def mean_of(model, tag, seed=1):
            exr = m.out / "invariance" / f"{tag}_{kind}_render{seed}.exr"
            m.render(model, exr, camera, light, m.spp, seed=seed)
            return m.mean_foreground(ref, exr)

        stackings = {s: mean_of(v, f"stack{s}") for s, v in by_stacking.items()}
        seeds = {s: stackings[1] if s == 1 else mean_of(v, f"stack1_optimiser{s}") for s, v in by_optimiser_seed.items()}
        renders = [mean_of(by_stacking[1], "stack1", seed) for seed in (1, 2, 3)]
        result[kind] = {"stacking_means": stackings, "optimiser_seed_means": seeds, "render_seed_means": renders,
                        "stacking_spread": relative_spread(list(stackings.values())),
                        "optimiser_spread": relative_spread(list(seeds.values())),
                        "render_spread": relative_spread(renders),
                        "stacking_2_vs_1": (stackings[2] - stackings[1]) / stackings[1]}
    return result


def write_report(out, r):
    lines = ["# make modularity: one optimisation of stacked exemplars serves every model (§7)", "",
             "Generated by `scripts/modularity_experiment.py` (docs/modularity.md). Six exemplars of 64 x 64 x 16",
             f"voxels, reduced by {FACTOR} with {LOBES} lobes and {CLUSTERS} clusters; model A: 8 x 8 blocks, model B:",
             "16 x 4 blocks of another pattern. Held out: three-quarter view (azimuth 250, elevation 40) under an",
             "environment map and a point light over a ground; errors over the full model's foreground.", "",
             "## Shared optimisation: two layouts from one optimised block set (stacking 1)", "",
             "Columns: naive (the split of the un-optimised lobes), shared (the one stacked optimisation), own (the",
             "full model reduced and optimised by itself, for comparison).", "",
             "| model | held-out light | naive mean | shared mean | own mean | naive tile RMSE | shared tile RMSE | "
             "own tile RMSE | bar (shared: <= naive / 3, <= 2%, tile RMSE below naive) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for model in ("A", "B"):
        for tag, c in r["held_out"][model].items():
            o = r["own"][model][tag]
            n, s_ = c["naive"], c["optimised"]
            bar = (abs(s_["mean_error"]) <= abs(n["mean_error"]) / 3 and abs(s_["mean_error"]) <= 0.02
                   and s_["tile_rmse"] < n["tile_rmse"])
            lines.append(f"| {model} | {tag} | {100 * n['mean_error']:+.2f}% | {100 * s_['mean_error']:+.2f}% | "
                         f"{100 * o['mean_error']:+.2f}% | {n['tile_rmse']:.4f} | {s_['tile_rmse']:.4f} | "
                         f"{o['tile_rmse']:.4f} | {'yes' if bar else 'no'} |")
    lines += ["", "## Seams: pixels near block borders against pixels inside blocks", "",
              f"Pixels whose ray meets the sheet's mid-plane within {SEAM_BAND} world units of a border between two "
              f"blocks (a block is {BLOCK_WORLD:g} units; a reduced voxel 0.25) against pixels farther than "
              f"{INSIDE_FROM} from every border; per-pixel relative RMSE and mean error against the full model.", "",
              "| model | light | reduction | border: mean, RMSE | inside: mean, RMSE |", "|---|---|---|---|---|"]
    for model in ("A", "B"):
        for kind in ("env_map", "point_light"):
            for label in ("naive", "optimised"):
                b_ = r["seams"][model][f"{kind}_{label}_border"]
                i_ = r["seams"][model][f"{kind}_{label}_inside"]
                lines.append(f"| {model} | {kind} | {label} | {100 * b_['mean_error']:+.2f}%, {b_['relative_rmse']:.4f} | "
                             f"{100 * i_['mean_error']:+.2f}%, {i_['relative_rmse']:.4f} |")
    lines += ["", "## Stacking invariance (Fig. 10): model A from four random stackings", "",
              "Mean foreground intensity of model A (render seed 1) from stackings 1-4 (optimiser seed 1), against the",
              "Monte Carlo noise of such a mean: the optimiser's (stacking 1 optimised with seeds 1-3: other training",
              "renders) and the render's (stacking 1 rendered with seeds 1-3). Spreads: sample standard deviations",
              "relative to the mean.", "",
              "| held-out light | stacking 2 vs 1 | spread over stackings | spread over optimiser seeds | render noise | "
              "noise of the comparison (optimiser and render) |", "|---|---|---|---|---|---|"]
    for kind, c in r["invariance"].items():
        noise = math.sqrt(c["optimiser_spread"] ** 2 + c["render_spread"] ** 2)
        lines.append(f"| {kind} | {100 * c['stacking_2_vs_1']:+.2f}% | {100 * c['stacking_spread']:.2f}% | "
                     f"{100 * c['optimiser_spread']:.2f}% | {100 * c['render_spread']:.2f}% | {100 * noise:.2f}% |")
    s, own = r["seconds"]["stack_1"], r["seconds"]["own"]
    stacked = s["stack"] + s["lobes"] + s["optimise"] + s["split"]
    per_model_assemble = (r["seconds"]["assemble_A"] + r["seconds"]["assemble_B"]) / 2
    per_model_own = (own["A"] + own["B"]) / 2
    lines += ["", "## Amortised cost", "",
              f"Stacked pipeline: stack {s['stack']:.1f} s, lobes {s['lobes']:.1f} s, optimisation {s['optimise']:.1f} s, "
              f"split {s['split']:.1f} s; assembling a model {per_model_assemble:.1f} s. Each model on its own (lobes + "
              f"optimisation of the full model): A {own['A']:.1f} s, B {own['B']:.1f} s.", "",
              "| models | stacked, once (s) | each on its own (s) | ratio |", "|---|---|---|---|"]
    for n in (2, 8):
        a = stacked + n * per_model_assemble
        b = own["A"] + own["B"] if n == 2 else n * per_model_own
        lines.append(f"| {n}{'' if n == 2 else ' (own: 8 x the mean of A and B)'} | {a:.1f} | {b:.1f} | {b / a:.2f} |")
    i = r["instancing"]
    lines += ["", "## Instancing", "",
              f"A {i['layout']} layout of blocks of {i['block_voxels'][0]} x {i['block_voxels'][1]} x "
              f"{i['block_voxels'][2]} voxels: {i['model_cells'] / 1e9:.2f} G voxel cells, {i['model_active_voxels'] / 1e6:.0f} M "
              f"active voxels if built; instanced file {i['file_bytes'] / 1e6:.1f} MB. `vdb_render` at 1280x720, 16 spp: "
              f"peak resident memory {i['peak_rss_mb']:.0f} MB (/usr/bin/time -v), wall {i['wall']}, render "
              f"{i['render_seconds']:.1f} s, {i['majorant_voxels'] / 1e6:.1f} M majorant voxels.", "",
              f"Model A built and instanced, rendered alike (120x90, 16 spp, same seed): RMSE {i['built_vs_instanced_rmse']:.3g}, "
              f"mean {100 * i['built_vs_instanced_mean_error']:+.4f}%.", "",
              "How memory grows with the model (the same blocks and render; the model's majorant is walked "
              "through the layout, not built):", "",
              "| layout | active voxels if built | majorant voxels if built | peak resident memory | render |",
              "|---|---|---|---|---|"]
    rows = [{"layout": i["layout"], "model_active_voxels": i["model_active_voxels"], "majorant_voxels": i["majorant_voxels"],
             "peak_rss_mb": i["peak_rss_mb"], "render_seconds": i["render_seconds"]}] + i.get("growth", [])
    for g in sorted(rows, key=lambda g: g["model_active_voxels"]):
        lines.append(f"| {g['layout']} | {g['model_active_voxels'] / 1e6:,.0f} M | {g['majorant_voxels'] / 1e6:,.1f} M | "
                     f"{g['peak_rss_mb']:.0f} MB | {g['render_seconds']:.1f} s |")
    lines += ["", "![instanced](instancing/model_64x64.png)"]
    lines += ["", "## Pictures", ""]
    for model in ("A", "B"):
        for tag in r["held_out"][model]:
            lines += comparison_pictures(model, tag, f"Model {model}, {tag}")
    (out / "report.md").write_text("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_render_arguments(parser, "modularity-out")
    parser.add_argument("--stack-flags", default="", help="extra flags for vdb_exemplar_stack stack (e.g. --shape 3x2x1)")
    args = parser.parse_args()
    start = time.monotonic()
    m = Modularity(args)
    for d in ("A", "B", "invariance", "instancing", "stack_1", "stack_2", "stack_3", "stack_4", "stack_1_seed_2",
              "stack_1_seed_3", "own_A", "own_B"):
        shutil.rmtree(m.out / d, ignore_errors=True)  # renders of an earlier run would be reused
    for d in ("A", "B", "invariance"):
        (m.out / d).mkdir(exist_ok=True)
    blocks, layout_b = m.exemplars()
    seconds = {}
    print("modularity: stacked pipelines", file=sys.stderr)
    opt1, naive1, seconds["stack_1"] = m.stacked_pipeline(blocks, 1)
    stacked_blocks = {1: opt1}
    for seed in (2, 3, 4):
        stacked_blocks[seed], _, seconds[f"stack_{seed}"] = m.stacked_pipeline(blocks, seed)
    reseeded_blocks = {1: opt1}
    for seed in (2, 3):
        reseeded_blocks[seed], _, _ = m.stacked_pipeline(blocks, 1, optimiser_seed=seed)
    models = {}
    for name, layout in (("A", None), ("B", layout_b)):
        models[name] = {"full": m.out / name / "full.vdb", "naive": m.out / name / "naive.vdb",
                        "optimised": m.out / name / "optimised.vdb"}
        m.assemble(blocks, models[name]["full"], layout)
        m.assemble(naive1, models[name]["naive"], layout)
        seconds[f"assemble_{name}"] = m.assemble(opt1, models[name]["optimised"], layout)
    by_stacking, by_optimiser_seed = {1: models["A"]["optimised"]}, {1: models["A"]["optimised"]}
    for seed in (2, 3, 4):
        by_stacking[seed] = m.out / "invariance" / f"optimised_stack{seed}.vdb"
        m.assemble(stacked_blocks[seed], by_stacking[seed])
    for seed in (2, 3):
        by_optimiser_seed[seed] = m.out / "invariance" / f"optimised_stack1_seed{seed}.vdb"
        m.assemble(reseeded_blocks[seed], by_optimiser_seed[seed])
    print("modularity: held-out renders", file=sys.stderr)
    held_out = {name: m.held_out(name, v["full"], v["naive"], v["optimised"]) for name, v in models.items()}
    invariance = stacking_invariance(m, models["A"]["full"], by_stacking, by_optimiser_seed)
    seams = {"A": m.seams("A", models["A"]["full"], 8, 8), "B": m.seams("B", models["B"]["full"], 16, 4)}
    print("modularity: each model optimised on its own", file=sys.stderr)
    seconds["own"] = {name: m.own_optimisation(v["full"], name) for name, v in models.items()}
    own = {name: m.own_accuracy(name, v["full"]) for name, v in models.items()}
    print("modularity: instancing", file=sys.stderr)
    instancing = m.instancing()
    result = {"held_out": held_out, "own": own, "invariance": invariance, "seams": seams, "seconds": seconds,
              "instancing": instancing, "total_seconds": time.monotonic() - start}
    (m.out / "report.json").write_text(json.dumps(result, indent=1))
    write_report(m.out, result)
    print(f"modularity: {m.out / 'report.md'} in {time.monotonic() - start:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
