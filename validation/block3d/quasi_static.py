#!/usr/bin/env python3
"""The 3D block of 001 Sec. 6.4 in mode I, grown quasi-statically, against its FEM/LEFM
reference (fem/reference_block.json, written by fem/fem_block.py).

    dhpd run validation/block3d/scenes/mode1_10mm_quasi_static.toml --out OUT
    python3 validation/block3d/quasi_static.py OUT

Copies the run's load-displacement curve to results/, writes
results/mode1_10mm_quasi_static.csv (peak load and opening against LEFM) and
mode1_quasi_static.png (load against opening with the FEM's elastic line and LEFM
path; the crack plane's damage at the end of the run).
"""
import csv
import json
import os
import shutil
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from study import A0, B, D_TH, H, L, read_vtu  # noqa: E402

NAME = "mode1_10mm_quasi_static"
GRIP = 1e-3          # grip displacement at load factor 1 (each grip; the opening is twice it)
SPACING = 0.01


def main(out):
    curve_path = os.path.join(HERE, "results", f"{NAME}_load_displacement.csv")
    shutil.copyfile(os.path.join(out, "load_displacement.csv"), curve_path)
    with open(curve_path) as f:
        rows = list(csv.DictReader(f))
    opening = np.array([2 * GRIP * float(r["load_factor"]) for r in rows])
    load = np.array([float(r["reaction_top_y"]) for r in rows])
    broken = np.array([int(r["broken_total"]) for r in rows])
    summary = json.load(open(os.path.join(out, "summary.json")))
    ref = json.load(open(os.path.join(HERE, "fem", "reference_block.json")))
    fem3d = ref["model_3d"]["free_faces_corrected"]
    peak = int(np.argmax(load))
    first = int(np.argmax(broken > 0))
    elastic = load[first - 1] / opening[first - 1] if first > 0 else np.nan

    # the crack front at the end: per z layer, the largest x of a damaged point beside the plane
    v = read_vtu(os.path.join(out, "points.vtu"))
    p, damage = v["points"], v["damage"]
    band = np.abs(p[:, 1] - H / 2) < SPACING
    fronts = []
    for z in np.unique(np.round(p[band, 2], 6)):
        layer = band & (np.abs(p[:, 2] - z) < 1e-6) & (damage >= D_TH)
        fronts.append(p[layer, 0].max() if layer.any() else A0)

    result = {
        "points": summary["counts"]["points"],
        "nnz_l": summary["counts"]["nnz_l"],
        "elastic_stiffness_N_per_m": elastic,
        "fem_3d_stiffness_N_per_m": fem3d["k_N_per_m"],
        "first_break_opening_mm": 1e3 * opening[first],
        "peak_load_kN": 1e-3 * load[peak],
        "peak_opening_mm": 1e3 * opening[peak],
        "lefm_3d_P_c_kN": 1e-3 * fem3d["P_c"],
        "lefm_3d_opening_mm": 1e3 * fem3d["opening_2v_c"],
        "peak_over_lefm": load[peak] / fem3d["P_c"],
        "final_opening_mm": 1e3 * opening[-1],
        "final_load_kN": 1e-3 * load[-1],
        "final_front_mean_m": float(np.mean(fronts)),
        "bonds_broken": int(broken[-1]),
        "run_seconds": summary.get("total_seconds", np.nan),
    }
    with open(os.path.join(HERE, "results", f"{NAME}.csv"), "w") as f:
        w = csv.writer(f)
        w.writerow(result.keys())
        w.writerow([f"{x:.6g}" if isinstance(x, float) else x for x in result.values()])
    for k, x in result.items():
        print(f"{k:28s} {x}")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.2), gridspec_kw=dict(width_ratios=[1, 1.3]))
    ax.plot(1e3 * opening, 1e-3 * load, "k.-", ms=3, lw=0.8, label="dhpd, shear model, 10 mm")
    s = np.linspace(0, 1e3 * opening.max(), 50)
    ax.plot(s, 1e-3 * fem3d["k_N_per_m"] * s * 1e-3, "b:", lw=0.8, label="FEM 3D, elastic")
    for plane, style in (("stress", "g--"), ("strain", "m--")):
        path = ref["propagation_path_half_model"][plane]
        ax.plot([1e3 * q["opening_2v_c"] for q in path], [1e-3 * q["P_c"] for q in path], style,
                lw=1, label=f"LEFM path (FEM plane {plane}, a = 0.30-0.45 m)")
    ax.plot(1e3 * fem3d["opening_2v_c"], 1e-3 * fem3d["P_c"], "bo", ms=5, label="LEFM initiation, FEM 3D")
    ax.set_xlabel("opening 2v [mm]")
    ax.set_ylabel("load P [kN]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    nx, nz = round(L / SPACING), round(B / SPACING)
    img = np.zeros((nz, nx))
    ix = np.clip((p[band, 0] / SPACING).astype(int), 0, nx - 1)
    iz = np.clip((p[band, 2] / SPACING).astype(int), 0, nz - 1)
    np.maximum.at(img, (iz, ix), damage[band])
    im = bx.imshow(img, origin="lower", extent=[0, L, 0, B], vmin=0, vmax=0.6, cmap="inferno")
    bx.axvline(A0, color="c", lw=0.8, ls="--")
    bx.set_title(f"crack plane at the end (2v = {1e3 * opening[-1]:.2f} mm): damage of the rows beside y = 0.1",
                 fontsize=8)
    bx.set_xlabel("x [m]")
    bx.set_ylabel("z [m]")
    fig.colorbar(im, ax=bx, shrink=0.6, label="damage")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "mode1_quasi_static.png"), dpi=110)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join("/tmp/block3d", NAME))
