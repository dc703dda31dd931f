#!/usr/bin/env python3
"""Re-implements the linearised shear-model bond force (src/model/shear.rs, formulation Sec. 4)
from points.csv of a dhpd run of the strip (strip_2d.toml with kind = "shear" and stress output,
run through pd.py), and computes for the cuts x = 0.25 and x = 0.75
  (1) the exact force through the cut (all owner bonds crossing it), which must equal the
      reaction (a check of this re-implementation),
  (2) per row of the column next to the cut: the Eq. 32 stress sigma_xx (dhpd output), the
      force flux P_xx = sum_j f_ij xi_x V_j nu_ij (what the row transmits) and alpha = (Kxx-Kyy)/m.
Usage: flux.py NU [--gradient]   ->  results/flux_nu{NU}_{weighted|gradient}_cut{c}.json"""
import sys, csv, math, json, os
import numpy as np
from scipy.spatial import cKDTree
import pd
from theory import factor

def load(out):
    rows = list(csv.DictReader(open(f"{out}/points.csv")))
    g = lambda k: np.array([float(r[k]) for r in rows])
    P = dict(x=np.c_[g("x"), g("y")], u=np.c_[g("u_x"), g("u_y")], V=g("volume"), dx=g("spacing"),
             delta=g("horizon"), E=np.array([1.0 if r["material"] == "soft" else 2.0 for r in rows]))  # E1 = 1, E2 = 2
    if "sxx" in rows[0]:
        P["sxx"] = g("sxx")
    return P

def families(P, rule="overlap"):
    tree = cKDTree(P["x"])
    reach = (P["dx"] / math.sqrt(math.pi)).max()
    fam = []
    for i in range(len(P["V"])):
        js = tree.query_ball_point(P["x"][i], P["delta"][i] + reach + 1e-12)
        out = []
        for j in js:
            if j == i: continue
            d = np.linalg.norm(P["x"][j] - P["x"][i])
            f = factor(d, P["delta"][i], P["dx"][j], rule)
            if f > 0: out.append((j, f))
        fam.append(out)
    return fam

def owner_forces(P, fam, i, nu, gradient=False):
    E = P["E"][i]; mu = E / (2 * (1 + nu)); kap = E / (2 * (1 - nu))
    js = np.array([j for j, _ in fam[i]]); nf = np.array([f for _, f in fam[i]])
    xi = P["x"][js] - P["x"][i]; eta = P["u"][js] - P["u"][i]
    l2 = (xi**2).sum(1); w = P["V"][js] * nf / l2
    m = (w * l2).sum(); K = (w[:, None, None] * xi[:, :, None] * xi[:, None, :]).sum(0)
    Ki = np.linalg.inv(K); b = (w[:, None] * (xi @ Ki.T))
    G = (eta[:, :, None] * b[:, None, :]).sum(0); W = 0.5 * (G - G.T)
    theta = np.trace(G) if gradient else 2 / m * (w * (eta * xi).sum(1)).sum()
    er = eta - xi @ W.T
    f = (2 / (l2 * m))[:, None] * (kap * theta * xi + 2 * mu * (er - theta / 2 * xi))
    return js, nf, xi, f, m, K

def analyse(out, nu, c, grad):
    P = load(out); fam = families(P)
    x = P["x"]
    # exact cut force: bonds i->j with x_i < c < x_j: force on the right part = -f V_i V_j nu (on j);
    # bonds with x_i > c > x_j: force on i (right) = +f V_i V_j nu
    F = 0.0
    near = np.where(np.abs(x[:, 0] - c) < 0.07)[0]
    rowdata = []
    dxc = P["dx"][np.argmin(np.abs(x[:, 0] - c))]
    col = near[np.abs(x[near, 0] - (c + dxc / 2)) < 1e-9]     # the column just right of the cut
    for i in near:
        js, nf, xi, f, m, K = owner_forces(P, fam, i, nu, grad)
        fv = f * (P["V"][i] * P["V"][js] * nf)[:, None]
        if x[i, 0] < c:
            F -= fv[x[js, 0] > c, 0].sum()
        else:
            F += fv[x[js, 0] < c, 0].sum()
        if i in col:
            Pxx = (f[:, 0] * xi[:, 0] * P["V"][js] * nf).sum()
            rowdata.append(dict(y=x[i, 1], alpha=(K[0, 0] - K[1, 1]) / m, Pxx=Pxx,
                                sxx=P.get("sxx", np.full(len(x), np.nan))[i], ux=P["u"][i, 0]))
    rowdata.sort(key=lambda r: r["y"])
    print(f"cut x={c}: force through the cut (re-implementation) = {-F:.6e}  [sign: tension > 0]")
    Fp = sum(r["Pxx"] for r in rowdata) * dxc
    Fs = sum(r["sxx"] for r in rowdata) * dxc
    print(f"  sum over the column next to the cut: sum P_xx dy = {Fp:.6e}, sum sigma_xx(Eq.32) dy = {Fs:.6e}")
    for r in rowdata:
        print(f"  y={r['y']:.4f} alpha={r['alpha']:+.4f} sigma_xx(Eq.32)={r['sxx']:.5e} P_xx={r['Pxx']:.5e} P/sigma={r['Pxx']/r['sxx']:.4f}")
    return dict(cut=c, F=-F, sumP=Fp, sumS=Fs, rows=rowdata)


if __name__ == "__main__":
    nu = float(sys.argv[1])
    dil = "gradient" if "--gradient" in sys.argv else "weighted"
    res = pd.run(pd.defaults(nu=nu, dil=dil, stress=True))
    print(f"dhpd reaction (right) = {res['rx']['right']:.6e}")
    for c in (0.25, 0.75):
        out = analyse(res["out"], nu, c, dil == "gradient")
        json.dump(out, open(os.path.join(pd.RESULTS, f"flux_nu{nu:.4f}_{dil}_cut{c}.json"), "w"), indent=1)
