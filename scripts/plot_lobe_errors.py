#!/usr/bin/python3
"""Plots vdb_lobe_cluster reports (Fig. 16 of the downsampling paper): the relative L2 fit error
against the lobe count m, and the share of voxels for which the §8.1 rule picks each m.
Runs with Debian's python3 and python3-matplotlib.
Usage: plot_lobe_errors.py OUT.png REPORT.json [REPORT.json ...]
"""
import json
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    out, paths = sys.argv[1], [pathlib.Path(p) for p in sys.argv[2:]]
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    width = 0.8 / len(paths)
    for k, path in enumerate(paths):
        r = json.loads(path.read_text())
        name = path.stem.replace("_lobes", "")
        m = [e["lobes"] for e in r["error_by_lobes"]]
        left.plot(m, [e["relative_l2_error"] for e in r["error_by_lobes"]], marker="o", label=name)
        share = [100 * e["voxels_fitted_with"] / r["voxels"] for e in r["error_by_lobes"]]
        right.bar([x + (k - (len(paths) - 1) / 2) * width for x in m], share, width, label=name)
    left.set(xlabel="lobes m", ylabel="relative L2 error of the whole medium", yscale="log",
             title="fit error against lobe count")
    left.set_xticks(m)
    left.grid(True, which="both", alpha=0.3)
    left.legend()
    right.set(xlabel="lobes m", ylabel="% of occupied voxels", title="lobe count chosen per voxel (§8.1 rule)")
    right.set_xticks(m)
    right.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main()
