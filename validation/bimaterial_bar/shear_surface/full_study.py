#!/usr/bin/env python3
"""The strip's reaction against FEM (results/fem_reactions.jsonl, domain [a, b] = the innermost
constrained point centres of each PD run), and the part explained by the free edges: the series
combination of the two halves' section factors s1, s2 measured by the column test at the same
parameters. Writes results/full_study.json, full_study_repo.json, full_study_bb_extra.json."""
import json, os
import pd

REF_ORIG = 1.40930432696e-05   # ../fem/reference.json (a = 0.025, b = 0.9725)


def fem_lookup(a, b, H, nu, e2, left="clamped"):
    best = None
    for line in open(os.path.join(pd.RESULTS, "fem_reactions.jsonl")):
        d = json.loads(line)
        if (abs(d["a"] - a) < 1e-9 and abs(d["b"] - b) < 1e-9 and abs(d["H"] - H) < 1e-12
                and abs(d["nu"] - nu) < 1e-12 and d["E2"] == e2 and d["left"] == left):
            best = d
    return best


def case(**kw):
    p = pd.defaults(**kw)
    x = pd.run(p)
    R = x["rx"]["right"]
    fem = fem_lookup(x["a"], x["b"], p["H"], p["nu"], p["e2"], "roller" if p["sup"] == "roller" else "clamped")
    Rf = fem["reaction_x"] if fem else float("nan")
    c = pd.run(dict(p, sup="columns", stress=False))
    s1 = c["cuts"][0.25] / (pd.EPS * p["H"] * 1.0)
    s2 = c["cuts"][0.75] / (pd.EPS * p["H"] * p["e2"])
    L1, L2 = 0.5 - x["a"], x["b"] - 0.5
    series = (L1 / 1.0 + L2 / p["e2"]) / (L1 / (1.0 * s1) + L2 / (p["e2"] * s2))
    row = dict(kind=p["kind"], nu=p["nu"], dxl=x["dxl"], dxr=x["dxr"], H=p["H"], m=p["m"], e2=p["e2"],
               dil=p["dil"], vc=p["vc"], sup=p["sup"], a=x["a"], b=x["b"], R=R, R_fem=Rf,
               err=R / Rf - 1, err_vs_orig_ref=R / REF_ORIG - 1, s1=s1, s2=s2, series=series,
               residual=R / (Rf * series) - 1, scene=x["name"] + ".toml")
    print(f"{p['kind']:10s} nu={p['nu']:.3f} dx={x['dxl']:.5f}/{x['dxr']:.5f} H={p['H']} m={p['m']} e2={p['e2']} "
          f"{p['dil']:8s} {p['vc']:7s} {p['sup']:6s} R={R:.5e} FEM={Rf:.5e} err={100*(R/Rf-1):+.2f}% "
          f"section s1={s1:.4f} s2={s2:.4f} -> series {100*(series-1):+.2f}%, rest {100*row['residual']:+.2f}%",
          flush=True)
    return row


def main_rows():
    rows = []
    for nu in (1/3, 0.0):
        for r in (1, 2, 3, 4):
            rows.append(case(nu=nu, r=r))
        for r in (1, 2):
            rows.append(case(nu=nu, r=r, dil="gradient"))
        for m in (2.015, 4.015):
            rows.append(case(nu=nu, m=m))
        for vc in ("ramp", "none"):
            rows.append(case(nu=nu, vc=vc))
        for H in (0.2, 0.4):
            rows.append(case(nu=nu, H=H))
        for u in (0.01, 0.005):
            rows.append(case(nu=nu, e2=1.0, uniform=u))
        rows.append(case(nu=nu, sup="roller"))
    for r in (1, 2, 3, 4):
        rows.append(case(kind="bond_based", r=r))
    return rows


def repo_rows():
    """The layers of src/validation: a = 0.025, b = 0.9725 at r = 1, 3, 5 (the README's table)."""
    rows = []
    for r in (1, 3, 5):
        for kind in ("shear", "bond_based"):
            rows.append(case(kind=kind, r=r, sup="repo"))
    rows.append(case(r=3, sup="repo", dil="gradient"))
    rows.append(case(r=3, sup="repo", nu=0.0))
    return rows


def bb_extra_rows():
    """Bond-based counterparts of the single-material and H = 0.4 rows."""
    return [case(kind="bond_based", e2=1.0, uniform=u) for u in (0.01, 0.005)] + [case(kind="bond_based", H=0.4)]


if __name__ == "__main__":
    for fn, rows in (("full_study.json", main_rows), ("full_study_repo.json", repo_rows),
                     ("full_study_bb_extra.json", bb_extra_rows)):
        json.dump(rows(), open(os.path.join(pd.RESULTS, fn), "w"), indent=1)
