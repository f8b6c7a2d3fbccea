#!/usr/bin/python3
"""Plots of scripts/lightgrid_experiment.py: coefficient (7, 2) along a line with three interpolants
from 10 nodes (like Fig. 5.4 of the dissertation), and the cost of evaluating the grid and of
interpolating 1M points against the number of lights (like Fig. 5.8b). Runs with Debian's python3
and python3-matplotlib.
Usage: plot_lightgrid.py REPORT.json LINE.json OUT.png
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    report, line, out = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), sys.argv[3]
    fig, (curve, cost) = plt.subplots(1, 2, figsize=(11, 4))
    curve.plot(line["x"], line["analytic"], color="tab:blue", lw=2, label="analytic (2000 points)")
    for method, style in [("hermite", "k--"), ("trilinear", "r--"), ("taylor", "c--")]:
        curve.plot(line["x"], line[method], style, lw=1, label=f"{method} from 10 nodes")
    xs = line["nodes"]
    ys = [line["analytic"][min(range(len(line["x"])), key=lambda i: abs(line["x"][i] - x))] for x in xs]
    curve.plot(xs, ys, "o", color="tab:blue")
    curve.set(xlabel="x (y = 0.3, z = 0; square light at z = 1.5)", ylabel="L_7,2", title="coefficient (7, 2) along a line")
    curve.legend(fontsize=7)
    rows = report["scaling"]
    for name, style in [("EvaluateGrid", "o-"), ("InterpolateHermite", "s-"), ("InterpolateTrilinear", "^--")]:
        pts = sorted((r["lights"], r["ms"]) for r in rows if r["benchmark"] == name)
        cost.plot([p[0] for p in pts], [p[1] for p in pts], style, label={"EvaluateGrid": "evaluate 8^3 grid",
                  "InterpolateHermite": "interpolate 1M points (Hermite)", "InterpolateTrilinear": "interpolate 1M points (trilinear)"}[name])
    analytic = sorted((r["lights"], r["ms"] / r["points"] * 1e6) for r in rows if r["benchmark"] == "AnalyticPerPoint")
    if analytic:
        cost.plot([p[0] for p in analytic], [p[1] for p in analytic], "x:", label="analytic SH at 1M points (from the timed subset)")
    cost.set(xscale="log", yscale="log", xlabel="triangle lights", ylabel="ms", title="cost against the number of lights")
    cost.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
