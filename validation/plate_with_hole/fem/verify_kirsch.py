#!/usr/bin/env python3
"""Self-check of the FE pipeline of fem_plate_with_hole.py against an exact
solution: the quarter model is loaded on x = 0.5 and y = 0.5 with the exact
Kirsch (infinite plate, remote sigma_xx = P) tractions, so the FE solution
must converge to the Kirsch field everywhere.  Uses the same mesh, element,
boundary conditions, point evaluation and full-plate mirroring as the
reference script and prints the max error over the 201 x 201 full-plate grid.

Run:  python3 verify_kirsch.py        (about 10 s; writes nothing)
"""
import os
import sys

import numpy as np
from skfem import (Basis, BilinearForm, ElementTriP2, ElementVector,
                   FacetBasis, LinearForm, asm, condense, solve)
from skfem.helpers import ddot, eye, sym_grad, trace

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fem_plate_with_hole as F  # noqa: E402

P, a = F.P, F.R
lam, mu = F.lame(F.E, F.NU, "stress")
kap = (3.0 - F.NU) / (1.0 + F.NU)      # plane-stress Kolosov constant


def kirsch(x, y):
    r = np.hypot(x, y)
    th = np.arctan2(y, x)
    c2, s2 = np.cos(2 * th), np.sin(2 * th)
    q = a * a / r ** 2
    srr = P / 2 * (1 - q) + P / 2 * (1 - 4 * q + 3 * q * q) * c2
    stt = P / 2 * (1 + q) - P / 2 * (1 + 3 * q * q) * c2
    srt = -P / 2 * (1 + 2 * q - 3 * q * q) * s2
    c, s = np.cos(th), np.sin(th)
    sxx = srr * c * c + stt * s * s - 2 * srt * s * c
    syy = srr * s * s + stt * c * c + 2 * srt * s * c
    sxy = (srr - stt) * s * c + srt * (c * c - s * s)
    ur = P / (8 * mu * r) * ((kap - 1) * r * r + 2 * a * a
                             + 2 * (r * r + (kap + 1) * a * a - a ** 4 / r ** 2)
                             * c2)
    ut = -P / (8 * mu * r) * 2 * (r * r + (kap - 1) * a * a + a ** 4 / r ** 2) * s2
    return ur * c - ut * s, ur * s + ut * c, sxx, syy, sxy


def main():
    xs = np.round(-0.5 + 0.005 * np.arange(201), 12)
    X, Y = np.meshgrid(xs, xs)
    X, Y = X.ravel(), Y.ravel()
    outside = np.hypot(X, Y) >= a - 1e-9
    ex = kirsch(X[outside], Y[outside])
    print("N    max|err| ux        uy        sxx [Pa]  syy [Pa]  sxy [Pa]"
          "   sxx(0,R)/3P-1  syy(R,0)/(-P)-1")
    for N in (8, 16, 32, 64):
        mesh, _, _ = F.build_mesh(N, 3 * N // 2)
        e = ElementVector(ElementTriP2())
        basis = Basis(mesh, e, intorder=4)

        @BilinearForm
        def bil(u, v, w):
            eu = sym_grad(u)
            return ddot(2 * mu * eu + lam * eye(trace(eu), 2), sym_grad(v))

        @LinearForm
        def trac(v, w):
            _, _, sxx, syy, sxy = kirsch(w.x[0], w.x[1])
            n = w.n
            return ((sxx * n[0] + sxy * n[1]) * v.value[0]
                    + (sxy * n[0] + syy * n[1]) * v.value[1])

        f = 0.0
        for i in (0, 1):
            fac = mesh.facets_satisfying(
                lambda x, i=i: np.isclose(x[i], F.HALF), boundaries_only=True)
            f = f + asm(trac, FacetBasis(mesh, e, facets=fac, intorder=6))
        D = np.concatenate([
            basis.get_dofs(facets=mesh.facets_satisfying(
                lambda x: np.isclose(x[0], 0.0), boundaries_only=True)).all("u^1"),
            basis.get_dofs(facets=mesh.facets_satisfying(
                lambda x: np.isclose(x[1], 0.0), boundaries_only=True)).all("u^2")])
        u = solve(*condense(asm(bil, basis), f, D=D))
        ev = F.PointEvaluator(mesh, basis)
        g = F.sample(ev, u, lam, mu, X[outside], Y[outside])
        err = [np.max(np.abs(g[k] - ex[j]))
               for j, k in enumerate(("ux", "uy", "sxx", "syy", "sxy"))]
        pt = F.sample(ev, u, lam, mu, np.array([0.0, a]), np.array([a, 0.0]))
        print("%-4d %.2e  %.2e  %.2e  %.2e  %.2e   %+.2e      %+.2e"
              % (N, *err, pt["sxx"][0] / (3 * P) - 1, pt["syy"][1] / (-P) - 1))
    print("(max |u| of the Kirsch field on the grid: %.3e m)"
          % np.max(np.hypot(ex[0], ex[1])))


if __name__ == "__main__":
    main()
