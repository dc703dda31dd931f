#!/usr/bin/env python3
"""FEM sigma_xx(y) across the strip at x = 0.25 and x = 0.75 (P2 gradients via the sampler of
../../fem/fem_bimaterial_strip.py), h = 0.0025, and the section integral.
Usage: fem_profile.py NU [a b]  ->  ../results/profile_nu{NU:.4f}.json"""
import json, os, sys
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "fem"))
import fem_bimaterial_strip as F

nu = float(sys.argv[1]); a = float(sys.argv[2]) if len(sys.argv) > 2 else 0.025
b = float(sys.argv[3]) if len(sys.argv) > 3 else 0.9725
F.NU = nu
mesh, basis, u, R, _ = F.solve_level(a, b, 0.0025)
out = {"nu": nu, "a": a, "b": b, "h": 0.0025, "reaction_x": R}
for xs, E in ((0.25, F.E1), (0.75, F.E2)):
    ys = (np.arange(2000) + 0.5) * F.H / 2000
    _, _, exx, eyy = F.sample(mesh, basis, u, np.full_like(ys, xs), ys, a, b)
    sxx = E / (1 - nu**2) * (exx + nu * eyy)
    yr = np.array(sorted(set(np.round(np.r_[(np.arange(10) + 0.5) * 0.01, (np.arange(20) + 0.5) * 0.005], 6))))
    _, _, e1, e2 = F.sample(mesh, basis, u, np.full_like(yr, xs), yr, a, b)
    out[f"x={xs}"] = {"section_integral": float(sxx.sum() * F.H / 2000),
                      "y": yr.tolist(), "sxx": (E / (1 - nu**2) * (e1 + nu * e2)).tolist()}
    print(f"nu={nu} x={xs}: int sxx dy = {sxx.sum()*F.H/2000:.6e} (R = {R:.6e}); sxx min/max over y {sxx.min():.5e}/{sxx.max():.5e}")
json.dump(out, open(os.path.join(HERE, "..", "results", f"profile_nu{nu:.4f}.json"), "w"), indent=1)
