#!/usr/bin/env python3
"""make modularity: §7 of the downsampling paper with vdb_exemplar_stack, measured.

Six woven exemplars (vdb_make_medium exemplars, blocks of 64 x 64 x 16 voxels) are stacked into one
exemplar volume twice (two random stackings), each reduced by 4 with 2 lobes and 2 clusters
(vdb_lobe_cluster) and optimised once (vdb_optimize_weights, default settings), then split back into
reduced blocks. Two models are assembled from them: A, the block set's own 8 x 8 layout, and B, a
16 x 4 layout with another pattern (layout_16x4.json). Each is judged against its own full-resolution
reference (the same layout assembled from the full blocks) under the held-out lighting of make
optimize (three-quarter view; an environment map, a point light over a ground), next to the naive
reduction (the split of the un-optimised lobes).

- Stacking invariance (Fig. 10): model A from the two stackings, the relative difference of their
  mean foreground intensities, against the Monte Carlo noise of such a difference (the spread of the
  means of model A rendered with three seeds, times sqrt(2)).
- Shared optimisation: A and B against their references: mean error and 8x8-tile relative RMSE,
  naive and optimised, with side-by-side images and error maps.
- Amortised cost: the stacked pipeline (stack, lobes, optimisation, split, one assemble per model)
  against reducing and optimising each full model on its own (lobes + optimisation of A and of B,
  measured; for 8 models the per-model cost is the mean of the two).

Writes modularity-out/: report.md, report.json, images.
Usage: scripts/modularity_experiment.py [--build build] [--out modularity-out] [--spp 32]
"""
import argparse
import json
import math
import pathlib
import sys
import time

from optimize_experiment import Experiment

FACTOR, LOBES, CLUSTERS = 4, 2, 2


class Modularity(Experiment):
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

    def stacked_pipeline(self, blocks, seed):
        """stack, lobes, optimisation, split: the reduced blocks (optimised and naive) and the seconds."""
        d = self.out / f"stack_{seed}"
        d.mkdir(exist_ok=True)
        stacked, lobes, opt = d / "stacked.vdb", d / "lobes.vdb", d / "optimised.vdb"
        seconds = {"stack": self.timed("vdb_exemplar_stack", "stack", "--seed", seed, blocks, stacked)}
        seconds["lobes"] = self.timed("vdb_lobe_cluster", "-f", FACTOR, "--lobes", LOBES, "--clusters", CLUSTERS,
                                      stacked, lobes)
        seconds["optimise"] = self.timed("vdb_optimize_weights", stacked, lobes, opt, "--cache", self.cache,
                                         "--log", d / "run.jsonl", "--report", d / "optimize.json", *self.optimize_flags)
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

    def mean_foreground(self, reference_exr, exr):
        c = json.loads(self.tool("vdb_image_compare", reference_exr, exr, "--foreground", "--report", "-").stdout)
        return c["mean_test"]


def stacking_invariance(m, full_a, model_a1, model_a2):
    """Mean of model A from stacking 2 against stacking 1, and the noise of such a difference."""
    camera = m.camera(full_a, 250, 40)
    result = {}
    for kind in ("env_map", "point_light"):
        light = m.lights(full_a, kind)
        ref = m.out / "A" / f"full_three-quarter_{kind}.exr"
        means = []
        for seed in (1, 2, 3):
            exr = m.out / "invariance" / f"stack1_{kind}_seed{seed}.exr"
            m.render(model_a1, exr, camera, light, m.spp, seed=seed)
            means.append(m.mean_foreground(ref, exr))
        exr2 = m.out / "invariance" / f"stack2_{kind}_seed1.exr"
        m.render(model_a2, exr2, camera, light, m.spp, seed=1)
        other = m.mean_foreground(ref, exr2)
        mean = sum(means) / 3
        spread = math.sqrt(sum((x - mean) ** 2 for x in means) / 2)
        result[kind] = {"stacking_difference": (other - means[0]) / mean,
                        "noise_of_a_difference": math.sqrt(2) * spread / mean, "means_seed_1_2_3": means,
                        "mean_stacking_2": other}
    return result


def write_report(out, r):
    lines = ["# make modularity: one optimisation of stacked exemplars serves every model (§7)", "",
             "Generated by `scripts/modularity_experiment.py` (docs/modularity.md). Six exemplars of 64 x 64 x 16",
             f"voxels, reduced by {FACTOR} with {LOBES} lobes and {CLUSTERS} clusters; model A: 8 x 8 blocks, model B:",
             "16 x 4 blocks of another pattern. Held out: three-quarter view (azimuth 250, elevation 40) under an",
             "environment map and a point light over a ground; errors over the full model's foreground.", "",
             "## Shared optimisation: two layouts from one optimised block set (stacking 1)", "",
             "| model | held-out light | naive mean | optimised mean | naive tile RMSE | optimised tile RMSE |",
             "|---|---|---|---|---|---|"]
    for model in ("A", "B"):
        for tag, c in r["held_out"][model].items():
            lines.append(f"| {model} | {tag} | {100 * c['naive']['mean_error']:+.2f}% | "
                         f"{100 * c['optimised']['mean_error']:+.2f}% | {c['naive']['tile_rmse']:.4f} | "
                         f"{c['optimised']['tile_rmse']:.4f} |")
    lines += ["", "## Stacking invariance (Fig. 10): model A from two random stackings", "",
              "| held-out light | mean, stacking 2 vs 1 | Monte Carlo noise of such a difference |", "|---|---|---|"]
    for kind, c in r["invariance"].items():
        lines.append(f"| {kind} | {100 * c['stacking_difference']:+.2f}% | {100 * c['noise_of_a_difference']:.2f}% |")
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
    lines += ["", "## Pictures", ""]
    for model in ("A", "B"):
        for tag in r["held_out"][model]:
            lines += [f"Model {model}, {tag}: full | naive | error map, then full | optimised | error map (red: brighter, "
                      "blue: darker, saturating at 25%)", "",
                      f"![naive]({model}/compare_naive_{tag}.png)", f"![optimised]({model}/compare_optimised_{tag}.png)", ""]
    (out / "report.md").write_text("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="modularity-out")
    parser.add_argument("--spp", type=int, default=32, help="samples per pixel of the held-out renders")
    parser.add_argument("--size", default="240x180", help="held-out image size")
    parser.add_argument("--keep-cache", action="store_true", help="keep the reference cache of an earlier run")
    parser.add_argument("--optimize-flags", default="", help="extra flags for vdb_optimize_weights (studies)")
    args = parser.parse_args()
    start = time.monotonic()
    m = Modularity(args)
    for d in ("A", "B", "invariance"):
        (m.out / d).mkdir(exist_ok=True)
    blocks, layout_b = m.exemplars()
    seconds = {}
    print("modularity: stacked pipelines", file=sys.stderr)
    opt1, naive1, seconds["stack_1"] = m.stacked_pipeline(blocks, 1)
    opt2, _, seconds["stack_2"] = m.stacked_pipeline(blocks, 2)
    models = {}
    for name, layout in (("A", None), ("B", layout_b)):
        models[name] = {"full": m.out / name / "full.vdb", "naive": m.out / name / "naive.vdb",
                        "optimised": m.out / name / "optimised.vdb"}
        m.assemble(blocks, models[name]["full"], layout)
        m.assemble(naive1, models[name]["naive"], layout)
        seconds[f"assemble_{name}"] = m.assemble(opt1, models[name]["optimised"], layout)
    model_a2 = m.out / "invariance" / "optimised_stack2.vdb"
    m.assemble(opt2, model_a2)
    print("modularity: held-out renders", file=sys.stderr)
    held_out = {name: m.held_out(name, v["full"], v["naive"], v["optimised"]) for name, v in models.items()}
    invariance = stacking_invariance(m, models["A"]["full"], models["A"]["optimised"], model_a2)
    print("modularity: each model optimised on its own", file=sys.stderr)
    seconds["own"] = {name: m.own_optimisation(v["full"], name) for name, v in models.items()}
    result = {"held_out": held_out, "invariance": invariance, "seconds": seconds,
              "total_seconds": time.monotonic() - start}
    (m.out / "report.json").write_text(json.dumps(result, indent=1))
    write_report(m.out, result)
    print(f"modularity: {m.out / 'report.md'} in {time.monotonic() - start:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
