#!/usr/bin/env python3
"""FEM reference (scikit-fem, P2 triangles) for the 2D bimaterial strip.

Problem (linear elasticity, plane stress, thickness 1 m, SI units):
  domain    x in [a, b], y in [0, H], a = 0.025, b = 0.9725, H = 0.1
            (the PD body [0,1]x[0,0.1] minus its rigid constrained layers;
            a and b are the centres of the innermost constrained PD points)
  material  E1 = 1 for x < 0.5, E2 = 2 for x > 0.5, nu = 1/3 in both;
            every element takes E from its centroid, the mesh has a node
            line (element edges) on the interface x = 0.5
  BCs       x = a: u_x = u_y = 0;  x = b: u_x = 1e-4, u_y free;
            y = 0 and y = H traction-free; no body force
Structured meshes (MeshTri.init_tensor) with nominal size h are solved for a
sequence of h; the finest one is sampled on a regular grid and a centreline
and written, with the convergence history, to reference.json.

The reaction R_x at x = b is the x-sum of the residual K u - f (f = 0) over
the constrained dofs on x = b.  Sampled values use the P2 solution itself
(no projection): u_x, u_y by interpolation (CellBasis.probes); exx = du_x/dx
from the P2 gradient at the point.  That gradient jumps across element edges
and the sample points mostly are mesh vertices, so exx is the mean over all
elements whose closure holds the point; on the interface x = 0.5 it is the
mean of the left and right one-sided limits.  Points on the outer boundary
are nudged inward by 1e-12*(b-a) so the element finder always succeeds.
solve_time_s is the wall time of assembly + direct solve (scipy SuperLU).

Usage:  python fem_bimaterial_strip.py [--a 0.025] [--b 0.9725] [--out reference.json]
"""
import argparse
import json
import math
import os
import time

import numpy as np
from scipy.spatial import cKDTree
import skfem
from skfem import (Basis, BilinearForm, ElementTriP0, ElementTriP2,
                   ElementVector, MeshTri, asm, condense, solve)
from skfem.helpers import ddot, sym_grad, trace, eye

H, XI, E1, E2, NU, U_RIGHT = 0.1, 0.5, 1.0, 2.0, 1.0 / 3.0, 1e-4
HS = [0.02, 0.01, 0.005, 0.0025, 0.00125]          # nominal element sizes
PROBES = [(0.25, 0.05), (0.5, 0.05), (0.75, 0.05), (0.5, 0.0), (0.75, 0.1)]
DX_GRID, DX_LINE = 0.0025, 0.001


@BilinearForm
def elasticity(u, v, w):
    """Plane-stress Hooke's law with elementwise E (w.E)."""
    eps_u, eps_v = sym_grad(u), sym_grad(v)
    lam, two_mu = w.E * NU / (1 - NU ** 2), w.E / (1 + NU)
    return ddot(two_mu * eps_u + eye(lam * trace(eps_u), 2), eps_v)


def build_mesh(a, b, h):
    n = lambda L: max(1, math.ceil(L / h - 1e-9))
    x = np.concatenate([np.linspace(a, XI, n(XI - a) + 1),
                        np.linspace(XI, b, n(b - XI) + 1)[1:]])
    return MeshTri.init_tensor(x, np.linspace(0.0, H, n(H) + 1))


def solve_level(a, b, h, clamp=True, e2=E2):
    """Solve on the mesh of size h; clamp=False: roller at x = a (u_x = 0,
    u_y = 0 only at (a, H/2)), to separate the clamping effect."""
    mesh = build_mesh(a, b, h)
    basis = Basis(mesh, ElementVector(ElementTriP2()))
    cx = mesh.p[0, mesh.t].mean(axis=0)                 # element centroids
    E = basis.with_element(ElementTriP0()).interpolate(np.where(cx < XI, E1, e2))
    t0 = time.perf_counter()
    K = asm(elasticity, basis, E=E)
    left = basis.get_dofs(lambda x: np.isclose(x[0], a))
    if clamp:
        left = left.all()
    else:
        ly = left.all('u^2')
        pin = ly[np.argmin(np.abs(basis.doflocs[1, ly] - 0.5 * H))]
        left = np.append(left.all('u^1'), pin)
    right_x = basis.get_dofs(lambda x: np.isclose(x[0], b)).all('u^1')
    u = basis.zeros()
    u[right_x] = U_RIGHT
    u = solve(*condense(K, x=u, D=np.concatenate([left, right_x])))
    t_solve = time.perf_counter() - t0
    reaction = float((K @ u)[right_x].sum())            # residual K u - f, f = 0
    return mesh, basis, u, reaction, t_solve


def sample(mesh, basis, u, x, y, a, b):
    """u_x, u_y (CellBasis.probes) and exx, eyy (P2 gradients) at points (x, y).

    The P2 gradient is discontinuous across element edges, and the sample
    points often lie on them (e.g. at mesh vertices), so exx/eyy are the mean
    over all elements whose closure contains the point; on the interface
    x = 0.5 the left and right elements get weight 1/2 each (mean of the two
    one-sided limits)."""
    d = 1e-12 * (b - a)                                  # nudge off the boundary
    pts = np.vstack([np.clip(np.asarray(x, float), a + d, b - d),
                     np.clip(np.asarray(y, float), d, H - d)])
    (ux_d, bx), (uy_d, by) = basis.split(u)             # scalar P2 components
    # u: probes, chunked because skfem's element finder is O(npts^2) per call
    ux = np.concatenate([bx.probes(pts[:, i:i + 256]) @ ux_d for i in range(0, pts.shape[1], 256)])
    uy = np.concatenate([by.probes(pts[:, i:i + 256]) @ uy_d for i in range(0, pts.shape[1], 256)])
    # gradients: all elements containing each point among the 16 nearest centroids
    cen = mesh.p[:, mesh.t].mean(axis=1)
    cand = cKDTree(cen.T).query(pts.T, 16)[1]           # (npts, 16)
    P = np.repeat(pts, cand.shape[1], axis=1)[:, :, None]
    X = bx.mapping.invF(P, tind=cand.ravel())           # reference coords
    inside = ((X[0] >= -1e-11) & (X[1] >= -1e-11) & (1 - X[0] - X[1] >= -1e-11))[:, 0]
    inside = inside.reshape(cand.shape)
    assert inside.any(axis=1).all(), "sample point outside mesh"
    n = lambda m: np.maximum(m.sum(axis=1, keepdims=True), 1)
    left = inside & (cen[0, cand] < XI)
    right = inside & ~left
    w = inside / n(inside)                               # mean over elements
    on_if = np.isclose(pts[0], XI, rtol=0, atol=1e-12)
    w[on_if] = (0.5 * left / n(left) + 0.5 * right / n(right))[on_if]

    def grad(bs, ud, i):                                 # weighted d(ud)/dx_i
        g = sum(ud[bs.element_dofs[k, cand.ravel()]]
                * bs.elem.gbasis(bs.mapping, X, k, tind=cand.ravel())[0].grad[i, :, 0]
                for k in range(bs.Nbfun))
        return (w * g.reshape(cand.shape)).sum(axis=1)
    return ux, uy, grad(bx, ux_d, 0), grad(by, uy_d, 1)


def r12(v):
    return float(f"{v:.12g}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--a", type=float, default=0.025)
    ap.add_argument("--b", type=float, default=0.9725)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(
        os.path.abspath(__file__)), "reference.json"))
    args = ap.parse_args()
    a, b = args.a, args.b
    t_start = time.perf_counter()

    r_1d = U_RIGHT / ((XI - a) / (E1 * H) + (b - XI) / (E2 * H))
    print(f"skfem {skfem.__version__}, numpy {np.__version__}")
    print(f"1D series-spring reaction R_1D = {r_1d:.12g}")
    print(f"{'h':>8} {'ndofs':>8} {'R_x':>18} {'R_x/R_1D-1':>12} "
          + " ".join(f"ux({px},{py})".rjust(15) for px, py in PROBES) + "  t_solve[s]")
    conv, prev = [], None
    for h in HS:
        if conv:
            prev = (mesh, basis, u)
        mesh, basis, u, reaction, t_solve = solve_level(a, b, h)
        ux = sample(mesh, basis, u, [p[0] for p in PROBES], [p[1] for p in PROBES], a, b)[0]
        conv.append({"h": h, "ndofs": int(basis.N), "reaction_x": r12(reaction),
                     "ux_probe": {f"x={px},y={py}": r12(v) for (px, py), v in zip(PROBES, ux)},
                     "solve_time_s": round(t_solve, 3)})
        print(f"{h:8.5f} {basis.N:8d} {reaction:18.12e} {reaction / r_1d - 1:12.5e} "
              + " ".join(f"{v:15.9e}" for v in ux) + f"  {t_solve:8.2f}")

    # finest level: equilibrium check, int sigma_xx dy over a section = R_x
    ys = (np.arange(4000) + 0.5) * H / 4000             # midpoint rule in y
    for xs in (0.25, 0.75):
        _, _, exx, eyy = sample(mesh, basis, u, np.full_like(ys, xs), ys, a, b)
        Ex = E1 if xs < XI else E2
        fx = (Ex / (1 - NU ** 2) * (exx + NU * eyy)).sum() * H / 4000
        print(f"  equilibrium: int sigma_xx dy at x={xs} = {fx:.10e} (R_x = {reaction:.10e})")

    r_roll = solve_level(a, b, HS[-2], clamp=False)[3]
    r_homog = solve_level(a, b, HS[1], clamp=False, e2=E1)[3]
    print(f"  solver check, E2 = E1 with roller (h={HS[1]}): R_x / (E1 H u_right/(b-a)) - 1 = "
          f"{r_homog / (E1 * H * U_RIGHT / (b - a)) - 1:.2e}")
    r_clamp = conv[-2]["reaction_x"]
    print(f"  roller left edge (h={HS[-2]}): R_x = {r_roll:.12g}, R_x/R_1D - 1 = "
          f"{r_roll / r_1d - 1:.6e}; clamping adds {r_clamp / r_roll - 1:.6e}")

    nx = int(round((b - a) / DX_GRID)) + 1
    ny = int(round(H / DX_GRID)) + 1
    gx, gy = a + DX_GRID * np.arange(nx), DX_GRID * np.arange(ny)
    X, Y = np.meshgrid(gx, gy)                            # rows indexed by y
    gux, guy, gexx = (f.reshape(ny, nx) for f in
                      sample(mesh, basis, u, X.ravel(), Y.ravel(), a, b)[:3])
    # field error indicator: finest minus previous level on the grid
    for name, f, g in zip(("ux", "uy", "exx"), (gux, guy, gexx),
                          sample(*prev, X.ravel(), Y.ravel(), a, b)[:3]):
        e = np.abs(f.ravel() - g)
        far = (X.ravel() - a > 0.05) & (X.ravel() - a < b - a - 0.05)  # >0.05 from x=a, b
        print(f"  grid |{name}(h={HS[-1]}) - {name}(h={HS[-2]})|: max {e.max():.3e}, "
              f"99th pct {np.percentile(e, 99):.3e}, max for 0.05<x-a<b-a-0.05 "
              f"{e[far].max():.3e}; max|{name}| = {np.abs(f).max():.4e}")
    nl = int(round((b - a) / DX_LINE)) + 1
    lx = a + DX_LINE * np.arange(nl)
    lux, _, lexx, _ = sample(mesh, basis, u, lx, np.full(nl, 0.5 * H), a, b)

    tolist = lambda arr: [[r12(v) for v in row] for row in arr]
    out = {
        "description": "scikit-fem P2 plane-stress FEM reference for the bimaterial strip "
                       "[a,b]x[0,0.1]: E=1 (x<0.5), E=2 (x>0.5), nu=1/3; u=0 at x=a, "
                       "u_x=1e-4 (u_y free) at x=b. Fields from the finest mesh; u by "
                       "interpolation (probes); exx = du_x/dx evaluated from the P2 gradient "
                       "at the point (mean over the elements sharing the point, mean of the "
                       "one-sided limits at x=0.5); boundary points nudged inward by "
                       "1e-12*(b-a).",
        "generator": "fem_bimaterial_strip.py",
        "skfem_version": skfem.__version__,
        "problem": {"a": a, "b": b, "height": H, "interface_x": XI, "E1": E1, "E2": E2,
                    "nu": NU, "plane": "stress", "thickness": 1.0, "u_right": U_RIGHT},
        "convergence": conv,
        "reaction_x": conv[-1]["reaction_x"],
        "reaction_x_est_error": r12(abs(conv[-1]["reaction_x"] - conv[-2]["reaction_x"])),
        "grid": {"x0": a, "dx": DX_GRID, "nx": nx, "y0": 0.0, "dy": DX_GRID, "ny": ny,
                 "ux": tolist(gux), "uy": tolist(guy), "exx": tolist(gexx)},
        "centerline": {"y": 0.5 * H, "x": [r12(v) for v in lx],
                       "ux": [r12(v) for v in lux], "exx": [r12(v) for v in lexx]},
    }
    with open(args.out, "w") as f:
        json.dump(out, f)
    print(f"R_x(finest) = {reaction:.12g}, est. error {out['reaction_x_est_error']:.3g}, "
          f"R_x/R_1D - 1 = {reaction / r_1d - 1:.6e}")
    print(f"wrote {args.out}; total runtime {time.perf_counter() - t_start:.1f} s")


if __name__ == "__main__":
    main()
