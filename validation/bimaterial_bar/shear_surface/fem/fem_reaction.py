#!/usr/bin/env python3
"""FEM reaction of the strip for a given (a, b, H, nu, E2, left BC), reusing the repository's
../../fem/fem_bimaterial_strip.py with its module constants overridden. Prints and appends one
JSON line (the reaction on each mesh of the sequence) to ../results/fem_reactions.jsonl.
Usage: fem_reaction.py --a 0.025 --b 0.9725 --H 0.1 --nu 0.3333 --e2 2 [--hs 0.005,0.0025,0.00125] [--roller]"""
import argparse, json, os, sys, time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "fem"))
import fem_bimaterial_strip as F

ap = argparse.ArgumentParser()
ap.add_argument("--a", type=float, default=0.025)
ap.add_argument("--b", type=float, default=0.9725)
ap.add_argument("--H", type=float, default=0.1)
ap.add_argument("--nu", type=float, default=1/3)
ap.add_argument("--e2", type=float, default=2.0)
ap.add_argument("--hs", default="0.005,0.0025,0.00125")
ap.add_argument("--roller", action="store_true")
ap.add_argument("--tag", default="")
args = ap.parse_args()
F.H, F.NU, F.E2 = args.H, args.nu, args.e2
res = []
for h in [float(s) for s in args.hs.split(",")]:
    t = time.perf_counter()
    _, basis, u, r, _ = F.solve_level(args.a, args.b, h, clamp=not args.roller, e2=args.e2)
    res.append({"h": h, "ndofs": int(basis.N), "reaction_x": r})
    print(f"h={h} ndofs={basis.N} R={r:.10e} ({time.perf_counter()-t:.1f}s)", flush=True)
out = {"tag": args.tag, "a": args.a, "b": args.b, "H": args.H, "nu": args.nu, "E1": 1.0, "E2": args.e2,
       "left": "roller" if args.roller else "clamped", "levels": res,
       "reaction_x": res[-1]["reaction_x"],
       "est_error": abs(res[-1]["reaction_x"] - res[-2]["reaction_x"]) if len(res) > 1 else None}
with open(os.path.join(HERE, "..", "results", "fem_reactions.jsonl"), "a") as f:
    f.write(json.dumps(out) + "\n")
print(json.dumps(out))
