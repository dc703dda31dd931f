#!/usr/bin/env python3
"""Figures of the fracture validation (validation/fracture/README.md).

Reads the CSV files that `cargo run --release --example fracture_study -- ...`
writes into results/ and the FEM reference in fem/; writes
  lefm.png            peak load / LEFM against delta/a, m = 3 and 4, both models
  curves.png          load-displacement curves of the three strategies with the LEFM path
  damage.png          damage maps: mode I (DH-PD band), shear grip, inclined crack
  error_vs_time.png   peak-load error against run time, both models

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


def energy_factor(model, m):
    """sqrt(dissipated / (G0 A)) of the full-separation runs at this m (mean)."""
    vals = [float(r["dissipated_over_g0a"]) for r in rows(f"energy_{model}.csv")
            if abs(float(r["m"]) - m) < 0.1]
    return (sum(vals) / len(vals)) ** 0.5 if vals else None


def plot_lefm():
    fig, ax = plt.subplots(figsize=(6, 4))
    for model, marker in (("bond_based", "o"), ("shear", "s")):
        data = rows(f"lefm_{model}.csv")
        for m, colour in ((3.015, "C0"), (4.015, "C1")):
            pts = sorted((float(r["delta_over_a"]), float(r["peak"]) / float(r["lefm"]))
                         for r in data if abs(float(r["m"]) - m) < 0.1)
            if not pts:
                continue
            style = "-" if model == "bond_based" else "--"
            ax.plot([p[0] for p in pts], [p[1] for p in pts], style, marker=marker,
                    color=colour, label=f"{model.replace('_', '-')}, m = {m:.0f}")
            factor = energy_factor(model, m)
            if factor and model == "bond_based":
                ax.axhline(factor, color=colour, lw=0.8, ls=":",
                           label=f"LEFM with the dissipated energy, m = {m:.0f}")
    ax.axhline(1.0, color="k", lw=1, label="LEFM (FEM, clamped grips), G$_0$")
    ax.set_xscale("log")
    ax.set_xlabel("δ / a")
    ax.set_ylabel("peak load / LEFM critical load")
    ax.invert_xaxis()
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "lefm.png"), dpi=120)


def plot_curves():
    fig, ax = plt.subplots(figsize=(6, 4))
    data = rows("strategies.csv")
    for k, r in enumerate(data):
        label = f"{r['strategy']} {r['steps']}".strip()
        name = r.get("curve", "")
        path = os.path.join(RESULTS, name) if name else None
        if not path or not os.path.exists(path):
            continue
        with open(path) as f:
            curve = list(csv.DictReader(f))
        ax.plot([1e6 * float(c["displacement"]) for c in curve],
                [1e-3 * float(c["reaction_top_y"]) for c in curve],
                lw=0.8, color=f"C{k}", label=label)
    a, p, d = lefm_path()
    ax.plot([1e6 * x for x in d], [1e-3 * x for x in p], "k--", lw=1.2,
            label="LEFM path (FEM, G$_0$), a/W = 0.2 … 0.9")
    ax.set_xlabel("grip displacement [µm]")
    ax.set_ylabel("reaction [kN per m thickness]")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "curves.png"), dpi=120)


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


def plot_error_vs_time():
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharex=True)
    for model, marker in (("bond_based", "o"), ("shear", "s")):
        data = rows(f"lefm_{model}.csv")
        for m, colour in ((3.015, "C0"), (4.015, "C1")):
            pts = sorted((float(r["seconds"]), float(r["peak"]) / float(r["lefm"]), r["delta_over_a"])
                         for r in data if abs(float(r["m"]) - m) < 0.1)
            if not pts:
                continue
            style = "-" if model == "bond_based" else "--"
            label = f"{model.replace('_', '-')}, m = {m:.0f}"
            factor = energy_factor(model, m)
            for ax, scale in ((axes[0], 1.0), (axes[1], factor)):
                if scale is None:
                    continue
                ax.plot([p[0] for p in pts], [100 * (p[1] / scale - 1) for p in pts], style,
                        marker=marker, color=colour, label=label)
                for t, ratio, da in pts:
                    ax.annotate(f"δ/a={float(da):.2f}", (t, 100 * (ratio / scale - 1)), fontsize=6)
    axes[0].set_title("against LEFM with G$_0$", fontsize=9)
    axes[1].set_title("against LEFM with the energy the model dissipates (Sec. 2)", fontsize=9)
    for ax in axes:
        ax.set_xscale("log")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_xlabel("run time to 70 % past the peak [s] (2 cores)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("peak load / LEFM − 1 [%]")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "error_vs_time.png"), dpi=120)


if __name__ == "__main__":
    plot_lefm()
    plot_curves()
    plot_damage()
    plot_error_vs_time()
    print("figures written to", HERE)
