#!/usr/bin/python3
"""The log-log plot of make bench-scale: seconds and peak GB against active voxels, one line per command.
Usage: scripts/plot_scale.py scale.json scale.png (Debian's python3-matplotlib)."""
import json
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

COMMANDS = [("make", "vdb_make_medium"), ("downsample_in_core", "downsample, whole"),
            ("downsample_slabs", "downsample, in slabs"), ("vdb_lod_density", "vdb_lod, density"),
            ("lobe_cluster_in_core", "vdb_lobe_cluster, whole"), ("lobe_cluster_slabs", "vdb_lobe_cluster, in slabs"),
            ("render", "vdb_render 64x64, compact"), ("render_full", "vdb_render 64x64, float grids")]


def main():
    rows = json.load(open(sys.argv[1]))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for key, label in COMMANDS:
        points = [(r["active_voxels"], r[key]) for r in rows if key in r]
        if not points:
            continue
        x = [p[0] for p in points]
        axes[0].loglog(x, [p[1][0] for p in points], "o-", label=label)
        axes[1].loglog(x, [p[1][1] for p in points], "o-", label=label)
    for ax, what in zip(axes, ("wall seconds", "peak resident GB")):
        ax.set_xlabel("active voxels")
        ax.set_ylabel(what)
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
