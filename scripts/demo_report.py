#!/usr/bin/env python3
"""Summarises the demo's reports as a table (stdout and FOLDER/report.md)."""
import json
import pathlib
import sys

REDUCED = ("2x", "4x", "4x_lobes", "4x_optimised", "8x")


def load(folder, name):
    return json.loads((folder / name).read_text())


def rows_of(folder):
    make_seconds = float((folder / "make_seconds.txt").read_text())
    full = load(folder, "twill_2x.json")["input"]
    rows = [("full resolution", full, f"made in {make_seconds:.2f} s", "twill", None)]
    for reduced in REDUCED:
        r = load(folder, f"twill_{reduced}.json")
        if reduced == "4x_lobes":
            label = f"4x, {r['lobe_count']} lobes, {len(r['clusters'])} clusters"
            made = f"fitted in {r['seconds']['fit']:.2f} s"
        elif reduced == "4x_optimised":
            label = "4x, the same, optimised weights"
            made = (f"optimised in {r['seconds']['total']:.0f} s ({r['iterations']} iterations, "
                    f"E {r['E_naive']:.3g} -> {r['E_final']:.3g})")
            rows.append((label, load(folder, "twill_4x_lobes.json")["output"], made, f"twill_{reduced}", reduced))
            continue
        else:
            label = f"naive {reduced}"
            made = f"downsampled in {r['seconds']['downsample']:.3f} s"
        rows.append((label, r["output"], made, f"twill_{reduced}", reduced))
    return rows


def table(folder):
    header = ("| medium | active voxels | memory MB | file MB | made | render s | paths/s | "
              "mean intensity (fabric) | error vs full | relative RMSE | on 8x8 tiles |\n"
              "|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|\n")
    lines = []
    for label, medium, made, render_name, reduced in rows_of(folder):
        render = load(folder, f"render_{render_name}.json")
        cells = [label, f"{medium['active_voxels']:,}", f"{medium['memory_bytes'] / 1e6:.1f}",
                 f"{medium['file_bytes'] / 1e6:.1f}", made, f"{render['seconds']:.1f}",
                 f"{render['paths_per_second']:.3g}"]
        if reduced:
            pixels, tiles = load(folder, f"compare_{reduced}.json"), load(folder, f"compare_{reduced}_tiles.json")
            cells += [f"{pixels['mean_test']:.4f}", f"{100 * pixels['mean_relative_error']:+.2f}%",
                      f"{100 * pixels['relative_rmse']:.1f}%", f"{100 * tiles['relative_rmse']:.1f}%"]
        else:
            cells += [f"{load(folder, 'compare_2x.json')['mean_reference']:.4f}", "reference", "", ""]
        lines.append("| " + " | ".join(cells) + " |")
    return header + "\n".join(lines) + "\n"


def main():
    folder = pathlib.Path(sys.argv[1])
    text_table = table(folder)
    spp = load(folder, "render_twill.json")["spp"]
    voxel_size = load(folder, "twill_2x.json")["input"]["voxel_size"]
    pictures = "\n\n".join(f"{name}: full | reduced | error (red: brighter, blue: darker, saturating at 50%)\n\n"
                           f"![compare {name}](compare_{name}.png)" for name in REDUCED)
    text = ("# vdbappear demo\n\nThe default medium (`vdb_make_medium twill --yarns 12`: a 2/2 twill of twisted "
            "fibres, pink warp and yellow weft as in Fig. 9 of the downsampling paper, voxel size "
            f"{voxel_size:.4g}) downsampled naively (Eq. 5-6) with `vdb_sggx_downsample`, and by 4 with two "
            "SGGX lobes per voxel and two albedo clusters with `vdb_lobe_cluster` (§5-6.2, naive lobe weights). "
            f"Each is rendered by `vdb_render` ({spp} spp, 320x240, sky 0.25 and a sun of irradiance 3, grey "
            "ground) and compared with the full-resolution render by `vdb_image_compare --foreground` (means "
            "over the pixels where the full-resolution fabric covers more than half the pixel; the last column "
            "compares 8x8-pixel tile means, with less noise).\n\n" + text_table +
            "\nThe naive reductions brighten the fabric: averaging density and S weakens the shadowing "
            "inside the yarns (Fig. 1-2 of the paper). Two lobes keep more of the fibres' anisotropy but not "
            "the shadowing. `vdb_optimize_weights` then scales the two lobes' weights of each cluster (and a "
            "colour scale per cluster) by stochastic gradient descent on restricted mean intensities of "
            "training renders from above under four band 0-1 skies over a ground (docs/optimize.md); this "
            "camera and these lights are not among them. The relative RMSE includes Monte Carlo noise.\n\n"
            + pictures + "\n")
    (folder / "report.md").write_text(text)
    print()
    print(text_table)
    print(f"demo: report written to {folder / 'report.md'}")


if __name__ == "__main__":
    main()
