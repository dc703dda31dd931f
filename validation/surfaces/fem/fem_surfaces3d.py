#!/usr/bin/env python3
"""FEM references for the 3D surface cases (issue 33): a bar in tension, a
cantilever under a tip load and a thick plate with a through hole.

Linear elasticity, E = 1 Pa (results scale with E), nu = 1/4 (the bond-based
model's 3D value; the shear model is run at the same nu), small strain, P2
tetrahedra (scikit-fem), direct sparse solve.

Geometry and boundary conditions, chosen to be the continuum of what the PD
scenes (../scenes) discretise: a PD point stands for its cell, so a grip is the
rigid block of the cells it holds and a tip load spread over the outermost
layer of points is a body force over that layer of cells.

* bar: [0, 0.24] x [0, 0.04] x [0, 0.04] m; the faces x = 0 and x = 0.24 are
  clamped to the grips (u = 0 and u = (U, 0, 0)); lateral faces free.
  Stiffness k = F / U, F the grip force. 1/8 model (mid-planes of symmetry;
  u_x = U/2 on x = 0.12).
* cantilever: [0, 0.20] x [0, 0.04] x [0, 0.04] m, clamped on x = 0; a load P
  along -z spread uniformly over the slab x in [L - dx, L] (dx = 0.04/n, the
  PD spacing of n points through the depth: one FEM solve per n). Stiffness
  k = P / w, w = the mean deflection at the PD points of that slab (cell
  centres x = L - dx/2, y, z = (k + 1/2) dx). Half model (y mid-plane).
  The same with the load as a traction on the face x = L and the deflection
  averaged over that face (the "face" convention) is reported too.
* plate: [0, 0.16] x [0, 0.16] x [0, 0.04] m with a through hole of radius
  0.04 m about the z axis through (0.08, 0.08); grips clamp x = 0 and
  x = 0.16 (u = 0 and (U, 0, 0)). Stiffness k = F / U. 1/8 model on an
  O-grid (the hole is a polygon of straight tetrahedron edges; its
  discretisation error falls with the mesh and is in the convergence figure).

Convergence: every case is solved on levels doubling the elements in each
direction; the reference is the finest level, the change from the previous
one is its estimated error (P2: the error falls by ~4-8x per level).

Run:  python3 fem_surfaces3d.py   (writes reference_surfaces3d.json here, ~6 min)
"""
import json
import os
import platform
import time

import numpy as np
import scipy
import scipy.sparse.linalg as sla
import skfem
from skfem import Basis, BilinearForm, ElementTetP2, ElementVector, LinearForm, MeshTet, asm
from skfem.helpers import ddot, sym_grad, trace, eye

E, NU = 1.0, 0.25
LAM = E * NU / ((1 + NU) * (1 - 2 * NU))
MU = E / (2 * (1 + NU))
H = 0.04                       # smallest dimension of every case
N_THROUGH = [4, 6, 8, 12, 16]  # PD points through H the references serve


@BilinearForm
def stiffness(u, v, w):
    eu, ev = sym_grad(u), sym_grad(v)
    return 2 * MU * ddot(eu, ev) + LAM * trace(eu) * trace(ev)


def graded(a, b, n, breaks=()):
    """Nodes on [a, b]: n uniform cells, plus the `breaks` inserted."""
    x = np.linspace(a, b, n + 1)
    return np.unique(np.concatenate([x, [t for t in breaks if a < t < b]]))


def solve(basis, K, f, fixed_dofs, fixed_vals):
    u = np.zeros(basis.N)
    u[fixed_dofs] = fixed_vals
    free = np.setdiff1d(np.arange(basis.N), fixed_dofs)
    rhs = f - K @ u
    A = K[free][:, free].tocsc()
    u[free] = sla.spsolve(A, rhs[free], permc_spec="MMD_AT_PLUS_A")
    return u


def dofs_where(basis, pred, comp):
    """Global dofs of component `comp` whose node lies where `pred(x)` holds."""
    nodal = basis.nodal_dofs[comp]
    facet = basis.facet_dofs[comp] if basis.facet_dofs.size else np.array([], int)
    edge = basis.edge_dofs[comp] if basis.edge_dofs.size else np.array([], int)
    out = []
    m = basis.mesh
    out.append(nodal[pred(m.p)])
    if edge.size:
        mid = 0.5 * (m.p[:, m.edges[0]] + m.p[:, m.edges[1]])
        out.append(edge[pred(mid)])
    return np.unique(np.concatenate(out))


def bar(level):
    L = 0.24
    mesh = MeshTet.init_tensor(graded(L / 2, L, 3 * level), graded(H / 2, H, level),
                               graded(H / 2, H, level))
    basis = Basis(mesh, ElementVector(ElementTetP2()))
    K = asm(stiffness, basis)
    tol = 1e-12
    fixed, vals = [], []
    for comp, pred, val in [
        (0, lambda x: np.abs(x[0] - L / 2) < tol, 0.5),
        (0, lambda x: np.abs(x[0] - L) < tol, 1.0),
        (1, lambda x: np.abs(x[0] - L) < tol, 0.0),
        (2, lambda x: np.abs(x[0] - L) < tol, 0.0),
        (1, lambda x: np.abs(x[1] - H / 2) < tol, 0.0),
        (2, lambda x: np.abs(x[2] - H / 2) < tol, 0.0),
    ]:
        d = dofs_where(basis, pred, comp)
        fixed.append(d)
        vals.append(np.full(d.size, val))
    fixed = np.concatenate(fixed)
    vals = np.concatenate(vals)
    fixed, idx = np.unique(fixed, return_index=True)
    vals = vals[idx]
    u = solve(basis, K, np.zeros(basis.N), fixed, vals)
    grip = dofs_where(basis, lambda x: np.abs(x[0] - L) < tol, 0)
    F_quarter = (K @ u)[grip].sum()
    # 1/8 model: force of the quarter section (x4), elongation of the half (U/2 -> U)
    return {"k": 4 * F_quarter / 1.0, "dofs": int(basis.N)}


def cantilever(level, n):
    L, b = 0.20, H
    dx = H / n
    slab = L - dx
    mesh = MeshTet.init_tensor(graded(0.0, L, 5 * level, [slab]), graded(b / 2, b, level // 2 or 1),
                               graded(0.0, H, level))
    basis = Basis(mesh, ElementVector(ElementTetP2()))
    K = asm(stiffness, basis)
    tol = 1e-12
    P = 1.0
    # half model (y >= b/2): load P/2 on the half slab, volume (b/2) H dx
    q = (P / 2) / ((b / 2) * H * dx)

    @LinearForm
    def body(v, w):
        return -q * v[2] * (w.x[0] > slab + 1e-12 * L)

    f = asm(body, basis)
    fixed = [dofs_where(basis, lambda x: np.abs(x[0]) < tol, c) for c in range(3)]
    fixed.append(dofs_where(basis, lambda x: np.abs(x[1] - b / 2) < tol, 1))
    fixed = np.unique(np.concatenate(fixed))
    u = solve(basis, K, f, fixed, np.zeros(fixed.size))
    # PD points of the slab in the half model: y = b/2 + (k + 1/2) dx, z = (k + 1/2) dx
    cy = b / 2 + (np.arange(n // 2) + 0.5) * dx if n % 2 == 0 else None
    cz = (np.arange(n) + 0.5) * dx
    Y, Z = np.meshgrid(cy, cz, indexing="ij")
    pts = np.vstack([np.full(Y.size, L - dx / 2), Y.ravel(), Z.ravel()])
    w = -(basis.probes(pts) @ u)[2 * Y.size:].mean()
    return {"k": P / w, "dofs": int(basis.N)}


def cantilever_face(level):
    L, b = 0.20, H
    mesh = MeshTet.init_tensor(graded(0.0, L, 5 * level), graded(b / 2, b, level // 2 or 1),
                               graded(0.0, H, level))
    basis = Basis(mesh, ElementVector(ElementTetP2()))
    K = asm(stiffness, basis)
    tol = 1e-12
    P = 1.0
    from skfem import FacetBasis
    fb = FacetBasis(mesh, basis.elem, facets=mesh.facets_satisfying(lambda x: np.abs(x[0] - L) < tol))
    t = (P / 2) / ((b / 2) * H)

    @LinearForm
    def trac(v, w):
        return -t * v[2]

    f = asm(trac, fb)
    fixed = [dofs_where(basis, lambda x: np.abs(x[0]) < tol, c) for c in range(3)]
    fixed.append(dofs_where(basis, lambda x: np.abs(x[1] - b / 2) < tol, 1))
    fixed = np.unique(np.concatenate(fixed))
    u = solve(basis, K, f, fixed, np.zeros(fixed.size))
    # face-average deflection: integrate u_z over the face
    @LinearForm
    def one(v, w):
        return v[2]
    avg = (asm(one, fb) @ u) / ((b / 2) * H)
    return {"k": -P / avg, "dofs": int(basis.N)}


def oplate_map(A, s, R, half, beta=1.5):
    """O-grid of the quarter [0, half]^2 minus the disc of radius R (centre 0)."""
    g = np.expm1(beta * s) / np.expm1(beta)
    th = A * np.pi / 4.0
    cx, cy = R * np.cos(th), R * np.sin(th)
    ox = np.where(A <= 1.0, half, half * (2.0 - A))
    oy = np.where(A <= 1.0, half * A, half)
    return (1 - g) * cx + g * ox, (1 - g) * cy + g * oy


def plate(level):
    W, R, T = 0.16, 0.04, H
    half = W / 2
    mesh = MeshTet.init_tensor(graded(0.0, 2.0, 4 * level), graded(0.0, 1.0, 2 * level),
                               graded(T / 2, T, level))
    A, s, z = mesh.p
    x, y = oplate_map(A, s, R, half)
    mesh = MeshTet(np.vstack([x + half, y + half, z]), mesh.t)
    basis = Basis(mesh, ElementVector(ElementTetP2()))
    K = asm(stiffness, basis)
    tol = 1e-9
    fixed, vals = [], []
    for comp, pred, val in [
        (0, lambda p: np.abs(p[0] - half) < tol, 0.0),
        (1, lambda p: np.abs(p[1] - half) < tol, 0.0),
        (2, lambda p: np.abs(p[2] - T / 2) < tol, 0.0),
        (0, lambda p: np.abs(p[0] - W) < tol, 0.5),
        (1, lambda p: np.abs(p[0] - W) < tol, 0.0),
        (2, lambda p: np.abs(p[0] - W) < tol, 0.0),
    ]:
        d = dofs_where(basis, pred, comp)
        fixed.append(d)
        vals.append(np.full(d.size, val))
    fixed = np.concatenate(fixed)
    vals = np.concatenate(vals)
    # later entries win (the grip's u_y = 0 over the symmetry line's): unique keeps the first
    order = np.arange(fixed.size)[::-1]
    fixed, idx = np.unique(fixed[order], return_index=True)
    vals = vals[order][idx]
    u = solve(basis, K, np.zeros(basis.N), fixed, vals)
    grip = dofs_where(basis, lambda p: np.abs(p[0] - W) < tol, 0)
    F_q = (K @ u)[grip].sum()
    return {"k": 4 * F_q / 1.0, "dofs": int(basis.N)}


def study(name, fn, levels):
    rows = []
    for lv in levels:
        t0 = time.perf_counter()
        r = fn(lv)
        r["level"] = lv
        r["seconds"] = round(time.perf_counter() - t0, 2)
        rows.append(r)
        print(f"{name} level {lv}: k = {r['k']:.8e} ({r['dofs']} dofs, {r['seconds']} s)", flush=True)
    k, prev = rows[-1]["k"], rows[-2]["k"]
    return {"k": k, "estimated_error": abs(k - prev) / abs(k), "levels": rows}


def main():
    t0 = time.perf_counter()
    out = {
        "E": E, "nu": NU, "H": H,
        "software": {"python": platform.python_version(), "numpy": np.__version__,
                     "scipy": scipy.__version__, "scikit-fem": skfem.__version__},
        "cases": {},
    }
    out["cases"]["bar"] = study("bar", bar, [2, 4, 8])
    out["cases"]["plate"] = study("plate", plate, [2, 4, 6])
    out["cases"]["cantilever_face"] = study("cantilever_face", cantilever_face, [2, 4, 8])
    for n in N_THROUGH:
        out["cases"][f"cantilever_n{n}"] = study(f"cantilever n={n}", lambda lv: cantilever(lv, n), [2, 4, 8])
    out["seconds"] = round(time.perf_counter() - t0, 1)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "reference_surfaces3d.json")
    with open(path, "w") as fh:
        json.dump(out, fh, indent=1)
    print("wrote", path)


if __name__ == "__main__":
    main()
