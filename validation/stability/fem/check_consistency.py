#!/usr/bin/env python3
"""Independent consistency checks of the plane-strain references (about 5 s).

Reads reference_nu*.json (written by fem_plate_with_hole_plane_strain.py) and
the plane-stress reference ../../plate_with_hole/fem/reference.json.

1. Convergence of the mixed solution: observed order and Richardson
   extrapolate from the last three levels, and the estimated error of the
   finest level (|finest - Richardson| / |Richardson|).
2. Michell's theorem: with traction boundary conditions, a traction-free hole
   and self-equilibrated edge loads, the exact in-plane stress does not
   depend on the elastic constants, so plane strain at any nu and plane stress
   must give the same stress.  The hole stresses are compared with the
   Richardson values of the plane-stress reference (N = 32, 64, 128).
3. nu-scaling of the displacement: since sigma is nu-independent, the exact
   plane-strain displacement is u(nu) = (1 + nu) (U1 - nu U2) with fixed
   fields U1 (from eps = sigma / E) and U2 (from eps = tr(sigma) I / E), and
   plane stress gives u = (1 + nu) U1 - nu U2.  U1, U2 are solved from the
   nu = 0.3 and 0.45 grids; the prediction is compared with the computed
   nu = 0.49, 0.499, 0.4999 grids and with the plane-stress reference grid
   (nu = 1/3, every second sample, dx = 0.01).
"""
import json
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
NUS = [0.3, 0.45, 0.49, 0.499, 0.4999]


def load(nu):
    with open(os.path.join(HERE, "reference_nu%g.json" % nu)) as fh:
        return json.load(fh)


def arr(g, k):
    return np.array([[np.nan if v is None else v for v in row]
                     for row in g[k]])


def main():
    refs = {nu: load(nu) for nu in NUS}
    with open(os.path.join(HERE, "..", "..", "plate_with_hole", "fem",
                           "reference.json")) as fh:
        ps = json.load(fh)
    cs = ps["convergence_summary"]
    sxx_ex = cs["sxx_hole_top"]["richardson_extrapolate"]
    syy_ex = cs["syy_hole_side"]["richardson_extrapolate"]

    print("1. mixed formulation: observed order (levels 16, 32, 64), "
          "Richardson extrapolate, est. rel. error of N=64")
    print("%-7s %-14s %7s %18s %10s" % ("nu", "quantity", "order",
                                        "Richardson", "err N=64"))
    for nu in NUS:
        rows = [r for r in refs[nu]["convergence"]
                if r["formulation"] == "mixed"]
        for key in ("max_abs_u", "sxx_hole_top", "syy_hole_side"):
            a, b, c = (rows[-3][key], rows[-2][key], rows[-1][key])
            if (b - a) * (c - b) > 0:
                p = np.log2((b - a) / (c - b))
                rich = c + (c - b) / (2 ** p - 1)
                print("%-7g %-14s %7.2f %18.10e %10.1e" % (
                    nu, key, p, rich, abs(c / rich - 1)))
            else:
                print("%-7g %-14s %7s %18s %10.1e (non-monotone; last "
                      "change)" % (nu, key, "-", "-", abs(c / b - 1)))

    print("\n2. Michell: hole stresses vs plane-stress Richardson values "
          "sxx(0,R) = %.8e, syy(R,0) = %.8e Pa (rel. diff.)" % (sxx_ex,
                                                                  syy_ex))
    print("%-7s %12s %12s %12s %12s" % ("nu", "mixed sxx", "mixed syy",
                                        "P2-disp sxx", "P2-disp syy"))
    for nu in NUS:
        rows = refs[nu]["convergence"]
        m = [r for r in rows if r["formulation"] == "mixed"][-1]
        d = [r for r in rows if r["formulation"] == "disp"][-1]
        print("%-7g %+12.2e %+12.2e %+12.2e %+12.2e" % (
            nu, m["sxx_hole_top"] / sxx_ex - 1, m["syy_hole_side"] / syy_ex - 1,
            d["sxx_hole_top"] / sxx_ex - 1, d["syy_hole_side"] / syy_ex - 1))

    print("\n3. nu-scaling of u: fields U1, U2 from the nu = 0.3 and 0.45 "
          "grids; rel. L2 difference (and rel. diff. of ux(0.5,0)) of the "
          "prediction vs the computed grid")
    ux = {nu: arr(refs[nu]["grid"], "ux") for nu in NUS}
    uy = {nu: arr(refs[nu]["grid"], "uy") for nu in NUS}

    def fields(n1, n2):
        # u(nu)/(1+nu) = U1 - nu U2
        out = []
        for u in (ux, uy):
            a1, a2 = u[n1] / (1 + n1), u[n2] / (1 + n2)
            U2 = (a1 - a2) / (n2 - n1)
            U1 = a1 + n1 * U2
            out.append((U1, U2))
        return out

    (X1, X2), (Y1, Y2) = fields(0.3, 0.45)
    i0 = 50   # x = 0 column; row iy = 50 is y = 0; ix = 100 is x = 0.5

    def rel(px, py, cx, cy):
        ok = np.isfinite(cx)
        num = np.sum((px - cx)[ok] ** 2 + (py - cy)[ok] ** 2)
        den = np.sum(cx[ok] ** 2 + cy[ok] ** 2)
        return np.sqrt(num / den), px[i0, 100] / cx[i0, 100] - 1
    for nu in (0.49, 0.499, 0.4999):
        px, py = (1 + nu) * (X1 - nu * X2), (1 + nu) * (Y1 - nu * Y2)
        print("  plane strain nu = %-7g L2 %.2e   ux(0.5,0) %+.2e"
              % ((nu,) + rel(px, py, ux[nu], uy[nu])))
    nps = 1.0 / 3.0
    px, py = (1 + nps) * X1 - nps * X2, (1 + nps) * Y1 - nps * Y2
    cx = arr(ps["grid"], "ux")[::2, ::2]
    cy = arr(ps["grid"], "uy")[::2, ::2]
    print("  plane stress nu = 1/3 (reference.json, N=128) L2 %.2e   "
          "ux(0.5,0) %+.2e" % rel(px, py, cx, cy))


if __name__ == "__main__":
    main()
