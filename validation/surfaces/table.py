#!/usr/bin/env python3
"""Prints results/study.json as the report's Markdown table (error in % vs FEM)."""
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
r = json.load(open(os.path.join(HERE, "results", "study.json")))
ns = sorted({int(k.split("/")[2][1:]) for k in r})
print("| case | model | " + " | ".join(f"n = {n}" for n in ns) + " |")
print("|---|---|" + "---|" * len(ns))
for case in ["bar", "cantilever", "plate"]:
    for kind, label in [("bond_based", "bond-based"), ("shear", "shear")]:
        for v, vl in [("plain", "before"), ("corrected", "after")]:
            cells = []
            for n in ns:
                x = r.get(f"{case}/{kind}/n{n}/{v}")
                cells.append(f"{100 * x['error_vs_fem']:+.1f} % ({x['seconds']:.1f} s)" if x and "error_vs_fem" in x else "–")
            print(f"| {case} | {label}, {vl} | " + " | ".join(cells) + " |")
