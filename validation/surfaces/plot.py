#!/usr/bin/env python3
"""Plots results/study.json (written by study.py): stiffness error against the
FEM versus points through the thickness, and versus run time, for the three 3D
cases, both models, corrected (dhpd's defaults) and uncorrected.

    python3 validation/surfaces/plot.py    # writes results/error_vs_n.png, results/error_vs_time.png
"""
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
CASES = ["bar", "cantilever", "plate"]
STYLE = {
    ("bond_based", "corrected"): ("C0", "-o", "bond-based, surface correction"),
    ("bond_based", "plain"): ("C0", ":x", "bond-based, none"),
    ("shear", "corrected"): ("C3", "-s", "shear, energy formulation"),
    ("shear", "plain"): ("C3", ":+", "shear, paper's force"),
}


def series(results, case, kind, variant):
    rows = []
    for key, r in results.items():
        c, k, n, v = key.split("/")
        if (c, k, v) == (case, kind, variant) and "error_vs_fem" in r:
            rows.append((int(n[1:]), 100 * r["error_vs_fem"], r["seconds"]))
    return sorted(rows)


def main():
    results = json.load(open(os.path.join(HERE, "results", "study.json")))
    for xaxis, name in [(0, "error_vs_n"), (2, "error_vs_time")]:
        fig, axes = plt.subplots(1, 3, figsize=(13, 4), sharey=False)
        for ax, case in zip(axes, CASES):
            for (kind, variant), (colour, style, label) in STYLE.items():
                rows = series(results, case, kind, variant)
                if rows:
                    ax.plot([r[xaxis] for r in rows], [abs(r[1]) for r in rows],
                            style, color=colour, label=label)
            ax.axhline(2.0, color="grey", lw=0.8, ls="--")
            ax.set_yscale("log")
            ax.set_xscale("log")
            ax.set_title(case)
            ax.set_xlabel("points through the thickness" if xaxis == 0 else "run time (s)")
            ax.set_ylabel("|stiffness error| vs FEM (%)")
        axes[0].legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(HERE, "results", name + ".png"), dpi=110)


if __name__ == "__main__":
    main()
