#!/usr/bin/env python3
"""Column test: every point column gets u_x = eps x (u_y free, one point pinned), so the force
through a cut is the section's axial stiffness without supports. Measured section factor
(force / (E H eps)) at x = 0.25 and 0.75 against theory.section(). Writes results/columns_study.json."""
import json, os
import pd, theory

rows = []


def go(**kw):
    p = pd.defaults(sup="columns", **kw)
    x = pd.run(p)
    for c, E, dx in ((0.25, 1.0, x["dxl"]), (0.75, p["e2"], x["dxr"])):
        s = x["cuts"][c] / (pd.EPS * p["H"] * E)
        if p["kind"] == "shear":
            wtd, grd, _ = theory.section(int(round(p["H"] / dx)), p["m"], p["nu"], p["vc"])
            pr = wtd if p["dil"] == "weighted" else grd
        else:
            pr = float("nan")
        rows.append(dict(kind=p["kind"], nu=p["nu"], dx=dx, H=p["H"], m=p["m"], dil=p["dil"], vc=p["vc"],
                         section=s, predicted=pr, scene=x["name"]))
        print(f"{p['kind']:10s} nu={p['nu']:.3f} dx={dx:.5f} H={p['H']} m={p['m']} {p['dil']:8s} {p['vc']:7s}: "
              f"section stiffness / (E H) = {s:.4f}  (prediction {pr:.4f})", flush=True)


if __name__ == "__main__":
    for nu in (1/3, 0.0):
        for kind in ("shear", "bond_based"):
            go(kind=kind, nu=nu)
        go(nu=nu, dil="gradient")
        go(nu=nu, r=2)
        go(nu=nu, r=2, dil="gradient")
        for H in (0.2, 0.4):
            go(nu=nu, H=H)
        for m in (2.015, 4.015):
            go(nu=nu, m=m)
        for vc in ("ramp", "none"):
            go(nu=nu, vc=vc)
    for nu in (0.25, 0.45, -0.3):
        go(nu=nu)
    json.dump(rows, open(os.path.join(pd.RESULTS, "columns_study.json"), "w"), indent=1)
