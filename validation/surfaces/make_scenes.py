#!/usr/bin/env python3
"""Writes the 3D surface scenes of issue 33 (validation/surfaces/scenes).

Three bodies, E = 1 Pa (the FEM's), nu = 1/4, n points through the smallest
dimension H = 0.04 m (spacing H/n, horizon 3.015 spacings), both models:

* bar: [0, 0.24] x [0, H] x [0, H], grips of three point layers beyond each end
  (x < 0 held, x > 0.24 moved 1e-4 m along x, both clamped laterally);
* cantilever: [0, 0.20] x [0, H] x [0, H], root grip x < 0 held, a traction of
  total 1 N along -z on the face x = 0.20 (dhpd puts it on the outermost layer);
* plate: [0, 0.16] x [0, 0.16] x [0, H] with a through hole of radius 0.04 m
  along z through (0.08, 0.08), grips beyond x = 0 and x = 0.16 as the bar's.

The FEM (fem/fem_surfaces3d.py) models the same bodies with the grips as
clamped faces and the tip load as a body force over the outermost cell layer.

Run:  python3 validation/surfaces/make_scenes.py
"""
import os

H = 0.04
HERE = os.path.dirname(os.path.abspath(__file__))
N = {"bond_based": [4, 6, 8, 12, 16], "shear": [4, 6, 8, 12]}
U = 1e-4


def header(name, kind, what):
    model = 'kind = "shear"\n' if kind == "shear" else ""
    return f"""# {what}
# Issue 33 (validation/surfaces/README.md); FEM reference: fem/reference_surfaces3d.json.
name = "{name}"

[model]
dimension = "3d"
{model}
[materials.solid]
youngs_modulus = 1.0
poisson_ratio = 0.25

[output]
vtu = false
"""


def region(lo, hi, dx):
    return f"""
[[regions]]
material = "solid"
spacing = {dx!r}
box = {{ min = {lo}, max = {hi} }}
"""


def grip(name, lo, hi, ux):
    return f"""
[[boundary]]
name = "{name}"
box = {{ min = {lo}, max = {hi} }}
displacement = {{ x = {ux!r}, y = 0.0, z = 0.0 }}
"""


def bar(kind, n):
    dx = H / n
    L = 0.24
    g = 3 * dx
    name = f"bar_{kind}_n{n}"
    s = header(name, kind, f"Bar in tension, {n} points through {H} m, {kind} model.")
    s += region([-g, 0.0, 0.0], [L + g, H, H], dx)
    s += grip("left", [-g - 1, -1, -1], [0.0, 1, 1], 0.0)
    s += grip("right", [L, -1, -1], [L + g + 1, 1, 1], U)
    return name, s


def cantilever(kind, n):
    dx = H / n
    L = 0.20
    g = 3 * dx
    name = f"cantilever_{kind}_n{n}"
    s = header(name, kind, f"Cantilever under a tip load, {n} points through {H} m, {kind} model.")
    s += region([-g, 0.0, 0.0], [L, H, H], dx)
    s += grip("root", [-g - 1, -1, -1], [0.0, 1, 1], 0.0)
    s += f"""
[[loads]]
name = "tip"
kind = "traction"
face = "+x"
value = [0.0, 0.0, {-1.0 / (H * H)!r}]
"""
    return name, s


def plate(kind, n):
    dx = H / n
    W = 0.16
    g = 3 * dx
    name = f"plate_{kind}_n{n}"
    s = header(name, kind, f"Thick plate with a through hole, {n} points through {H} m, {kind} model.")
    s += region([-g, 0.0, 0.0], [W + g, W, H], dx)
    s += f"""
[[holes]]
center = [0.08, 0.08, 0.0]
axis = [0.0, 0.0, 1.0]
radius = 0.04
"""
    s += grip("left", [-g - 1, -1, -1], [0.0, 1, 1], 0.0)
    s += grip("right", [W, -1, -1], [W + g + 1, 1, 1], U)
    return name, s


def main():
    out = os.path.join(HERE, "scenes")
    os.makedirs(out, exist_ok=True)
    for kind, ns in N.items():
        for n in ns:
            for make in (bar, cantilever, plate):
                name, text = make(kind, n)
                with open(os.path.join(out, name + ".toml"), "w") as fh:
                    fh.write(text)


if __name__ == "__main__":
    main()
