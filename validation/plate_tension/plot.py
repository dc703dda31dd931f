"""Plot the plate-under-tension profiles against the scikit-fem reference.

Reads the CSV files that `cargo run --release --example plate_tension` writes to
`results/` and writes `plate_tension.png` next to this script:

* rows 1-2: u_x along y = 0.5 and its error, normalised by the FEM u_x(1, 0.5);
* rows 3-4: u_y along x = 0.5 and its error, normalised by the FEM max |u_y| on
  that line;
* left column bond-based, right column shear model; one colour per n = δ/Δx.

The y = 0.5 profile uses the row of points just below the line (y = 0.4975 in
region 1, 0.495 in region 2); the row above is its mirror image. The x = 0.5
profile has one column in each region: x = 0.4975 (region 1, Δx = 0.005, lines)
and x = 0.505 (region 2, Δx = 0.01, dots). Every point is compared with the FEM
field interpolated at its own position.

    python3 validation/plate_tension/plot.py      # needs numpy and matplotlib
"""

import csv
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
NS = [2, 3, 4, 5]
MODELS = [("bond_based", "bond-based"), ("shear", "shear")]
COLOURS = {2: "tab:blue", 3: "tab:orange", 4: "tab:green", 5: "tab:red"}


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def main():
    ref = json.loads((HERE / "fem" / "reference.json").read_text())
    ux_tip = ref["ux_at_(1,0.5)"]
    fem_y = ref["profiles"]["y=0.5"]
    fem_x = ref["profiles"]["x=0.5"]
    uy_scale = max(abs(v) for v in fem_x["uy"])

    fig, axes = plt.subplots(
        4, 2, figsize=(13, 14), sharex="row",
        gridspec_kw={"height_ratios": [1.3, 1, 1.3, 1]},
    )
    for col, (model, label) in enumerate(MODELS):
        ax_u, ax_e = axes[0, col], axes[1, col]
        ax_u.plot(fem_y["x"], 1e3 * np.array(fem_y["ux"]), "k-", lw=2.5, label="FEM (scikit-fem P2)")
        for n in NS:
            path = RESULTS / f"{model}_n{n}_ux_y0.5.csv"
            if not path.exists():
                continue
            d = read(path)
            below = d["y"] < 0.5
            x, u, f = d["x"][below], d["u_x"][below], d["u_x_fem"][below]
            ax_u.plot(x, 1e3 * u, "-", color=COLOURS[n], lw=1.2, label=f"n = {n}")
            ax_e.plot(x, 100 * (u - f) / ux_tip, "-", color=COLOURS[n], lw=1.2, label=f"n = {n}")
        ax_u.set_title(f"{label}: u_x along y = 0.5")
        ax_u.set_ylabel("u_x (mm)")
        ax_e.set_ylabel("(u_x − u_x,FEM) / u_x,FEM(1, 0.5)  (%)")
        ax_e.set_xlabel("x (m)")

        ax_u, ax_e = axes[2, col], axes[3, col]
        ax_u.plot(fem_x["y"], 1e3 * np.array(fem_x["uy"]), "k-", lw=2.5, label="FEM (scikit-fem P2)")
        for n in NS:
            path = RESULTS / f"{model}_n{n}_uy_x0.5.csv"
            if not path.exists():
                continue
            d = read(path)
            for side, style, kw in [
                (d["x"] < 0.5, "-", {"lw": 1.2}),
                (d["x"] > 0.5, ".", {"ms": 3}),
            ]:
                y, u, f = d["y"][side], d["u_y"][side], d["u_y_fem"][side]
                lab = f"n = {n}" if style == "-" else None
                ax_u.plot(y, 1e3 * u, style, color=COLOURS[n], label=lab, **kw)
                ax_e.plot(y, 100 * (u - f) / uy_scale, style, color=COLOURS[n], label=lab, **kw)
        ax_u.set_title(f"{label}: u_y along x = 0.5 (lines: x = 0.4975, region 1; dots: x = 0.505, region 2)",
                       fontsize=10)
        ax_u.set_ylabel("u_y (mm)")
        ax_e.set_ylabel("(u_y − u_y,FEM) / max|u_y,FEM|  (%)")
        ax_e.set_xlabel("y (m)")

    for ax in axes.flat:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="best")
    for ax in axes[[1, 3]].flat:
        ax.axhline(0, color="k", lw=0.8)
    for ax in axes[1]:
        ax.axvline(0.5, color="grey", lw=0.8, ls="--")
    fig.suptitle(
        "Plate under tension, two regions (Δx = 0.005 m | 0.01 m, δ = nΔx): DH-PD vs FEM",
        fontsize=13,
    )
    fig.tight_layout()
    out = HERE / "plate_tension.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
