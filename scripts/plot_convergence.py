#!/usr/bin/python3
"""Plots the convergence of vdb_optimize_weights from its JSON-lines log (--log): the error E of
Eq. 14 and every factor against the iteration, as in Fig. 13 of the downsampling paper.
Runs with Debian's python3 and python3-matplotlib.
Usage: plot_convergence.py LOG.jsonl OUT.png [TITLE]
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    log, out = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else log
    entries = [json.loads(line) for line in open(log) if line.strip()]
    if not entries:
        sys.exit(f"{log}: no iterations")
    t = [e["t"] for e in entries]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    left.plot(t, [e["E"] for e in entries], marker="o")
    left.set(xlabel="iteration t", ylabel="E (Eq. 14, at the iteration's start)", title="error")
    left.grid(True, alpha=0.3)
    names = list(entries[0]["factors"].keys())
    for name in names:
        right.plot(t, [e["factors"][name] for e in entries], marker=".", label=name)
    right.set(xlabel="iteration t", ylabel="factor", title="factors w_k,j and colour scales s_k")
    right.grid(True, alpha=0.3)
    right.legend(fontsize="small", ncol=2 if len(names) > 8 else 1)
    for axis in (left, right):
        axis.xaxis.set_major_locator(MaxNLocator(integer=True))
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
