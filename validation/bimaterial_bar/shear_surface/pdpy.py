#!/usr/bin/env python3
"""Small Python re-implementation of the linearised shear model (single material, uniform
grid, overlap partial volumes) to test a surface-corrected force against the paper's force.
  paper_w : f = (d w/m)[(k-2mu/d) theta_w xi + 2mu (eta - W xi)],  theta_w = (d/m) sum w xi.eta
  paper_g : the same with theta = tr G                         (dhpd's dilatation = "gradient")
  corrected: f = w[(k-2mu/d) trG K^-1 xi + 2mu (G_s K^-1 xi + (d/m)(eta - G xi))]
             (identical to paper_* wherever K = (m/d) I, i.e. full symmetric families; its flux
              tensor sum f(x)xi V = (k-2mu/d) trG I + 2mu G_s is Hooke's for ANY family)
Cases: 'strip' (layers x<=0.03 clamped, x>=0.97 u_x=1e-4, as strip_2d.toml) and 'columns'
(u_x = eps x on every column, u_y free, one u_y pinned; cut force at x=0.5).
Writes results/pdpy_results.json. Not part of dhpd: the corrected force exists only here."""
import math, json, os
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spl
from scipy.spatial import cKDTree
from theory import factor

RESULTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results")

def grid(L, H, dx):
    xs = (np.arange(int(round(L / dx))) + 0.5) * dx
    ys = (np.arange(int(round(H / dx))) + 0.5) * dx
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    return np.c_[X.ravel(), Y.ravel()]

def stiffness(x, dx, mfac, E, nu, mode):
    N = len(x); V = dx * dx; delta = mfac * dx
    mu = E / (2 * (1 + nu)); kap = E / (2 * (1 - nu)); d = 2
    tree = cKDTree(x); reach = dx / math.sqrt(math.pi)
    rows, cols, vals = [], [], []
    for i in range(N):
        js = np.array([j for j in tree.query_ball_point(x[i], delta + reach + 1e-12) if j != i])
        xi = x[js] - x[i]; l2 = (xi**2).sum(1)
        nf = np.array([factor(math.sqrt(v), delta, dx, "overlap") for v in l2])
        keep = nf > 0; js, xi, l2, nf = js[keep], xi[keep], l2[keep], nf[keep]
        n = len(js); om = 1 / l2; w = om * V * nf
        m = (w * l2).sum(); K = np.einsum("j,ja,jb->ab", w, xi, xi); Ki = np.linalg.inv(K)
        b = w[:, None] * (xi @ Ki)                      # b_j = w_j K^-1 xi_j (K symmetric)
        # probe: unknowns u_S, S = [i, js...], 2 components each -> C = 2(n+1) columns
        C = 2 * (n + 1); U = np.zeros((n + 1, 2, C))
        for s in range(n + 1):
            for a in range(2):
                U[s, a, 2 * s + a] = 1.0
        eta = U[1:] - U[0][None]                        # (n, 2, C)
        G = np.einsum("jaC,jb->abC", eta, b)
        W = 0.5 * (G - G.transpose(1, 0, 2)); Gs = 0.5 * (G + G.transpose(1, 0, 2))
        trG = G[0, 0] + G[1, 1]
        if mode == "paper_w":
            th = d / m * np.einsum("j,ja,jaC->C", w, xi, eta)
        else:
            th = trG
        if mode in ("paper_w", "paper_g"):
            Wxi = np.einsum("abC,jb->jaC", W, xi)
            f = (d * om / m)[:, None, None] * ((kap - 2 * mu / d) * th[None, None, :] * xi[:, :, None]
                                               + 2 * mu * (eta - Wxi))
        else:
            Kxi = xi @ Ki                                # K^-1 xi_j (rows)
            Gxi = np.einsum("abC,jb->jaC", G, xi)
            GsKxi = np.einsum("abC,jb->jaC", Gs, Kxi)
            f = om[:, None, None] * ((kap - 2 * mu / d) * th[None, None, :] * Kxi[:, :, None]
                                     + 2 * mu * (GsKxi + d / m * (eta - Gxi)))
        fv = f * (V * V * nf)[:, None, None]            # force on i: +fv, on j: -fv
        Fi = fv.sum(0)                                   # (2, C)
        S = np.r_[i, js]
        dof_c = (2 * S[:, None] + np.arange(2)[None]).ravel()
        # K = -dF/du
        for a in range(2):
            rows.append(np.full(C, 2 * i + a)); cols.append(dof_c); vals.append(-Fi[a])
        for jj in range(n):
            for a in range(2):
                rows.append(np.full(C, 2 * js[jj] + a)); cols.append(dof_c); vals.append(fv[jj, a])
    Kg = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(2 * N, 2 * N))
    return Kg

def solve(Kg, fixed, uval):
    N2 = Kg.shape[0]; free = np.setdiff1d(np.arange(N2), fixed)
    u = np.zeros(N2); u[fixed] = uval
    rhs = -Kg[free][:, fixed] @ u[fixed]
    u[free] = spl.spsolve(Kg[free][:, free].tocsc(), rhs)
    return u, Kg @ u                                   # reaction = K u on constrained dofs

def run(dx, H, nu, mode, case, mfac=3.015, E=1.0, L=1.0):
    x = grid(L, H, dx); Kg = stiffness(x, dx, mfac, E, nu, mode)
    if case == "strip":
        left = np.where(x[:, 0] <= 0.03 + 1e-12)[0]; right = np.where(x[:, 0] >= 0.97 - 1e-12)[0]
        fixed = np.r_[2 * left, 2 * left + 1, 2 * right]
        uval = np.r_[np.zeros(2 * len(left)), np.full(len(right), 1e-4)]
        u, r = solve(Kg, fixed, uval)
        R = r[2 * right].sum()
        a = x[left, 0].max(); b = x[right, 0].min()
        return dict(R=R, a=a, b=b)
    else:
        eps = 1e-4
        pin = np.argmin(np.abs(x[:, 0] - (0.5 - dx / 2)) + np.abs(x[:, 1] - dx * (math.floor(H / 2 / dx) + 0.5)))
        fixed = np.r_[2 * np.arange(len(x)), 2 * pin + 1]
        uval = np.r_[eps * x[:, 0], 0.0]
        u, r = solve(Kg, fixed, uval)
        cut = -r[2 * np.where(x[:, 0] < 0.5)[0]].sum()
        return dict(section=cut / (E * H * eps))

if __name__ == "__main__":
    out = []
    for dx in (0.01, 0.005):
        for nu in (0.0, 1 / 3):
            for mode in ("paper_w", "paper_g", "corrected"):
                for case in ("columns", "strip"):
                    res = run(dx, 0.1, nu, mode, case)
                    res.update(dx=dx, nu=nu, mode=mode, case=case, H=0.1)
                    out.append(res); print(res, flush=True)
    json.dump(out, open(os.path.join(RESULTS, "pdpy_results.json"), "w"), indent=1)
