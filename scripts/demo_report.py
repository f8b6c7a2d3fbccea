#!/usr/bin/env python3
"""Summarises the demo's downsampling reports as a table (stdout and FOLDER/report.md)."""
import json
import pathlib
import sys


def main():
    folder = pathlib.Path(sys.argv[1])
    reports = sorted(folder.glob("twill_*x.json"), key=lambda p: json.loads(p.read_text())["factor"])
    make_seconds = float((folder / "make_seconds.txt").read_text())
    first = json.loads(reports[0].read_text())["input"]
    rows = [("full resolution", first["active_voxels"], first["memory_bytes"], first["file_bytes"],
             f"made in {make_seconds:.2f} s")]
    for path in reports:
        r = json.loads(path.read_text())
        s = r["seconds"]
        rows.append((f"naive {r['factor']}x", r["output"]["active_voxels"], r["output"]["memory_bytes"],
                     r["output"]["file_bytes"],
                     f"read {s['read']:.2f} s, downsample {s['downsample']:.3f} s, write {s['write']:.3f} s"))
    header = "| medium | active voxels | memory MB | file MB | time |\n|---|---:|---:|---:|---|\n"
    table = header + "".join(f"| {n} | {v:,} | {m / 1e6:.1f} | {f / 1e6:.1f} | {t} |\n" for n, v, m, f, t in rows)
    previews = " ".join(f"![{name}]({name}.png)" for name in
                        ["twill"] + [f"twill_{json.loads(p.read_text())['factor']}x" for p in reports])
    text = ("# vdbappear demo\n\nThe default medium (`vdb_make_medium twill`: a 2/2 twill of twisted fibers, "
            "pink warp and yellow weft as in Fig. 9 of the downsampling paper, "
            f"voxel size {first['voxel_size']:.4g}) downsampled naively (Eq. 5-6) with "
            "`vdb_sggx_downsample`.\n\n" + table +
            "\nPreviews (`vdb_preview`: absorption-emission with local shadows, not a renderer), full "
            "resolution then 2x, 4x, 8x:\n\n" + previews + "\n\n"
            "Rendered comparisons (full resolution vs naive, error maps) come with vdb_render.\n")
    (folder / "report.md").write_text(text)
    print()
    print(table)
    print(f"demo: report written to {folder / 'report.md'}")


if __name__ == "__main__":
    main()
