#!/usr/bin/env python3
"""Summarises the demo's reports as two tables (stdout and FOLDER/report.md)."""
import json
import pathlib
import sys


def load(folder, name):
    return json.loads((folder / name).read_text())


def main():
    folder = pathlib.Path(sys.argv[1])
    make_seconds = float((folder / "make_seconds.txt").read_text())
    downsampled = [load(folder, f"twill_{f}x.json") for f in (2, 4, 8)]
    first = downsampled[0]["input"]
    render = {name: load(folder, f"render_{name}.json") for name in ("twill", "twill_2x", "twill_4x", "twill_8x")}
    rows = [("full resolution", first["active_voxels"], first["memory_bytes"], first["file_bytes"],
             f"made in {make_seconds:.2f} s", render["twill"], None)]
    for r in downsampled:
        s = r["seconds"]
        rows.append((f"naive {r['factor']}x", r["output"]["active_voxels"], r["output"]["memory_bytes"],
                     r["output"]["file_bytes"], f"downsampled in {s['downsample']:.3f} s",
                     render[f"twill_{r['factor']}x"], load(folder, f"compare_{r['factor']}x.json")))
    header = ("| medium | active voxels | memory MB | file MB | made | render s | paths/s | "
              "mean intensity (fabric) | error vs full | relative RMSE |\n"
              "|---|---:|---:|---:|---|---:|---:|---:|---:|---:|\n")
    lines = []
    for name, voxels, memory, size, made, rend, cmp in rows:
        mean = cmp["mean_test"] if cmp else None
        lines.append(f"| {name} | {voxels:,} | {memory / 1e6:.1f} | {size / 1e6:.1f} | {made} | "
                     f"{rend['seconds']:.1f} | {rend['paths_per_second']:.3g} | "
                     + (f"{mean:.4f} | {100 * cmp['mean_relative_error']:+.2f}% | {100 * cmp['relative_rmse']:.1f}% |"
                        if cmp else f"{load(folder, 'compare_2x.json')['mean_reference']:.4f} | reference | |"))
    table = header + "\n".join(lines) + "\n"
    spp = render["twill"]["spp"]
    pictures = "\n\n".join(f"naive {f}x: full | naive | error (red: brighter, blue: darker, saturating at 50%)\n\n"
                           f"![compare {f}x](compare_{f}x.png)" for f in (2, 4, 8))
    text = ("# vdbappear demo\n\nThe default medium (`vdb_make_medium twill --yarns 12`: a 2/2 twill of twisted "
            "fibres, pink warp and yellow weft as in Fig. 9 of the downsampling paper, voxel size "
            f"{first['voxel_size']:.4g}) downsampled naively (Eq. 5-6) with `vdb_sggx_downsample`, each rendered "
            f"by `vdb_render` ({spp} spp, 320x240, sky 0.25 and a sun of irradiance 3, grey ground) and compared "
            "with the full-resolution render by `vdb_image_compare --foreground` (means over the pixels where "
            "the full-resolution fabric covers more than half the pixel).\n\n" + table +
            "\nThe naive reductions brighten the fabric: averaging density and S weakens the shadowing "
            "inside the yarns (Fig. 1-2 of the paper). The relative RMSE includes Monte Carlo noise.\n\n"
            + pictures + "\n")
    (folder / "report.md").write_text(text)
    print()
    print(table)
    print(f"demo: report written to {folder / 'report.md'}")


if __name__ == "__main__":
    main()
