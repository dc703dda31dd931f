#!/usr/bin/env python3
"""Plot the bimaterial bar / strip validation (CSVs in results/) to bimaterial.png.

(a), (b)  1D bar, spacing 0.01/0.005 and 0.005/0.01 (left/right): u(x) of DH-PD
          (dual horizons) and the constant-horizon baseline against the exact
          series-spring solution, with the error (u - u_exact)/u_R in % below.
(c)       2D strip, u_x along the centre line for refinements r = 1, 3, 5 against
          the FEM reference, with the error (u_x - u_x_fem)/u_R in % below.
(d)       2D strip, e_xx along the centre line.  DH-PD strain = central
          differences of u_x along x within each row of points, never across the
          interface x = 0.5; one-sided at the row ends (next to the interface and
          next to the supports).  The inset zooms on the interface.
The strip CSVs hold the two rows of points that straddle y = 0.05 in each half;
they are averaged by x.  u_R = 1e-4 m is the applied displacement.
FEM strain: drawn from the reference centre line of fem/reference.json
(y = 0.05, step 0.001), one line per material, so that the strain jump at the
interface is not blurred by grid interpolation.

Regenerate (matplotlib pinned in requirements-plot.txt):
    cargo run --release --example bimaterial_bar && python3 validation/bimaterial_bar/plot.py
"""
import json
import os

import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
RES = os.path.join(HERE, "results")
U_R, XI = 1e-4, 0.5
STRIP_COLORS = {1: "tab:orange", 3: "tab:green", 5: "tab:purple"}


def fem_centreline():
    """Supports a, b and the centre-line x, exx of the FEM reference, x = 0.5 dropped."""
    with open(os.path.join(HERE, "fem", "reference.json")) as f:
        ref = json.load(f)
    a, b = ref["problem"]["a"], ref["problem"]["b"]
    x, e = (np.array(ref["centerline"][k]) for k in ("x", "exx"))
    keep = (x != XI) & (x <= b)          # 0.5 holds the mean of the two sides
    return a, b, x[keep], e[keep]


def load(name):
    return np.genfromtxt(os.path.join(RES, name), delimiter=",", names=True)


def by_x(x, *cols):
    """Unique x and the mean of each column over the points sharing that x."""
    xs, inv = np.unique(x, return_inverse=True)
    n = np.bincount(inv)
    return (xs,) + tuple(np.bincount(inv, c) / n for c in cols)


def strip_strain(d):
    """du_x/dx per row (and per side of x = 0.5), then averaged by x."""
    xs, gs = [], []
    for y in np.unique(d["y"]):
        for side in (d["x"] < XI, d["x"] > XI):
            m = (d["y"] == y) & side
            if m.sum() < 2:
                continue
            o = np.argsort(d["x"][m])
            x, u = d["x"][m][o], d["u_x"][m][o]
            xs.append(x)
            gs.append(np.gradient(u, x))    # central inside, one-sided at the ends
    return by_x(np.concatenate(xs), np.concatenate(gs))


def shade(ax, a, b):
    for lo, hi in ((0.0, a), (b, 1.0)):
        ax.axvspan(lo, hi, color="0.85", lw=0)
    ax.axvline(XI, color="0.5", lw=0.8, ls=":")
    ax.set_xlim(0, 1)


def by_side(x, *cols):
    """Insert NaN at x = 0.5 so that lines are not drawn across the interface."""
    i = np.searchsorted(x, XI)
    return (np.insert(x, i, np.nan),) + tuple(np.insert(c, i, np.nan) for c in cols)


def main():
    fig = plt.figure(figsize=(12, 9.5), layout="constrained")
    gs = fig.add_gridspec(4, 2, height_ratios=[2.2, 1.2, 2.2, 1.2])

    # (a), (b): 1D bar
    for col, (tag, title) in enumerate([("coarse_left", "(a) 1D bar, spacing 0.01 | 0.005"),
                                        ("fine_left", "(b) 1D bar, spacing 0.005 | 0.01")]):
        ax, ae = fig.add_subplot(gs[0, col]), fig.add_subplot(gs[1, col])
        for kind, c, m, label in [("dual", "tab:blue", "o", "DH-PD (dual horizons)"),
                                  ("constant", "tab:red", "s", "constant horizon")]:
            d = load(f"bar1d_{tag}_{kind}.csv")
            o = np.argsort(d["x"])
            x, u, ue = d["x"][o], d["u"][o], d["u_exact"][o]
            ax.plot(x, u / U_R, m, ms=3, mfc="none", color=c, label=label)
            ae.plot(x, 100 * (u - ue) / U_R, "-" + m, ms=2.5, lw=1, color=c, label=label)
        ax.plot(x, ue / U_R, "k-", lw=1, label="exact (series springs)")
        a, b = x[2], x[-3]                  # innermost of the 3 held points per end
        for axx in (ax, ae):
            shade(axx, a, b)
        ax.set_title(title, loc="left")
        ax.set_ylabel(r"$u / u_R$")
        ax.legend(loc="upper left", fontsize=8)
        ae.axhline(0, color="k", lw=0.6)
        ae.set_ylabel(r"$(u-u_{exact})/u_R$ [%]")
        ae.set_xlabel("x [m]")

    # (c), (d): 2D strip on the centre line
    strip_a, strip_b, fem_x, fem_exx = fem_centreline()
    ax, ae = fig.add_subplot(gs[2, 0]), fig.add_subplot(gs[3, 0])
    ad = fig.add_subplot(gs[2:, 1])
    zoom = ad.inset_axes([0.07, 0.05, 0.38, 0.42])
    data = {r: load(f"strip2d_r{r}.csv") for r in (1, 3, 5)}
    for r, d in data.items():
        c = STRIP_COLORS[r]
        x, u, uf = by_x(d["x"], d["u_x"], d["u_x_fem"])
        dx = np.diff(x[x < XI])[0]
        label = f"DH-PD r={r} (spacing {dx:.3g} | {dx / 2:.3g})"
        xs, g = strip_strain(d)
        ax.plot(x, u / U_R, ".", ms=2.5 if r > 1 else 4, color=c, label=label)
        ae.plot(*by_side(x, 100 * (u - uf) / U_R), "-", lw=1, color=c, label=f"r={r}")
        for axx in (ad, zoom):
            axx.plot(*by_side(xs, g / 1e-4), ".-", ms=3 if axx is ad else 5, lw=0.7,
                     color=c, label=label)
    x, uf = by_x(data[5]["x"], data[5]["u_x_fem"])
    ax.plot(x, uf / U_R, "k-", lw=1, label="FEM (scikit-fem P2)")
    for axx in (ad, zoom):
        axx.plot(*by_side(fem_x, fem_exx / 1e-4), "k-", lw=1.2, label="FEM (scikit-fem P2)")
    for axx in (ax, ae, ad, zoom):
        shade(axx, strip_a, strip_b)
    ax.set_title("(c) 2D strip, $u_x$ on the centre line y = 0.05", loc="left")
    ax.set_ylabel(r"$u_x / u_R$")
    ax.legend(loc="upper left", fontsize=8)
    ae.axhline(0, color="k", lw=0.6)
    ae.set_ylabel(r"$(u_x-u_{x,FEM})/u_R$ [%]")
    ae.set_xlabel("x [m]")
    ae.legend(loc="upper right", fontsize=8, ncol=3)
    ad.set_title(r"(d) 2D strip, $\varepsilon_{xx}$ on the centre line", loc="left")
    ad.set_ylabel(r"$\varepsilon_{xx}$ [$10^{-4}$]")
    ad.set_xlabel("x [m]")
    ad.legend(loc="lower right", fontsize=8)
    ad.set_ylim(0.0, 2.0)
    zoom.set_xlim(0.47, 0.53)
    zoom.set_ylim(0.5, 2.0)
    zoom.tick_params(labelsize=7)
    zoom.set_title("interface zoom", fontsize=8)
    ad.indicate_inset_zoom(zoom, edgecolor="0.4")

    out = os.path.join(HERE, "bimaterial.png")
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
