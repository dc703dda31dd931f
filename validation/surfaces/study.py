#!/usr/bin/env python3
"""Runs the 3D surface cases (scenes/) and compares their stiffness with the
scikit-fem references (fem/reference_surfaces3d.json): issue 33's table.

Each scene runs as committed (the corrected models, dhpd's defaults) and as
the uncorrected variant (bond-based: discretization.surface_correction =
"none"; shear: model.formulation = "paper"), written to work/ (git-ignored).
Stiffness: bar and plate, grip force over grip displacement; cantilever, the
1 N tip load over the mean deflection of the outermost point layer (the FEM's
is sampled at the same points).

Run (after cargo build --release):
    python3 validation/surfaces/study.py [--cases bar,cantilever,plate] [--n 4,8]
writes results/study.json and prints the table (about 15 min in all on 2 cores).
"""
import argparse
import csv
import json
import os
import re
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DHPD = os.environ.get("DHPD", os.path.join(ROOT, "target", "release", "dhpd"))
H = 0.04
U = 1e-4


def variant(text, kind, corrected):
    if kind == "bond_based":
        value = "energy" if corrected else "none"
        return text.replace("[output]", f'[discretization]\nsurface_correction = "{value}"\n\n[output]')
    value = "energy" if corrected else "paper"
    return text.replace('kind = "shear"', f'kind = "shear"\nformulation = "{value}"')


def stiffness(case, out, n):
    if case == "cantilever":
        with open(os.path.join(out, "points.csv")) as fh:
            rows = list(csv.DictReader(fh))
        dx = H / n
        tip = [float(r["u_z"]) for r in rows if float(r["x"]) > 0.20 - dx]
        return 1.0 / (-sum(tip) / len(tip))
    with open(os.path.join(out, "summary.json")) as fh:
        s = json.load(fh)
    right = [r for r in s["reactions"] if r["name"] == "right"][0]
    return right["force"][0] / U


def run(case, kind, n, corrected):
    name = f"{case}_{kind}_n{n}"
    with open(os.path.join(HERE, "scenes", name + ".toml")) as fh:
        text = fh.read()
    work = os.path.join(HERE, "work")
    os.makedirs(work, exist_ok=True)
    tag = "corrected" if corrected else "plain"
    scene = os.path.join(work, f"{name}_{tag}.toml")
    with open(scene, "w") as fh:
        fh.write(variant(text, kind, corrected).replace(f'name = "{name}"', f'name = "{name}_{tag}"'))
    out = os.path.join(work, f"{name}_{tag}")
    t0 = time.perf_counter()
    p = subprocess.run([DHPD, "run", scene, "--out", out], capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    if p.returncode != 0:
        return {"error": p.stderr.strip()[-400:], "seconds": seconds}
    route = re.search(r"solver: (.*)", p.stdout)
    return {"k": stiffness(case, out, n), "seconds": round(seconds, 2),
            "route": route.group(1) if route else None}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", default="bar,cantilever,plate")
    ap.add_argument("--kinds", default="bond_based,shear")
    ap.add_argument("--n", default="4,6,8,12,16")
    ap.add_argument("--variants", default="corrected,plain")
    args = ap.parse_args()
    with open(os.path.join(HERE, "fem", "reference_surfaces3d.json")) as fh:
        fem = json.load(fh)["cases"]
    path = os.path.join(HERE, "results", "study.json")
    results = json.load(open(path)) if os.path.exists(path) else {}
    for case in args.cases.split(","):
        for kind in args.kinds.split(","):
            for n in map(int, args.n.split(",")):
                if not os.path.exists(os.path.join(HERE, "scenes", f"{case}_{kind}_n{n}.toml")):
                    continue
                ref = fem[f"cantilever_n{n}"]["k"] if case == "cantilever" else fem[case]["k"]
                for v in args.variants.split(","):
                    r = run(case, kind, n, v == "corrected")
                    if "k" in r:
                        r["error_vs_fem"] = r["k"] / ref - 1.0
                    r["fem"] = ref
                    results[f"{case}/{kind}/n{n}/{v}"] = r
                    err = f"{100 * r['error_vs_fem']:+.2f} %" if "k" in r else r["error"]
                    print(f"{case:10} {kind:10} n={n:2} {v:9}: {err} ({r['seconds']:.1f} s, {r.get('route')})", flush=True)
                    os.makedirs(os.path.dirname(path), exist_ok=True)
                    with open(path, "w") as fh:
                        json.dump(results, fh, indent=1, sort_keys=True)


if __name__ == "__main__":
    main()
