#!/usr/bin/env python3
"""Finite-element reference for the square plate under tension.

Setup (Wang, Oterkus & Oterkus, dual-horizon state-based PD, Sec. 5.1):
  plate [0, 1] x [0, 1] m, linear elastic, E = 200 GPa, nu = 1/3,
  plane stress (``--plane strain`` optional), thickness 1 (displacements of
  the plane-stress problem do not depend on the thickness when the load is a
  traction in Pa), left edge x = 0 fully fixed (u_x = u_y = 0), uniform
  traction 200 MPa in +x on the right edge x = 1, top and bottom free.
  The paper's "two regions" are a PD discretisation device only; the
  continuum (and this FE model) is one homogeneous plate.

Method (scikit-fem):
  * full model, P2 Lagrange triangles (ElementVector(ElementTriP2)) on
    straight-sided cells (the geometry is polygonal, so no geometry error);
  * structured N x N base mesh, each square split into two triangles with
    alternating (chequerboard) diagonals, which is mirror-symmetric about
    y = 0.5 for even N;
  * local refinement toward the two clamped corners (0, 0) and (0, 1),
    where the stresses are singular: K rounds of skfem's adaptive
    (conforming) refinement of the cells within 2.5 local cell sizes of a
    corner, giving h_min = h / 2^K there;
  * direct sparse solve (scipy SuperLU via skfem.solve);
  * mesh-convergence study: base N doubled per level, same K.

Sampling: displacements and stresses are evaluated at arbitrary points by
locating the containing cell and evaluating the P2 field and its gradient
there (no nodal averaging / L2 projection; stresses are the pointwise P2
gradient of the containing cell).  Points on the plate boundary are nudged
into the plate by 1e-12 m.  Stresses near the clamped corners are singular
and are not converged there (see README.md).

Run:  python3 fem_plate_tension.py            (writes reference.json here)
"""
import argparse
import json
import os
import platform
import sys
import time

import numpy as np
import scipy
from scipy.spatial import cKDTree

import skfem
from skfem import (Basis, BilinearForm, ElementTriP2, ElementVector,
                   FacetBasis, LinearForm, MeshTri1, asm, condense, solve)
from skfem.helpers import ddot, eye, sym_grad, trace

WIDTH = 1.0         # plate width (x) [m]
HEIGHT = 1.0        # plate height (y) [m]
E = 200e9           # Young's modulus [Pa]
NU = 1.0 / 3.0      # Poisson's ratio
SIG = 200e6         # traction on x = 1 [Pa]
THICK = 1.0         # thickness [m]
NUDGE = 1e-12       # inward nudge for sample points on boundaries [m]
CORNERS = np.array([[0.0, 0.0], [0.0, HEIGHT]])


def lame(E, nu, plane):
    mu = E / (2.0 * (1.0 + nu))
    if plane == "stress":
        lam = E * nu / (1.0 - nu ** 2)
    else:
        lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    return lam, mu


# --------------------------------------------------------------------------
# mesh
# --------------------------------------------------------------------------
def build_mesh(N, K):
    assert N % 2 == 0
    xs = np.linspace(0.0, WIDTH, N + 1)
    ys = np.linspace(0.0, HEIGHT, N + 1)
    X, Y = np.meshgrid(xs, ys)
    p = np.array([X.ravel(), Y.ravel()])
    idx = lambda i, j: j * (N + 1) + i
    I, J = np.meshgrid(np.arange(N), np.arange(N))
    I, J = I.ravel(), J.ravel()
    v00, v10 = idx(I, J), idx(I + 1, J)
    v11, v01 = idx(I + 1, J + 1), idx(I, J + 1)
    flip = (I + J) % 2 == 1
    t1 = np.where(flip, [v00, v10, v01], [v00, v10, v11])
    t2 = np.where(flip, [v10, v11, v01], [v00, v11, v01])
    mesh = MeshTri1(p, np.hstack([t1, t2]))
    h = WIDTH / N
    for k in range(K):
        hk = h / 2 ** k
        cent = mesh.p[:, mesh.t].mean(axis=1)
        d = np.min([np.hypot(cent[0] - c[0], cent[1] - c[1])
                    for c in CORNERS], axis=0)
        mesh = mesh.refined(np.where(d < 2.5 * hk)[0])
    e = mesh.p[:, mesh.facets[1]] - mesh.p[:, mesh.facets[0]]
    elen = np.linalg.norm(e, axis=0)
    return mesh, h, float(elen.min()), float(elen.max())


# --------------------------------------------------------------------------
# point evaluation of the P2 solution and its gradient
# --------------------------------------------------------------------------
def _inverse_map(mapping, x, cells, iters=5):
    xx = x[:, :, None]
    X = np.full(xx.shape, 1.0 / 3.0)
    for _ in range(iters):      # affine: exact after the first step
        F = mapping.F(X, tind=cells)
        invDF = mapping.invDF(X, tind=cells)
        dX = np.einsum("ijkl,jkl->ikl", invDF, xx - F)
        X = X + dX
        if np.max(np.abs(dX)) < 1e-15:
            break
    res = np.linalg.norm(xx - mapping.F(X, tind=cells), axis=0)[:, 0]
    return X, res


class PointEvaluator:
    """Locate points in the mesh and evaluate u, grad u there."""

    def __init__(self, mesh, basis, k=24):
        self.mesh, self.basis, self.k = mesh, basis, k
        self.tree = cKDTree(mesh.p[:, mesh.t].mean(axis=1).T)

    def locate(self, x):
        n = x.shape[1]
        k = min(self.k, self.mesh.t.shape[1])
        _, cand = self.tree.query(x.T, k)
        cell = -np.ones(n, dtype=np.int64)
        Xref = np.zeros((2, n))
        for r in range(k):
            todo = np.where(cell < 0)[0]
            if todo.size == 0:
                break
            c = cand[todo, r]
            X, res = _inverse_map(self.basis.mapping, x[:, todo], c)
            X = X[:, :, 0]
            out = np.maximum.reduce([-X[0], -X[1], X[0] + X[1] - 1.0,
                                     np.zeros(todo.size)])
            inside = (out <= 1e-12) & (res < 1e-13)
            cell[todo[inside]] = c[inside]
            Xref[:, todo[inside]] = X[:, inside]
        if (cell < 0).any():
            raise ValueError("points outside the mesh: %s" % x[:, cell < 0])
        return cell, Xref

    def __call__(self, x, u, chunk=20000):
        n = x.shape[1]
        val = np.zeros((2, n))
        grad = np.zeros((2, 2, n))
        b = self.basis
        for s0 in range(0, n, chunk):
            sl = slice(s0, min(n, s0 + chunk))
            cells, X = self.locate(x[:, sl])
            Xr = X[:, :, None]
            for kk in range(b.Nbfun):
                phi = b.elem.gbasis(b.mapping, Xr, kk, tind=cells)[0]
                coef = u[b.element_dofs[kk, cells]]
                val[:, sl] += coef * phi.value[:, :, 0]
                grad[:, :, sl] += coef * phi.grad[:, :, :, 0]
        return val, grad


def stresses(grad, lam, mu):
    exx, eyy = grad[0, 0], grad[1, 1]
    exy = 0.5 * (grad[0, 1] + grad[1, 0])
    tr = exx + eyy
    return (2 * mu * exx + lam * tr, 2 * mu * eyy + lam * tr, 2 * mu * exy)


def sample(ev, u, lam, mu, x, y):
    q = np.array([np.clip(np.asarray(x, float), NUDGE, WIDTH - NUDGE),
                  np.clip(np.asarray(y, float), NUDGE, HEIGHT - NUDGE)])
    val, grad = ev(q, u)
    sxx, syy, sxy = stresses(grad, lam, mu)
    return {"ux": val[0], "uy": val[1], "sxx": sxx, "syy": syy, "sxy": sxy}


# --------------------------------------------------------------------------
# one FE solve
# --------------------------------------------------------------------------
def solve_level(N, K, plane):
    lam, mu = lame(E, NU, plane)
    t0 = time.perf_counter()
    mesh, h, hmin, hmax = build_mesh(N, K)
    e = ElementVector(ElementTriP2())
    basis = Basis(mesh, e)

    @BilinearForm
    def a(u, v, w):
        eps_u = sym_grad(u)
        sig = 2.0 * mu * eps_u + lam * eye(trace(eps_u), 2)
        return THICK * ddot(sig, sym_grad(v))

    right = mesh.facets_satisfying(lambda x: np.isclose(x[0], WIDTH),
                                   boundaries_only=True)
    fb = FacetBasis(mesh, e, facets=right)

    @LinearForm
    def l(v, w):
        return THICK * SIG * v.value[0]

    K_ = asm(a, basis)
    f = asm(l, fb)
    left = mesh.facets_satisfying(lambda x: np.isclose(x[0], 0.0),
                                  boundaries_only=True)
    D = basis.get_dofs(facets=left).all()
    t1 = time.perf_counter()
    u = solve(*condense(K_, f, D=D))
    t2 = time.perf_counter()
    return dict(mesh=mesh, basis=basis, u=u, h=h, hmin=hmin, hmax=hmax,
                ndofs=int(basis.N), ncells=int(mesh.t.shape[1]),
                assemble_s=t1 - t0, solve_s=t2 - t1, lam=lam, mu=mu,
                load=float(f[basis.nodal_dofs[0]].sum()
                           + f[basis.facet_dofs[0]].sum()))


def rnd(a, sig=12):
    a = np.asarray(a, dtype=float)
    if a.ndim == 0:
        v = float(a)
        return None if not np.isfinite(v) else float("%.*g" % (sig, v))
    return [rnd(b, sig) for b in a]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--levels", type=int, nargs="+",
                    default=[8, 16, 32, 64, 128, 256],
                    help="base mesh divisions N per side (even)")
    ap.add_argument("--corner-refinements", type=int, default=6,
                    help="rounds of local refinement toward (0,0), (0,1)")
    ap.add_argument("--plane", choices=["stress", "strain"], default="stress")
    ap.add_argument("--out", default=os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "reference.json"))
    args = ap.parse_args()
    T0 = time.perf_counter()
    Kc = args.corner_refinements

    sp = np.round(0.0025 * np.arange(401), 12)
    half = np.full_like(sp, 0.5)
    conv, profs = [], []
    for N in args.levels:
        s = solve_level(N, Kc, args.plane)
        ev = PointEvaluator(s["mesh"], s["basis"])
        lam, mu, u = s["lam"], s["mu"], s["u"]
        pv = sample(ev, u, lam, mu, np.array([1.0, 0.5, 0.5, 0.0]),
                    np.array([0.5, 1.0, 0.5, 0.5]))
        py = sample(ev, u, lam, mu, sp, half)      # y = 0.5
        px = sample(ev, u, lam, mu, half, sp)      # x = 0.5
        profs.append((py, px))
        umag = np.hypot(u[s["basis"].nodal_dofs[0]], u[s["basis"].nodal_dofs[1]])
        row = {"N": N, "corner_refinements": Kc, "ncells": s["ncells"],
               "h": s["h"], "h_min": s["hmin"], "h_max": s["hmax"],
               "ndofs": s["ndofs"],
               "ux_at_(1,0.5)": float(pv["ux"][0]),
               "uy_at_(0.5,1)": float(pv["uy"][1]),
               "sxx_at_(0.5,0.5)": float(pv["sxx"][2]),
               "sxx_at_(0,0.5)": float(pv["sxx"][3]),
               "max_abs_u_nodal": float(umag.max()),
               "assembly_time_s": s["assemble_s"],
               "solve_time_s": s["solve_s"],
               "total_load_check": s["load"]}
        conv.append(row)
        print("N=%4d cells=%7d ndofs=%8d h=%.3e hmin=%.3e  ux(1,0.5)=%.12e "
              "uy(0.5,1)=%.12e sxx(0.5,0.5)=%.12e sxx(0,0.5)=%.12e  "
              "solve %.2fs"
              % (N, row["ncells"], row["ndofs"], row["h"], row["h_min"],
                 row["ux_at_(1,0.5)"], row["uy_at_(0.5,1)"],
                 row["sxx_at_(0.5,0.5)"], row["sxx_at_(0,0.5)"],
                 row["solve_time_s"]), flush=True)

    keys = ["ux_at_(1,0.5)", "uy_at_(0.5,1)", "sxx_at_(0.5,0.5)",
            "sxx_at_(0,0.5)"]
    fin = conv[-1]
    fpy, fpx = profs[-1]
    for row, (py, px) in zip(conv, profs):
        for k in keys:
            row["rel_diff_vs_finest_" + k] = abs(row[k] / fin[k] - 1.0)
        row["max_abs_diff_vs_finest_ux_profile_y=0.5"] = float(
            np.max(np.abs(py["ux"] - fpy["ux"])))
        row["max_abs_diff_vs_finest_uy_profile_y=0.5"] = float(
            np.max(np.abs(py["uy"] - fpy["uy"])))
        row["max_abs_diff_vs_finest_ux_profile_x=0.5"] = float(
            np.max(np.abs(px["ux"] - fpx["ux"])))
        row["max_abs_diff_vs_finest_uy_profile_x=0.5"] = float(
            np.max(np.abs(px["uy"] - fpx["uy"])))
        row["max_abs_diff_vs_finest_sxx_profile_y=0.5"] = float(
            np.max(np.abs(py["sxx"] - fpy["sxx"])))
        row["max_abs_diff_vs_finest_syy_profile_x=0.5"] = float(
            np.max(np.abs(px["syy"] - fpx["syy"])))
    orders = {}
    if len(conv) >= 3:
        for k in keys:
            a, b, c = (conv[-3][k], conv[-2][k], conv[-1][k])
            if (b - a) * (c - b) > 0:
                p_obs = np.log2(abs((b - a) / (c - b)))
                rich = c + (c - b) / (2 ** p_obs - 1)
            else:
                p_obs, rich = float("nan"), float("nan")
            orders[k] = {"observed_order_last3": rnd(p_obs),
                         "richardson_extrapolate": rnd(rich),
                         "finest_minus_previous_rel": rnd(abs(c / b - 1.0))}

    xs = np.round(0.005 * np.arange(201), 12)
    X, Y = np.meshgrid(xs, xs)          # X[iy, ix]
    g = sample(ev, u, lam, mu, X.ravel(), Y.ravel())
    g = {k: v.reshape(X.shape) for k, v in g.items()}
    py, px = profs[-1]
    runtime = time.perf_counter() - T0

    ref = {
        "description": ("Square plate, left edge clamped, uniform traction "
                        "on the right edge (Wang, Oterkus & Oterkus Sec. "
                        "5.1). scikit-fem, full model, P2 triangles, "
                        "uniform chequerboard base mesh + %d rounds of local "
                        "refinement toward the clamped corners. Grid/profile "
                        "values are pointwise evaluations of the finest FE "
                        "solution (P2 field and P2 gradient in the "
                        "containing cell, no projection); boundary points "
                        "nudged into the plate by 1e-12 m. Stresses at and "
                        "next to the clamped corners (0,0), (0,1) are "
                        "singular and not mesh-converged." % Kc),
        "generator": "validation/plate_tension/fem/fem_plate_tension.py",
        "command": "python3 " + " ".join(
            [os.path.basename(sys.argv[0])] + sys.argv[1:]),
        "skfem_version": skfem.__version__,
        "numpy_version": np.__version__,
        "scipy_version": scipy.__version__,
        "python_version": platform.python_version(),
        "problem": {"width": WIDTH, "height": HEIGHT, "E": E, "nu": NU,
                    "traction": SIG, "plane": args.plane,
                    "thickness": THICK},
        "method": {"element": "ElementVector(ElementTriP2)",
                   "mesh": "N x N chequerboard triangles + %d corner "
                           "refinement rounds (skfem MeshTri1.refined)" % Kc,
                   "bc": "u_x = u_y = 0 on x = 0; t = (traction, 0) on x = 1",
                   "solver": "scipy.sparse.linalg.spsolve (SuperLU) via "
                             "skfem.solve",
                   "stress_evaluation": "pointwise P2 gradient in the "
                                        "containing cell",
                   "boundary_nudge_m": NUDGE},
        "convergence": [{k: (rnd(v) if isinstance(v, float) else v)
                         for k, v in row.items()} for row in conv],
        "convergence_summary": orders,
        "ux_at_(1,0.5)": rnd(fin["ux_at_(1,0.5)"]),
        "uy_at_(0.5,1)": rnd(fin["uy_at_(0.5,1)"]),
        "sxx_at_(0.5,0.5)": rnd(fin["sxx_at_(0.5,0.5)"]),
        "sxx_at_(0,0.5)": rnd(fin["sxx_at_(0,0.5)"]),
        "runtime_s": round(runtime, 2),
        "grid": {"x0": 0.0, "dx": 0.005, "nx": 201,
                 "y0": 0.0, "dy": 0.005, "ny": 201,
                 "ux": rnd(g["ux"]), "uy": rnd(g["uy"]),
                 "sxx": rnd(g["sxx"]), "syy": rnd(g["syy"]),
                 "sxy": rnd(g["sxy"])},
        "profiles": {
            "y=0.5": {"x": rnd(sp), "ux": rnd(py["ux"]), "uy": rnd(py["uy"]),
                      "sxx": rnd(py["sxx"])},
            "x=0.5": {"y": rnd(sp), "ux": rnd(px["ux"]), "uy": rnd(px["uy"]),
                      "syy": rnd(px["syy"])}},
    }
    with open(args.out, "w") as fh:
        json.dump(ref, fh, separators=(",", ":"))
    print("uniform-stress estimate (no clamping effect): ux(1,y) = "
          "traction/E * width = %.6g m" % (SIG / E * WIDTH))
    print("wrote %s  (total runtime %.1f s)" % (args.out, runtime))


if __name__ == "__main__":
    main()
