#!/usr/bin/env python3
"""Figures of the fracture validation (validation/fracture/README.md).

Reads the CSV files that `cargo run --release --example fracture_study -- ...`
writes into results/ and the FEM reference in fem/; writes
  lefm.png            peak load / LEFM against delta/a, bond-based, three specimens, three calibrations
  curves.png          load-displacement curves of the three strategies with the LEFM path
  damage.png          damage maps: mode I (DH-PD band), shear grip, inclined crack
  kink.png            shear grip: the crack leaving the notch over resolution, m and lattice angle
  error_vs_time.png   peak-load error against run time, both models, three calibrations
  three_d.png         3D notched bars (Sec. 7): reaction per unit depth against grip
                      displacement, with the 3D FEM's critical load
  three_d_front.png   the 107,520-point bar's crack plane at the end of its run: the damage
                      next to y = 0 over x (along the ligament) and z (through the depth)

`python3 validation/fracture/plot.py front OUT/points.csv` first extracts that crack plane
from a run's points.csv into results/front_sent_bond_based_all_n80_m3_3d_depth10mm.csv.

Run from the repository root:  python3 validation/fracture/plot.py
(matplotlib and numpy; see requirements-plot.txt)
"""
import csv
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "results")


def rows(name):
    path = os.path.join(RESULTS, name)
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def lefm_path():
    with open(os.path.join(HERE, "fem", "reference_sent.json")) as f:
        ref = json.load(f)["materials"]["plane_stress_nu_1/3"]
    return ref["a_over_W"], ref["P_c"], ref["delta_c"]


SPECIMENS = (("sent_a50mm", "SENT a/W = 0.5", "o"), ("sent_a30mm", "SENT a/W = 0.3", "^"),
             ("cct_c20mm", "centre crack c/W = 0.2", "s"))


def series(data, specimen, m, calibration, criterion=None):
    """(delta/a, peak/LEFM, seconds) of one specimen, m, calibration (and criterion)."""
    return sorted((float(r["delta_over_a"]), float(r["peak"]) / float(r["lefm"]), float(r["seconds"]))
                  for r in data if r.get("specimen") == specimen and abs(float(r["m"]) - m) < 0.1
                  and r.get("calibration") == calibration
                  and (criterion is None or r.get("criterion") == criterion))


def plot_lefm():
    """Peak / LEFM against delta/a, bond-based, three specimens, three calibrations."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    data = rows("lefm_bond_based.csv")
    for ax, m in zip(axes, (3.015, 4.015)):
        for specimen, label, marker in SPECIMENS:
            for calibration, style in (("dissipation", "-"), ("peak", "--"), ("continuum", ":")):
                pts = series(data, specimen, m, calibration)
                if pts:
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], style, marker=marker,
                            label=f"{label}, {calibration}")
        ax.axhline(1.0, color="k", lw=1)
        ax.axhspan(0.95, 1.05, color="g", alpha=0.08, label="±5 %")
        ax.set_xscale("log")
        ax.invert_xaxis()
        ax.set_title(f"bond-based, m = {m:.0f}", fontsize=9)
        ax.set_xlabel("δ / a")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("peak load / LEFM critical load (FEM, G$_0$)")
    axes[1].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "lefm.png"), dpi=120)


def load_curve(path, per=1.0):
    """Grip displacement [µm] and top reaction [kN] / `per` of a curve file."""
    with open(path) as f:
        curve = list(csv.DictReader(f))
    return ([1e6 * float(c["displacement"]) for c in curve],
            [1e-3 * float(c["reaction_top_y"]) / per for c in curve])


def finish_curves(fig, ax, ylabel, name):
    """Labels, legend and grid of a load-displacement figure; writes it as `name`."""
    ax.set_xlabel("grip displacement [µm]")
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, name), dpi=120)


def plot_curves():
    fig, ax = plt.subplots(figsize=(6, 4))
    data = rows("strategies.csv")
    for k, r in enumerate(data):
        label = f"{r['strategy']} {r['steps']}".strip()
        name = r.get("curve", "")
        path = os.path.join(RESULTS, name) if name else None
        if not path or not os.path.exists(path):
            continue
        ax.plot(*load_curve(path), lw=0.8, color=f"C{k}", label=label)
    a, p, d = lefm_path()
    ax.plot([1e6 * x for x in d], [1e-3 * x for x in p], "k--", lw=1.2,
            label="LEFM path (FEM, G$_0$), a/W = 0.2 … 0.9")
    finish_curves(fig, ax, "reaction [kN per m thickness]", "curves.png")


def plot_damage():
    maps = [(n, t) for n, t in (
        ("damage_sent_bond_based_event_n80_m3_band12.csv", "mode I, DH-PD fine band"),
        ("damage_sent_bond_based_event_n40_m3_shear_loading.csv", "shear grip, bond-based"),
        ("damage_sent_shear_event_n40_m3_shear_loading.csv", "shear grip, shear model"),
        ("damage_sent_bond_based_event_n60_m3_inclined.csv", "inclined crack, bond-based"),
        ("damage_sent_shear_event_n40_m3_inclined.csv", "inclined crack, shear model"),
    ) if os.path.exists(os.path.join(RESULTS, n))]
    if not maps:
        return
    fig, axes = plt.subplots(1, len(maps), figsize=(2.6 * len(maps), 4.6))
    axes = axes if len(maps) > 1 else [axes]
    for ax, (name, title) in zip(axes, maps):
        data = rows(name)
        ax.scatter([float(r["x"]) for r in data], [float(r["y"]) for r in data],
                   c=[float(r["damage"]) for r in data], s=2, cmap="Reds",
                   vmin=0, vmax=0.5, rasterized=True)
        # The pre-crack (its bonds were never there, so it shows no damage).
        if "inclined" in name:
            h = 0.015 / 2 ** 0.5
            ax.plot([0.05 - h, 0.05 + h], [-h, h], "b-", lw=1)
        else:
            ax.plot([0.0, 0.05], [0.0, 0.0], "b-", lw=1)
        ax.set_aspect("equal")
        ax.set_ylim(-0.1, 0.1)
        ax.set_title(title, fontsize=8)
        ax.tick_params(labelsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "damage.png"), dpi=130)


def plot_kink():
    """Shear grip, bond-based: damage near the notch tip over delta/a, m and the
    lattice's orientation, with the MTS direction (-70.5 deg) and the fitted kink."""
    import math
    kinks = {(r["model"], r["cells"], r["m"], r["lattice_deg"]): float(r["kink_deg"])
             for r in rows("kink.csv") if r["case"] == "shear grip"}
    cases = [(model, cells, m, lat) for (model, cells, m, lat) in kinks if model == "bond_based"]
    if not cases:
        return
    fig, axes = plt.subplots(2, (len(cases) + 1) // 2, figsize=(2.6 * ((len(cases) + 1) // 2), 5.6))
    for ax, (model, cells, m, lat) in zip(axes.flat, cases):
        name = f"sent_{model}_event_n{cells}_m{int(float(m))}_shear_loading"
        if float(lat) != 0.0:
            name += f"_lattice{lat}deg".replace(".", "p")
        data = rows(f"damage_{name}.csv")
        near = [r for r in data if 0.04 < float(r["x"]) < 0.09 and -0.045 < float(r["y"]) < 0.005]
        ax.scatter([float(r["x"]) for r in near], [float(r["y"]) for r in near],
                   c=[float(r["damage"]) for r in near], s=1.5, cmap="Reds", vmin=0, vmax=0.5,
                   rasterized=True)
        for angle, style in ((-70.5, "b--"), (kinks[(model, cells, m, lat)], "k-")):
            t = math.radians(angle)
            ax.plot([0.05, 0.05 + 0.04 * math.cos(t)], [0.0, 0.04 * math.sin(t)], style, lw=0.8)
        ax.plot([0.04, 0.05], [0.0, 0.0], "b-", lw=1)
        ax.set_xlim(0.04, 0.09)
        ax.set_ylim(-0.045, 0.005)
        ax.set_aspect("equal")
        ax.set_title(f"W/dx = {cells}, m = {float(m):.0f}, lattice {float(lat):g}°\n"
                     f"kink {kinks[(model, cells, m, lat)]:.1f}° (MTS -70.5°)", fontsize=7)
        ax.tick_params(labelsize=5)
    for ax in list(axes.flat)[len(cases):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "kink.png"), dpi=130)


def plot_error_vs_time():
    """|peak / LEFM - 1| against run time: both models, three calibrations, every specimen."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    cases = [("bond_based", None, "bond-based")] + [("shear", c, f"shear, {c}") for c in ("energy", "deviatoric")]
    colours = iter(f"C{k}" for k in range(20))
    for model, criterion, name in cases:
        data = rows(f"lefm_{model}.csv")
        for calibration, fill in (("dissipation", "full"), ("peak", "left"), ("continuum", "none")):
            colour = next(colours)
            first = True
            for specimen, _, marker in SPECIMENS:
                for m in (3.015, 4.015):
                    pts = series(data, specimen, m, calibration, criterion)
                    if not pts:
                        continue
                    ax.plot([p[2] for p in pts], [100 * abs(p[1] - 1) for p in pts], "-",
                            marker=marker, fillstyle=fill, color=colour, lw=0.8,
                            label=f"{name}, {calibration}" if first else None)
                    first = False
    ax.axhline(5.0, color="k", lw=0.8, ls="--", label="target 5 %")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("run time to 70 % past the peak [s] (shared 2-core machine)")
    ax.set_ylabel("|peak load / LEFM − 1| [%]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "error_vs_time.png"), dpi=120)


# (curve file, label, depth [m]) of Sec. 7; the bond-based ones with the default
# (dissipation) calibration, the shear model's with the continuum value.
THREE_D = (
    ("curve_sent_bond_based_event_n20_m3_3d_depth20mm.csv", "bond-based, W/20, T = 20 mm", 0.02),
    ("curve_sent_bond_based_event_n30_m3_3d_depth30mm.csv", "bond-based, W/30, T = 30 mm", 0.03),
    ("curve_sent_bond_based_event_n20_m3_3d_depth40mm.csv", "bond-based, W/20, T = 40 mm", 0.04),
    ("curve_sent_shear_event_n20_m3_continuum_3d.csv", "shear (continuum), W/20, T = 20 mm", 0.02),
    ("curve_sent_bond_based_all_n80_m3_3d_depth10mm.csv",
     "bond-based, W/80, T = 10 mm (107,520 points, all)", 0.01),
    ("curve_sent_bond_based_all_n50_m3_3d_depth40mm.csv",
     "bond-based, W/50, T = 40 mm (120,000 points, all)", 0.04),
)


def plot_three_d():
    with open(os.path.join(HERE, "fem", "reference_sent3d.json")) as f:
        fem = json.load(f)["results"]
    fig, ax = plt.subplots(figsize=(6, 4))
    for k, (name, label, depth) in enumerate(THREE_D):
        path = os.path.join(RESULTS, name)
        if not os.path.exists(path):
            continue
        ax.plot(*load_curve(path, per=depth), lw=0.9, color=f"C{k}", label=label)
    for nu, style in (("nu_1/4", "k--"), ("nu_1/3", "k:")):
        p_c = [fem[t][nu]["P_c_per_depth"] for t in ("T_0.02", "T_0.04")]
        ax.axhline(1e-3 * sum(p_c) / 2, color="k", ls=style[1:], lw=1.0,
                   label=f"3D FEM critical load, ν = {nu[3:]} (T = 20-40 mm)")
    finish_curves(fig, ax, "reaction per unit depth [kN/m]", "three_d.png")


FRONT = "front_sent_bond_based_all_n80_m3_3d_depth10mm.csv"


def extract_front(points_csv):
    """The damage of the two point layers next to the crack plane y = 0 (the larger of
    the two at each x, z) from a run's points.csv, into results/FRONT."""
    damage = {}
    with open(points_csv) as f:
        for p in csv.DictReader(f):
            y = float(p["y"])
            if abs(y) < 1e-3:  # the layers at y = ±Δx/2 (Δx = 1.25 mm)
                key = (round(float(p["x"]), 7), round(float(p["z"]), 7))
                damage[key] = max(damage.get(key, 0.0), float(p["damage"]))
    with open(os.path.join(RESULTS, FRONT), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["x", "z", "damage"])
        for (x, z), d in sorted(damage.items()):
            w.writerow([x, z, f"{d:.6f}"])


def plot_three_d_front():
    data = rows(FRONT)
    if not data:
        return
    xs = sorted({float(r["x"]) for r in data})
    zs = sorted({float(r["z"]) for r in data})
    grid = [[0.0] * len(xs) for _ in zs]
    for r in data:
        grid[zs.index(float(r["z"]))][xs.index(float(r["x"]))] = float(r["damage"])
    fig, ax = plt.subplots(figsize=(7, 1.9))
    h = 0.5 * (xs[1] - xs[0])
    image = ax.imshow(grid, origin="lower", aspect="auto", cmap="magma_r", vmin=0, vmax=1,
                      extent=(1e3 * (xs[0] - h), 1e3 * (xs[-1] + h),
                              1e3 * (zs[0] - h), 1e3 * (zs[-1] + h)))
    ax.axvline(50.0, color="w", lw=0.8, ls="--")
    ax.set_xlabel("x [mm] (notch tip at 50 mm)")
    ax.set_ylabel("z [mm]")
    ax.set_title("3D bar, 107,520 points: damage next to the crack plane at 90 % past the peak",
                 fontsize=8)
    fig.colorbar(image, ax=ax, label="damage")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "three_d_front.png"), dpi=120)


if __name__ == "__main__":
    import sys
    if len(sys.argv) == 3 and sys.argv[1] == "front":
        extract_front(sys.argv[2])
    plot_lefm()
    plot_curves()
    plot_damage()
    plot_kink()
    plot_error_vs_time()
    plot_three_d()
    plot_three_d_front()
    print("figures written to", HERE)
