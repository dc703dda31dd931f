#!/usr/bin/env python3
"""results/*.json -> results/tables.md (the reaction table and the column-test table)."""
import json, os
import pd


def load(fn):
    return json.load(open(os.path.join(pd.RESULTS, fn)))


def nu_str(nu):
    return "1/3" if abs(nu - 1/3) < 1e-9 else f"{nu:g}"


out = []
rows = load("full_study.json") + load("full_study_repo.json") + load("full_study_bb_extra.json")
out.append("| model | ν | Δx left/right (m) | H (m) | m = δ/Δx | dilatation | volume corr. | support variant (FEM domain a..b) | reaction dhpd (N) | reaction FEM (N) | error | section-stiffness prediction | rest (supports + interface) |")
out.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
seen = set()
for r in rows:
    key = (r["kind"], r["nu"], r["dxl"], r["dxr"], r["H"], r["m"], r["dil"], r["vc"], r["sup"], r["e2"])
    if key in seen:
        continue
    seen.add(key)
    sup = {"std": "scene layers 0.03/0.97", "roller": "left roller (u_x only, u_y pinned mid-height)",
           "repo": "repo layers (0.025+Δx/4 / 0.9725−Δx/4)"}[r["sup"]]
    if r["e2"] == 1.0:
        sup += ", single material E=1"
    dil = r["dil"] if r["kind"] == "shear" else "–"
    out.append(f"| {r['kind']} | {nu_str(r['nu'])} | {r['dxl']:.4g} / {r['dxr']:.4g} | {r['H']} | {r['m']} | {dil} | {r['vc']} | {sup} ({r['a']:.5g}..{r['b']:.5g}) | "
               f"{r['R']:.5e} | {r['R_fem']:.5e} | {100*r['err']:+.2f} % | {100*(r['series']-1):+.2f} % | {100*r['residual']:+.2f} % |")
out.append("")
out.append("| model | ν | Δx (m) | H (m) | m | dilatation | volume corr. | section stiffness / (E H) measured | prediction mean(1+α)(1+αν/(1−ν)) [weighted] or mean(1+α) [gradient] |")
out.append("|---|---|---|---|---|---|---|---|---|")
seen = set()
for c in load("columns_study.json"):
    key = (c["kind"], c["nu"], c["dx"], c["H"], c["m"], c["dil"], c["vc"])
    if key in seen or (c["kind"] == "bond_based" and c["nu"] != 1/3):
        continue
    seen.add(key)
    dil, pr = (c["dil"], f"{c['predicted']:.4f}") if c["kind"] == "shear" else ("–", "–")
    out.append(f"| {c['kind']} | {nu_str(c['nu'])} | {c['dx']:.4g} | {c['H']} | {c['m']} | {dil} | {c['vc']} | {c['section']:.4f} | {pr} |")
open(os.path.join(pd.RESULTS, "tables.md"), "w").write("\n".join(out) + "\n")
