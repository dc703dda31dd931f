#!/usr/bin/env python3
"""Bending stress of both models against the exact plane elasticity solution
(issue 33, item 3): a 2D cantilever L = 1 m, H = 0.1 m (plane stress, unit
thickness, E = 1 Pa, nu = 1/3), clamped by a grip of three point layers behind
x = 0, P = 1 N down on the tip face. Away from its ends the exact solution is
sigma_xx = P (L - x) (y - H/2) / I (Timoshenko & Goodier, Sec. 21), I = H^3 / 12.

    python3 validation/surfaces/beam_stress.py scenes   # writes scenes/beam_*.toml
    python3 validation/surfaces/beam_stress.py run      # runs them (target/release/dhpd), prints the table

Measured at the column of points nearest mid-span: the least-squares slope
d(sigma_xx)/dy and the value at the outermost point, against the exact ones.
"""
import csv
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
MODELS = ["bond_based", "shear"]
NS = [5, 10, 20]


def scene(model, n):
    h = 0.1 / n
    kind = 'kind = "shear"\n' if model == "shear" else ""
    return f"""# 2D cantilever, {n} points through H = 0.1 m, {model} model: bending stress against
# sigma_xx = P (L - x) (y - H/2) / I. Issue 33 (validation/surfaces/README.md, beam_stress.py).
name = "beam_{model}_n{n}"

[model]
dimension = "plane_stress"
{kind}
[materials.solid]
youngs_modulus = 1.0
poisson_ratio = 0.3333333333333333

[output]
vtu = false
stress = true

[[regions]]
material = "solid"
spacing = {h!r}
box = {{ min = [{-3 * h!r}, 0.0], max = [1.0, 0.1] }}

[[boundary]]
name = "root"
box = {{ min = [-1.0, -1.0], max = [0.0, 1.0] }}
displacement = {{ x = 0.0, y = 0.0 }}

[[loads]]
name = "tip"
kind = "traction"
face = "+x"
value = [0.0, -10.0]
"""


def errors(points_csv):
    rows = list(csv.DictReader(open(points_csv)))
    x0 = min({float(r["x"]) for r in rows}, key=lambda x: abs(x - 0.5))
    col = [r for r in rows if float(r["x"]) == x0]
    inertia = 0.1**3 / 12
    ys = [float(r["y"]) - 0.05 for r in col]
    ss = [float(r["sxx"]) for r in col]
    slope = sum(a * b for a, b in zip(ys, ss)) / sum(a * a for a in ys) / ((1 - x0) / inertia) - 1
    k = max(range(len(col)), key=lambda i: ys[i])
    top = ss[k] / ((1 - x0) * ys[k] / inertia) - 1
    return slope, top


def main():
    what = sys.argv[1] if len(sys.argv) > 1 else "run"
    scenes = HERE / "scenes"
    if what == "scenes":
        for m in MODELS:
            for n in NS:
                (scenes / f"beam_{m}_n{n}.toml").write_text(scene(m, n))
        return
    dhpd = ROOT / "target" / "release" / "dhpd"
    work = HERE / "work"
    print("| model | n | slope dσxx/dy | outermost point σxx |")
    print("|---|---|---|---|")
    for m in MODELS:
        for n in NS:
            out = work / f"beam_{m}_n{n}"
            subprocess.run([str(dhpd), "run", str(scenes / f"beam_{m}_n{n}.toml"), "--out", str(out)],
                           check=True, capture_output=True)
            slope, top = errors(out / "points.csv")
            print(f"| {m.replace('_', '-')} | {n} | {100 * slope:+.1f} % | {100 * top:+.1f} % |")


if __name__ == "__main__":
    main()
