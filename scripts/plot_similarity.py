#!/usr/bin/python3
"""Plots of scripts/similarity_experiment.py: the phase functions A and B of the equal-first-moment
test with their altered tables (like Fig. 8a of the similarity paper), and relative RMSE and render
time against alpha (like Fig. 6). Runs with Debian's python3 and python3-matplotlib.
Usage: plot_similarity.py REPORT.json PHASE_TABLES.json OUT.png
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def mu(bins):
    return [-1 + (b + 0.5) * 2 / bins for b in range(bins)]


def main():
    report, tables, out = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), sys.argv[3]
    fig, (phases, speed) = plt.subplots(1, 2, figsize=(11, 4))
    for name, style in [("A", "-"), ("B", "--")]:
        original = tables["originals"][name]
        phases.plot(mu(len(original)), original, "k" + style, label=f"{name}: {tables['titles'][name]}")
    for name, style in [("A", "-"), ("B", "--")]:
        for label, colour in [("algorithm1", "tab:orange"), ("order1", "tab:blue")]:
            t = tables[name][label]
            phases.plot(mu(len(t["table"])), t["table"], style, color=colour,
                        label=f"{name} altered, order {t['order']} (alpha {t['alpha']:g})")
    phases.set(yscale="log", ylim=(1e-3, 100), xlabel="mu = cos(scattering angle)", ylabel="f(mu)",
               title="equal first moments and their altered tables")
    phases.legend(fontsize=7)
    for name, rows in report["speedup"].items():
        alphas = [r["alpha"] for r in rows]
        speed.plot(alphas, [r["relative_rmse"] for r in rows], "o-", label=f"{name}: rel. RMSE at equal spp")
        speed.plot(alphas, [r["seconds"] / rows[0]["seconds"] for r in rows], "s--", label=f"{name}: time / original's")
    speed.set(xlabel="alpha", title="error and render time against alpha")
    speed.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
