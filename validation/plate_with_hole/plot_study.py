#!/usr/bin/env python3
"""Error against wall time for the plate with a hole (issue 3).

Reads results/study_uniaxial.csv (written by
`cargo run --release --example plate_with_hole`) and the scikit-fem convergence
table in fem/reference.json, and writes study.png:
  left:  relative L2 error of u (interior points) against total wall time;
  right: error of sigma_xx at the top of the hole (shear model; pointwise, first
         row of points) against total wall time.
Lines join the spacings 0.02, 0.01, 0.005 m at a fixed m = delta/dx.
FEM points: each mesh level's assembly + solve time, error against the finest level.

Regenerate:  python3 validation/plate_with_hole/plot_study.py   (matplotlib, see
../bimaterial_bar/requirements-plot.txt)
"""
import csv
import json
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

here = os.path.dirname(os.path.abspath(__file__))
rows = list(csv.DictReader(open(os.path.join(here, "results", "study_uniaxial.csv"))))
fem = json.load(open(os.path.join(here, "fem", "reference.json")))["convergence"]

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
styles = {"bond_based": "o-", "shear": "s--"}
for model in ("bond_based", "shear"):
    for m in sorted({r["m"] for r in rows}):
        sel = sorted((r for r in rows if r["model"] == model and r["m"] == m), key=lambda r: -float(r["dx"]))
        t = [float(r["t_total"]) for r in sel]
        ax1.loglog(t, [100 * float(r["l2_u_interior"]) for r in sel], styles[model], label=f"{model}, m = {m}")
        if model == "shear":
            e = [100 * abs(float(r["sxx_top"]) / float(r["sxx_top_fem"]) - 1) for r in sel]
            ax2.loglog(t, e, styles[model], label=f"shear, m = {m}")
tf = [c["assembly_time_s"] + c["solve_time_s"] for c in fem[:-1]]
ax1.loglog(tf, [100 * max(c["rel_diff_vs_finest_max_abs_u"], 1e-9) for c in fem[:-1]], "k^-", label="scikit-fem P2 (max |u|)")
ax2.loglog(tf, [100 * max(c["rel_diff_vs_finest_sxx_hole_top"], 1e-9) for c in fem[:-1]], "k^-", label="scikit-fem P2")
ax1.set(xlabel="wall time (s)", ylabel="relative L2 error of u, interior (%)", title="displacement")
ax2.set(xlabel="wall time (s)", ylabel="|error| of $\\sigma_{xx}$ at the hole top (%)", title="stress concentration")
for ax in (ax1, ax2):
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
fig.suptitle("Plate with a hole, uniaxial 1 MPa: dhpd (dx = 0.02, 0.01, 0.005 m) against scikit-fem")
fig.tight_layout()
fig.savefig(os.path.join(here, "study.png"), dpi=110)
print("wrote", os.path.join(here, "study.png"))
