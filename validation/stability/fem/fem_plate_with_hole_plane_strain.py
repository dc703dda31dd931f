#!/usr/bin/env python3
"""Plane-strain FEM reference for the plate with a hole at near-incompressibility.

Same geometry, E and default 'uniaxial' loading as
validation/plate_with_hole/fem/fem_plate_with_hole.py (plate [-0.5, 0.5]^2 m,
central hole r = 0.125 m, E = 30 GPa, traction P = 1 MPa pulling outward on
x = +-0.5, top/bottom/hole free, thickness 1), but PLANE STRAIN and a sweep
over Poisson's ratio nu in {0.3, 0.45, 0.49, 0.499, 0.4999}.

For every nu and every mesh level the problem is solved twice on the same
isoparametric P2 O-grid (quarter model, symmetry u_x = 0 on x = 0 and
u_y = 0 on y = 0; mesh, point evaluation, nudging and mirroring are copied
from the plane-stress script so that this file is self-contained):

  disp   pure displacement P2:  ElementVector(ElementTriP2()),
         a(u, v) = (2 mu eps(u) + lam tr eps(u) I) : eps(v).
         Locks volumetrically as lam/mu -> infinity.
  mixed  Taylor-Hood P2/P1 displacement-pressure, p = lam div u:
           (2 mu eps(u), eps(v)) + (p, div v)      = l(v)
           (div u, q)            - (p, q) / lam    = 0
         sigma = 2 mu eps(u) + p I.  Inf-sup stable, uniformly in lam
         (nu -> 0.5 is fine).  Same P2 displacement space and geometry.

with lam = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)).

Per nu it prints/records max|u| (over all P2 nodes), the L2 norm of u over
the valid points of the sampled JSON grid, sigma_xx at the hole top (0, R),
the maximum of sigma_xx over the hole boundary, sigma_yy at the hole side,
the relative L2 difference of u between the two formulations, and the change
of each under refinement.  One JSON per nu (reference_nu<nu>.json, the same
schema as validation/plate_with_hole/fem/reference.json, read by
dhpd::reference::FemReference::from_json) is written from the mixed
formulation at the finest level (``--json-from disp`` to override).

Run (from this directory; about 170 s on 2 cores, 1.8 GB peak memory):
    /tmp/fenv/bin/python fem_plate_with_hole_plane_strain.py | tee run_log.txt
Options: --levels 8 16 32 64   --nus 0.3 0.45 0.49 0.499 0.4999
         --json-from mixed|disp   --outdir DIR   --no-json
"""
import argparse
import dataclasses
import json
import os
import platform
import sys
import time

import numpy as np
import scipy
import scipy.sparse as sps
from scipy.spatial import cKDTree

import skfem
from skfem import (Basis, BilinearForm, ElementTriP1, ElementTriP2,
                   ElementVector, FacetBasis, LinearForm, MeshTri1, MeshTri2,
                   asm, condense, solve)
from skfem.helpers import ddot, div, eye, sym_grad, trace

HALF = 0.5          # half width of the plate [m]
R = 0.125           # hole radius [m]
E = 30e9            # Young's modulus [Pa]
P = 1e6             # traction magnitude on x = +-0.5 [Pa]
THICK = 1.0         # thickness [m]
NUDGE = 1e-12       # inward nudge for sample points on boundaries [m]
BETA = 2.3          # radial grading parameter of the O-grid
NUS = [0.3, 0.45, 0.49, 0.499, 0.4999]
GRID_DX = 0.01      # JSON grid spacing (101 x 101, keeps files < 1 MB)
GRID_N = 101
SIG = 10            # significant digits stored in the JSON grid


def lame_plane_strain(E, nu):
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


# --------------------------------------------------------------------------
# mesh (copied from validation/plate_with_hole/fem/fem_plate_with_hole.py)
# --------------------------------------------------------------------------
def blend_map(A, s):
    """(A, s) in [0, 2] x [0, 1] -> quarter domain; s = 0 hole, s = 1 edge."""
    A = np.asarray(A, dtype=float)
    s = np.asarray(s, dtype=float)
    g = np.expm1(BETA * s) / np.expm1(BETA)
    th = A * np.pi / 4.0
    cx, cy = R * np.cos(th), R * np.sin(th)
    ox = np.where(A <= 1.0, HALF, HALF * (2.0 - A))
    oy = np.where(A <= 1.0, HALF * A, HALF)
    x = (1.0 - g) * cx + g * ox
    y = (1.0 - g) * cy + g * oy
    x = np.where(A == 2.0, 0.0, x)
    y = np.where(A == 0.0, 0.0, y)
    x = np.where((s == 1.0) & (A <= 1.0), HALF, x)
    y = np.where((s == 1.0) & (A >= 1.0), HALF, y)
    return np.array([x, y])


def build_mesh(N, M):
    """O-grid with N cells per 45-degree block along the hole, M radially."""
    nA = 2 * N + 1
    ii, jj = np.meshgrid(np.arange(nA), np.arange(M + 1))
    Apar = (ii / N).ravel()
    spar = (jj / M).ravel()
    p = blend_map(Apar, spar)
    idx = lambda i, j: j * nA + i
    I, J = np.meshgrid(np.arange(2 * N), np.arange(M))
    I, J = I.ravel(), J.ravel()
    v00, v10 = idx(I, J), idx(I + 1, J)
    v11, v01 = idx(I + 1, J + 1), idx(I, J + 1)
    flip = (I + J) % 2 == 1
    t1 = np.where(flip, [v00, v10, v01], [v00, v10, v11])
    t2 = np.where(flip, [v10, v11, v01], [v00, v11, v01])
    t = np.hstack([t1, t2])
    a, b, c = p[:, t[0]], p[:, t[1]], p[:, t[2]]
    det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    neg = det < 0
    t[1, neg], t[2, neg] = t[2, neg].copy(), t[1, neg].copy()
    m1 = MeshTri1(p, t)
    m2 = MeshTri2.from_mesh(m1)
    nv = m1.p.shape[1]
    doflocs = m2.doflocs.copy()
    assert doflocs.shape[1] == nv + m1.facets.shape[1]
    assert np.allclose(doflocs[:, nv:], m1.p[:, m1.facets].mean(axis=1))
    par = np.array([Apar, spar])
    pmid = par[:, m1.facets].mean(axis=1)
    doflocs[:, nv:] = blend_map(pmid[0], pmid[1])
    m2 = dataclasses.replace(m2, doflocs=doflocs)
    elen = np.linalg.norm(m1.p[:, m1.facets[1]] - m1.p[:, m1.facets[0]],
                          axis=0)
    return m2, float(elen.min()), float(elen.max())


# --------------------------------------------------------------------------
# point evaluation (copied, generalised to several bases on one mesh)
# --------------------------------------------------------------------------
def _inverse_map(mapping, x, cells, iters=40):
    xx = x[:, :, None]
    X = np.full(xx.shape, 1.0 / 3.0)
    with np.errstate(all="ignore"):
        for _ in range(iters):
            F = mapping.F(X, tind=cells)
            invDF = mapping.invDF(X, tind=cells)
            dX = np.einsum("ijkl,jkl->ikl", invDF, xx - F)
            dX = np.nan_to_num(dX, nan=0.0, posinf=0.0, neginf=0.0)
            X = np.clip(X + dX, -10.0, 10.0)
            if np.max(np.abs(dX)) < 1e-15:
                break
        res = np.linalg.norm(xx - mapping.F(X, tind=cells), axis=0)[:, 0]
    return X, np.nan_to_num(res, nan=np.inf)


class PointEvaluator:
    """Locate points in the (curved) cells; evaluate FE fields there."""

    def __init__(self, mesh, basis, k=24):
        self.mesh, self.basis, self.k = mesh, basis, k
        cent = mesh.doflocs[:, mesh.t].mean(axis=1)
        self.tree = cKDTree(cent.T)
        self.n_fallback = 0

    def locate(self, x):
        n = x.shape[1]
        k = min(self.k, self.mesh.t.shape[1])
        _, cand = self.tree.query(x.T, k)
        cell = -np.ones(n, dtype=np.int64)
        Xref = np.zeros((2, n))
        best_out = np.full(n, np.inf)
        best_cell = np.zeros(n, dtype=np.int64)
        best_X = np.zeros((2, n))
        for r in range(k):
            todo = np.where(cell < 0)[0]
            if todo.size == 0:
                break
            c = cand[todo, r]
            X, res = _inverse_map(self.basis.mapping, x[:, todo], c)
            X = X[:, :, 0]
            out = np.maximum.reduce([-X[0], -X[1], X[0] + X[1] - 1.0,
                                     np.zeros(todo.size)])
            out = np.where(res < 1e-13, out, np.inf)
            inside = out <= 1e-12
            hit = todo[inside]
            cell[hit] = c[inside]
            Xref[:, hit] = X[:, inside]
            better = out < best_out[todo]
            bt = todo[better]
            best_out[bt] = out[better]
            best_cell[bt] = c[better]
            best_X[:, bt] = X[:, better]
        miss = np.where(cell < 0)[0]
        if miss.size:
            if np.max(best_out[miss]) > 1e-6:
                raise ValueError("points outside the mesh: %s" % x[:, miss])
            cell[miss] = best_cell[miss]
            Xref[:, miss] = best_X[:, miss]
            self.n_fallback += miss.size
        return cell, Xref

    @staticmethod
    def eval_basis(b, coef_vec, cells, X):
        """Value and gradient of the field `coef_vec` of basis `b`."""
        Xr = X[:, :, None]
        val = grad = None
        for kk in range(b.Nbfun):
            phi = b.elem.gbasis(b.mapping, Xr, kk, tind=cells)[0]
            coef = coef_vec[b.element_dofs[kk, cells]]
            v = coef * phi.value[..., 0]
            g = coef * phi.grad[..., 0]
            val = v if val is None else val + v
            grad = g if grad is None else grad + g
        return val, grad


# --------------------------------------------------------------------------
# solves
# --------------------------------------------------------------------------
def _common(N):
    M = (3 * N) // 2
    mesh, hmin, hmax = build_mesh(N, M)
    e = ElementVector(ElementTriP2())
    ub = Basis(mesh, e, intorder=4)
    right = mesh.facets_satisfying(lambda x: np.isclose(x[0], HALF),
                                   boundaries_only=True)
    fb = FacetBasis(mesh, e, facets=right, intorder=4)

    @LinearForm
    def l(v, w):
        return THICK * P * v.value[0]

    f = asm(l, fb)
    fx0 = mesh.facets_satisfying(lambda x: np.isclose(x[0], 0.0),
                                 boundaries_only=True)
    fy0 = mesh.facets_satisfying(lambda x: np.isclose(x[1], 0.0),
                                 boundaries_only=True)
    D = np.concatenate([ub.get_dofs(facets=fx0).all("u^1"),
                        ub.get_dofs(facets=fy0).all("u^2")])
    return dict(N=N, M=M, mesh=mesh, hmin=hmin, hmax=hmax, ub=ub, f=f, D=D)


def solve_disp(N, nu):
    t0 = time.perf_counter()
    c = _common(N)
    lam, mu = lame_plane_strain(E, nu)

    @BilinearForm
    def a(u, v, w):
        eps = sym_grad(u)
        return THICK * ddot(2.0 * mu * eps + lam * eye(trace(eps), 2),
                            sym_grad(v))

    K = asm(a, c["ub"])
    t1 = time.perf_counter()
    u = solve(*condense(K, c["f"], D=c["D"]))
    t2 = time.perf_counter()
    r = K @ u - c["f"]
    r[c["D"]] = 0.0
    c["residual"] = float(np.linalg.norm(r) / np.linalg.norm(c["f"]))
    c.update(form="disp", u=u, pb=None, p=None, lam=lam, mu=mu,
             ndofs=int(c["ub"].N), assemble_s=t1 - t0, solve_s=t2 - t1)
    return c


def solve_mixed(N, nu):
    t0 = time.perf_counter()
    c = _common(N)
    lam, mu = lame_plane_strain(E, nu)
    ub = c["ub"]
    pb = Basis(c["mesh"], ElementTriP1(), intorder=4)

    # scaled unknowns: pt = p / mu (dimensionless), equations divided by mu,
    # so that all blocks are O(1) for the direct solver:
    #   (2 eps(u), eps(v)) + (pt, div v) = l(v) / mu
    #   (div u, q) - (mu / lam) (pt, q)  = 0
    @BilinearForm
    def a(u, v, w):
        return THICK * 2.0 * ddot(sym_grad(u), sym_grad(v))

    @BilinearForm
    def b(u, q, w):             # trial u (P2 vector), test q (P1)
        return THICK * div(u) * q

    @BilinearForm
    def m(p, q, w):
        return THICK * (mu / lam) * p * q

    A = asm(a, ub)
    B = asm(b, ub, pb)          # shape (Np, Nu)
    C = asm(m, pb)
    K = sps.bmat([[A, B.T], [B, -C]], format="csr")
    f = np.concatenate([c["f"] / mu, np.zeros(pb.N)])
    t1 = time.perf_counter()
    x = solve(*condense(K, f, D=c["D"]))
    t2 = time.perf_counter()
    r = K @ x - f
    r[c["D"]] = 0.0
    c["residual"] = float(np.linalg.norm(r) / np.linalg.norm(f))
    x[ub.N:] *= mu              # back to p [Pa]
    c.update(form="mixed", u=x[:ub.N], pb=pb, p=x[ub.N:], lam=lam, mu=mu,
             ndofs=int(ub.N + pb.N), assemble_s=t1 - t0, solve_s=t2 - t1)
    return c


# --------------------------------------------------------------------------
# sampling
# --------------------------------------------------------------------------
def quarter_points(x, y):
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    sx = np.where(x < 0, -1.0, 1.0)
    sy = np.where(y < 0, -1.0, 1.0)
    qx = np.clip(np.abs(x), NUDGE, HALF - NUDGE)
    qy = np.clip(np.abs(y), NUDGE, HALF - NUDGE)
    r = np.hypot(np.abs(x), np.abs(y))
    valid = r >= R - 1e-9
    rq = np.hypot(qx, qy)
    push = valid & (rq < R + NUDGE)
    fac = np.where(push, (R + NUDGE) / np.where(rq > 0, rq, 1.0), 1.0)
    return np.array([qx * fac, qy * fac]), sx, sy, valid


def sample(s, ev, x, y):
    """Full-plate sample of solution `s` at (x, y); NaN inside the hole.

    disp:  sigma = 2 mu eps + lam tr(eps) I  (pointwise P2 gradient)
    mixed: sigma = 2 mu eps + p I            (P2 gradient, P1 pressure)
    """
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    q, sx, sy, valid = quarter_points(x, y)
    out = {k: np.full(x.shape, np.nan) for k in
           ("ux", "uy", "sxx", "syy", "sxy", "p")}
    if valid.any():
        cells, X = ev.locate(q[:, valid])
        val, grad = ev.eval_basis(s["ub"], s["u"], cells, X)
        lam, mu = s["lam"], s["mu"]
        exx, eyy = grad[0, 0], grad[1, 1]
        exy = 0.5 * (grad[0, 1] + grad[1, 0])
        if s["pb"] is None:
            pr = lam * (exx + eyy)
        else:
            pr, _ = ev.eval_basis(s["pb"], s["p"], cells, X)
        out["ux"][valid] = sx[valid] * val[0]
        out["uy"][valid] = sy[valid] * val[1]
        out["sxx"][valid] = 2 * mu * exx + pr
        out["syy"][valid] = 2 * mu * eyy + pr
        out["sxy"][valid] = sx[valid] * sy[valid] * 2 * mu * exy
        out["p"][valid] = pr
    return out


def grid_axes():
    return np.round(-0.5 + GRID_DX * np.arange(GRID_N), 12)


def profile_points():
    s = np.round(-0.5 + 0.0025 * np.arange(401), 12)
    return s[np.abs(s) >= R - 1e-9]


def hole_points(n=721):
    th = np.linspace(0.0, np.pi / 2, n)
    return R * np.cos(th), R * np.sin(th)


def rnd(a, sig=12):
    a = np.asarray(a, dtype=float)
    if a.ndim == 0:
        v = float(a)
        return None if not np.isfinite(v) else float("%.*g" % (sig, v))
    return [rnd(b, sig) for b in a]


def analyse(s):
    """All sampled quantities for one solve."""
    ev = PointEvaluator(s["mesh"], s["ub"])
    ub, u = s["ub"], s["u"]
    umag = np.concatenate([
        np.hypot(u[ub.nodal_dofs[0]], u[ub.nodal_dofs[1]]),
        np.hypot(u[ub.facet_dofs[0]], u[ub.facet_dofs[1]])])
    xs = grid_axes()
    X, Y = np.meshgrid(xs, xs)              # X[iy, ix]
    g = sample(s, ev, X.ravel(), Y.ravel())
    g = {k: v.reshape(X.shape) for k, v in g.items()}
    ok = np.isfinite(g["ux"])
    l2 = float(np.sqrt(np.sum(g["ux"][ok] ** 2 + g["uy"][ok] ** 2)
                       * GRID_DX ** 2))
    pt = sample(s, ev, np.array([HALF, 0.0, R]), np.array([0.0, R, 0.0]))
    hx, hy = hole_points()
    hole = sample(s, ev, hx, hy)
    xp = profile_points()
    z = np.zeros_like(xp)
    py0 = sample(s, ev, xp, z)
    px0 = sample(s, ev, z, xp)
    return dict(grid=g, ok=ok, l2=l2, max_abs_u=float(umag.max()),
                ux_end=float(pt["ux"][0]), sxx_top=float(pt["sxx"][1]),
                syy_side=float(pt["syy"][2]),
                sxx_hole_max=float(np.max(hole["sxx"])),
                sxx_hole_max_deg=float(np.degrees(np.arctan2(
                    hy[np.argmax(hole["sxx"])], hx[np.argmax(hole["sxx"])]))),
                hole_sxx_tv=float(np.sum(np.abs(np.diff(hole["sxx"])))),
                profiles=(py0, px0), xp=xp, n_fallback=ev.n_fallback)


def rel_l2_diff_sigma(ga, gb):
    """||sigma_a - sigma_b|| / ||sigma_b|| (Frobenius, sxy counted twice)."""
    ok = np.isfinite(ga["sxx"]) & np.isfinite(gb["sxx"])
    d = sum(w * (ga[k][ok] - gb[k][ok]) ** 2 for k, w in
            (("sxx", 1), ("syy", 1), ("sxy", 2)))
    n = sum(w * gb[k][ok] ** 2 for k, w in (("sxx", 1), ("syy", 1),
                                             ("sxy", 2)))
    return float(np.sqrt(d.sum() / n.sum()))


def rel_l2_diff(ga, gb):
    ok = np.isfinite(ga["ux"]) & np.isfinite(gb["ux"])
    d = (ga["ux"][ok] - gb["ux"][ok]) ** 2 + (ga["uy"][ok] - gb["uy"][ok]) ** 2
    n = gb["ux"][ok] ** 2 + gb["uy"][ok] ** 2
    return float(np.sqrt(d.sum() / n.sum()))


# --------------------------------------------------------------------------
def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--levels", type=int, nargs="+", default=[8, 16, 32, 64])
    ap.add_argument("--nus", type=float, nargs="+", default=NUS)
    ap.add_argument("--json-from", choices=["mixed", "disp"], default="mixed")
    ap.add_argument("--outdir", default=os.path.dirname(
        os.path.abspath(__file__)))
    ap.add_argument("--no-json", action="store_true")
    args = ap.parse_args()
    T0 = time.perf_counter()
    print("plane strain, uniaxial P = %g Pa on x = +-0.5, E = %g Pa, "
          "R = %g m, plate [-0.5, 0.5]^2; levels %s; skfem %s numpy %s "
          "scipy %s python %s" % (P, E, R, args.levels, skfem.__version__,
                                  np.__version__, scipy.__version__,
                                  platform.python_version()))
    print("L2(u) = sqrt(sum |u|^2 dx dy) over the valid points of the "
          "%dx%d JSON grid (dx = %g m); sxx_hole_max = max of sigma_xx over "
          "721 points on the hole; d(L2) P2-vs-mixed = ||u_disp - u_mixed|| / "
          "||u_mixed|| on that grid" % (GRID_N, GRID_N, GRID_DX))
    summary = []
    for nu in args.nus:
        lam, mu = lame_plane_strain(E, nu)
        print("\n=== nu = %g  (lam/mu = %.4g) ===" % (nu, lam / mu))
        print("%-5s %4s %8s %18s %18s %16s %16s %16s %8s %9s" % (
            "form", "N", "ndofs", "max|u| [m]", "L2(u) [m^2]",
            "sxx(0,R) [Pa]", "max sxx hole", "syy(R,0) [Pa]", "solve s",
            "rel.resid"))
        res = {"disp": [], "mixed": []}
        for N in args.levels:
            for form, fn in (("disp", solve_disp), ("mixed", solve_mixed)):
                s = fn(N, nu)
                a = analyse(s)
                a.update(residual=s["residual"])
                a.update(N=N, M=s["M"], ndofs=s["ndofs"], hmin=s["hmin"],
                         hmax=s["hmax"], solve_s=s["solve_s"],
                         assemble_s=s["assemble_s"], ncells=int(
                             s["mesh"].t.shape[1]))
                res[form].append(a)
                print("%-5s %4d %8d %18.11e %18.11e %16.9e %16.9e %16.9e "
                      "%8.2f %9.1e" % (form, N, s["ndofs"], a["max_abs_u"],
                                       a["l2"], a["sxx_top"],
                                       a["sxx_hole_max"], a["syy_side"],
                                       s["solve_s"], s["residual"]),
                      flush=True)
                del s
            d = rel_l2_diff(res["disp"][-1]["grid"], res["mixed"][-1]["grid"])
            ds = rel_l2_diff_sigma(res["disp"][-1]["grid"],
                                   res["mixed"][-1]["grid"])
            res["mixed"][-1]["l2diff_disp_vs_mixed"] = d
            res["mixed"][-1]["l2diff_sigma_disp_vs_mixed"] = ds
            print("      N=%d: on the grid ||u_disp - u_mixed||/||u_mixed|| "
                  "= %.3e, ||sig_disp - sig_mixed||/||sig_mixed|| = %.3e"
                  % (N, d, ds))
        fd, fm = res["disp"][-1], res["mixed"][-1]
        rel = lambda a, b: a / b - 1.0
        def chg(lst, k):
            return rel(lst[-1][k], lst[-2][k]) if len(lst) > 1 else float("nan")
        row = dict(nu=nu, lam_over_mu=lam / mu, N=fd["N"],
                   mixed=dict(max_abs_u=fm["max_abs_u"], l2=fm["l2"],
                              sxx_top=fm["sxx_top"],
                              sxx_hole_max=fm["sxx_hole_max"],
                              syy_side=fm["syy_side"]),
                   disp=dict(max_abs_u=fd["max_abs_u"], l2=fd["l2"],
                             sxx_top=fd["sxx_top"],
                             sxx_hole_max=fd["sxx_hole_max"],
                             syy_side=fd["syy_side"]),
                   diff={k: rel(fd[k], fm[k]) for k in
                         ("max_abs_u", "l2", "sxx_top", "sxx_hole_max",
                          "syy_side")},
                   diff_l2_field=fm["l2diff_disp_vs_mixed"],
                   diff_l2_sigma=fm["l2diff_sigma_disp_vs_mixed"],
                   change_disp={k: chg(res["disp"], k) for k in
                                ("max_abs_u", "l2", "sxx_top", "sxx_hole_max",
                                 "syy_side")},
                   change_mixed={k: chg(res["mixed"], k) for k in
                                 ("max_abs_u", "l2", "sxx_top",
                                  "sxx_hole_max", "syy_side")})
        summary.append(row)
        print("  finest N=%d: (disp/mixed - 1): max|u| %+.3e  L2(u) %+.3e  "
              "sxx(0,R) %+.3e  max sxx hole %+.3e  syy(R,0) %+.3e; "
              "grid L2 diff u %.3e sigma %.3e" % (
                  fd["N"], row["diff"]["max_abs_u"], row["diff"]["l2"],
                  row["diff"]["sxx_top"], row["diff"]["sxx_hole_max"],
                  row["diff"]["syy_side"], row["diff_l2_field"],
                  row["diff_l2_sigma"]))
        for form in ("disp", "mixed"):
            ch = row["change_" + form]
            print("  change %s N=%d->%d: max|u| %+.3e  L2(u) %+.3e  "
                  "sxx(0,R) %+.3e  max sxx hole %+.3e  syy(R,0) %+.3e" % (
                      form, args.levels[-2] if len(args.levels) > 1 else 0,
                      args.levels[-1], ch["max_abs_u"], ch["l2"],
                      ch["sxx_top"], ch["sxx_hole_max"], ch["syy_side"]))
        if not args.no_json:
            write_json(args, nu, res, row)
        del res

    print("\n=== summary at the finest level N=%d (rel. = disp/mixed - 1; "
          "chg = finest/previous - 1) ===" % args.levels[-1])
    print("%-7s %9s %14s %14s %10s %10s %10s %10s %10s %10s %10s %10s %10s" % (
        "nu", "lam/mu", "max|u| mixed", "sxx(0,R) mix", "rel max|u|",
        "rel L2(u)", "rel sxx", "dL2 u", "dL2 sigma", "chg|u| P2",
        "chg|u| mx", "chgsxx P2", "chgsxx mx"))
    for r in summary:
        print("%-7g %9.4g %14.8e %14.8e %+10.2e %+10.2e %+10.2e %10.2e "
              "%10.2e %+10.2e %+10.2e %+10.2e %+10.2e" % (
                  r["nu"], r["lam_over_mu"], r["mixed"]["max_abs_u"],
                  r["mixed"]["sxx_top"], r["diff"]["max_abs_u"],
                  r["diff"]["l2"], r["diff"]["sxx_top"], r["diff_l2_field"],
                  r["diff_l2_sigma"],
                  r["change_disp"]["max_abs_u"],
                  r["change_mixed"]["max_abs_u"],
                  r["change_disp"]["sxx_top"], r["change_mixed"]["sxx_top"]))
    print("total runtime %.1f s" % (time.perf_counter() - T0))


def write_json(args, nu, res, row):
    src = args.json_from
    lv = res[src]
    fin = lv[-1]
    g = fin["grid"]
    py0, px0 = fin["profiles"]
    xp = fin["xp"]
    keys = ["max_abs_u", "ux_end", "l2", "sxx_top", "sxx_hole_max",
            "syy_side"]
    conv = []
    for form in ("disp", "mixed"):
        for a in res[form]:
            conv.append({"formulation": form, "N_arc_per_45deg": a["N"],
                         "N_radial": a["M"], "ncells": a["ncells"],
                         "ndofs": a["ndofs"], "h_min": rnd(a["hmin"]),
                         "h_max": rnd(a["hmax"]),
                         "max_abs_u": rnd(a["max_abs_u"]),
                         "ux_at_(0.5,0)": rnd(a["ux_end"]),
                         "l2_u_on_grid": rnd(a["l2"]),
                         "sxx_hole_top": rnd(a["sxx_top"]),
                         "sxx_hole_max": rnd(a["sxx_hole_max"]),
                         "syy_hole_side": rnd(a["syy_side"]),
                         "solve_time_s": round(a["solve_s"], 3)})
    other = "disp" if src == "mixed" else "mixed"
    lam, mu = lame_plane_strain(E, nu)
    desc = ("Plate with central hole, PLANE STRAIN, load 'uniaxial' "
            "(traction P = 1e6 Pa outward on x = +-0.5), E = 3e10 Pa, "
            "nu = %g (lam/mu = %.4g). Formulation: %s. Mesh: isoparametric "
            "P2 O-grid (MeshTri2), N = %d cells per 45 deg of hole arc, "
            "%d radially, %d cells in the quarter model, %d dofs; quarter "
            "model with symmetry, mirrored to the full plate (ux odd in x, "
            "uy odd in y, sxx/syy even, sxy odd in x and in y); null inside "
            "the hole. Grid: %dx%d samples, dx = %g m; pointwise evaluation "
            "(no projection), boundary points nudged inward by 1e-12 m. "
            "P2-displacement vs mixed at this mesh (disp/mixed - 1): "
            "max|u| %+.2e, L2(u) %+.2e, sxx(0,R) %+.2e, syy(R,0) %+.2e; "
            "relative L2 difference on the grid: u %.2e, sigma %.2e. Change of the %s "
            "solution from N = %d to N = %d: max|u| %+.1e, sxx(0,R) %+.1e."
            % (nu, lam / mu,
               "Taylor-Hood P2/P1 mixed displacement-pressure "
               "(p = lam div u; sigma = 2 mu eps(u) + p I)" if src == "mixed"
               else "pure displacement P2 (sigma = 2 mu eps + lam tr eps I)",
               fin["N"], fin["M"], fin["ncells"], fin["ndofs"], GRID_N,
               GRID_N, GRID_DX, row["diff"]["max_abs_u"], row["diff"]["l2"],
               row["diff"]["sxx_top"], row["diff"]["syy_side"],
               row["diff_l2_field"], row["diff_l2_sigma"], src,
               lv[-2]["N"] if len(lv) > 1 else fin["N"], fin["N"],
               row["change_" + src]["max_abs_u"],
               row["change_" + src]["sxx_top"]))
    ref = {
        "description": desc,
        "generator": "validation/stability/fem/fem_plate_with_hole_plane_strain.py",
        "command": "python3 " + " ".join(
            [os.path.basename(sys.argv[0])] + sys.argv[1:]),
        "skfem_version": skfem.__version__,
        "numpy_version": np.__version__,
        "scipy_version": scipy.__version__,
        "python_version": platform.python_version(),
        "problem": {"half_width": HALF, "hole_radius": R, "E": E, "nu": nu,
                    "lambda": lam, "mu": mu, "traction": P,
                    "plane": "strain", "thickness": THICK,
                    "load": "uniaxial"},
        "method": {"formulation": src,
                   "element": ("ElementVector(ElementTriP2) x ElementTriP1 "
                               "(Taylor-Hood)" if src == "mixed" else
                               "ElementVector(ElementTriP2)"),
                   "geometry": "MeshTri2 isoparametric",
                   "model": "quarter, symmetry u_x=0 on x=0, u_y=0 on y=0",
                   "mesh": "structured O-grid, N cells per 45 deg of hole "
                           "arc, 3N/2 radially, exponential radial grading "
                           "beta=%g" % BETA,
                   "N_arc_per_45deg": fin["N"],
                   "solver": "SuperLU via skfem.solve",
                   "boundary_nudge_m": NUDGE,
                   "n_points_evaluated_by_tiny_extrapolation":
                       fin["n_fallback"]},
        "p2_vs_mixed_finest": {
            "rel_diff_disp_over_mixed_minus_1": {k: rnd(v) for k, v in
                                                 row["diff"].items()},
            "rel_l2_diff_u_field": rnd(row["diff_l2_field"]),
            "rel_l2_diff_sigma_field": rnd(row["diff_l2_sigma"])},
        "change_finest_vs_previous": {
            "disp": {k: rnd(v) for k, v in row["change_disp"].items()},
            "mixed": {k: rnd(v) for k, v in row["change_mixed"].items()}},
        "convergence": conv,
        "max_abs_u": rnd(fin["max_abs_u"]),
        "ux_at_(0.5,0)": rnd(fin["ux_end"]),
        "sxx_hole_top": rnd(fin["sxx_top"]),
        "sxx_hole_max": rnd(fin["sxx_hole_max"]),
        "syy_hole_side": rnd(fin["syy_side"]),
        "grid": {"x0": -0.5, "dx": GRID_DX, "nx": GRID_N,
                 "y0": -0.5, "dy": GRID_DX, "ny": GRID_N,
                 "ux": rnd(g["ux"], SIG), "uy": rnd(g["uy"], SIG),
                 "sxx": rnd(g["sxx"], SIG), "syy": rnd(g["syy"], SIG),
                 "sxy": rnd(g["sxy"], SIG)},
        "profiles": {
            "y=0": {"x": rnd(xp), "ux": rnd(py0["ux"]), "uy": rnd(py0["uy"]),
                    "sxx": rnd(py0["sxx"]), "syy": rnd(py0["syy"])},
            "x=0": {"y": rnd(xp), "ux": rnd(px0["ux"]), "uy": rnd(px0["uy"]),
                    "sxx": rnd(px0["sxx"]), "syy": rnd(px0["syy"])}},
    }
    os.makedirs(args.outdir, exist_ok=True)
    out = os.path.join(args.outdir, "reference_nu%g.json" % nu)
    with open(out, "w") as fh:
        json.dump(ref, fh, separators=(",", ":"))
    print("  wrote %s (%.0f kB, from %s N=%d)" % (
        out, os.path.getsize(out) / 1e3, src, fin["N"]))


if __name__ == "__main__":
    main()
