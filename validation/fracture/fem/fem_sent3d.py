#!/usr/bin/env python3
"""FEM/LEFM reference for the clamped 3D SENT bar (problem E, issue 21 item 4).

Setup (the geometry of dhpd's 3D notched bar):
  body x in [0, W], y in [-L/2, L/2], z in [0, T]; W = 0.1 m, L = 0.2 m
  (free length between the grips), depths T = 0.02, 0.03, 0.04 m (others with
  --depths: 0.01 m for the thin bar of issue 19, reference_sent3d_thin.json);
  E = 30 GPa, linear elastic isotropic, small strain, nu = 1/4 and 1/3;
  through crack on y = 0 from x = 0 to x = a = 0.05 m (a/W = 0.5) over the
  whole depth (straight front along z at x = a), traction-free faces;
  clamped grips: u = (0, 0, 0) on the face y = -L/2, u = (0, Delta, 0) on
  the face y = +L/2 (all three components prescribed); the faces x = 0,
  x = W, z = 0, z = T are free.  All results per unit Delta (linear).

Model: the quarter y >= 0, z in [0, T/2] (mode I symmetry about y = 0 after
subtracting the rigid translation Delta/2, and mirror symmetry about the
mid-plane z = T/2):
  * top face y = L/2: u = (0, 1/2, 0) (i.e. Delta = 1);
  * y = 0: u_y = 0 on the ligament x > a, the crack faces x < a are free;
  * z = T/2: u_z = 0; z = 0 free (plane-strain check: u_z = 0 there too).
Bookkeeping: with P_q the y reaction of the quarter's top face, the grip
force of the whole bar is P = 2 P_q (two halves in z), so
  P/(Delta T) = 2 P_q / T,      U_bar = 4 U_q,
  G_avg = -(1/T) dP/da * (1/2) = -(1/T) dP_q/da   (compliance, Delta = 1),
  G_avg = 4 I_q / T             (domain integral I_q over the quarter).
The plane-strain check verifies this bookkeeping against the 2D code.

Mesh: a 2D triangle mesh of the quarter's cross-section [0, W] x [0, L/2]
(lefm_fem's structured base grid + red-green-blue refinement to
h = min(alpha W/2, alpha d), d = distance to the crack tip (floor 1e-3 W) or
to the two grip corners (floor 1e-4 W); the crack need not be opened since
y = 0 is a symmetry plane) is extruded through z layers graded
geometrically (factor 2) toward the free face z = 0, where the front meets
the free surface (corner singularity); each prism is split into 3
tetrahedra by the global-vertex-order rule (conforming).  P2 tetrahedra
(ElementVector(ElementTetP2())).  The layers are the same fractions of T/2
for every T, so the meshes of the three depths differ only by a z scaling.

Solve: the condensed system of the unshifted mesh for nu = 1/4 is factorised
once per mesh (SuperLU, MMD(A^T+A) ordering, symmetric mode); every solve
(both nu, the shifted meshes of the compliance derivative) is a preconditioned
CG with that factorisation as preconditioner, to a relative residual of
1e-13 (the shifted meshes need 3-5 iterations, nu = 1/3 about 15).

G_avg (energy released per unit crack area for a uniform advance of the whole
front) by two methods:
  (1) compliance: central difference over a with step delta = 1e-4 W; the
      meshes at a +- delta are the mesh of a with the nodes near the front
      shifted by +-delta phi(r), r = distance to the front line in the x-y
      plane (phi = 1 for r < 0.25 min(a, W - a), smooth step to 0 at 0.5
      min(a, W - a)), the same in every z layer: the whole front advances
      rigidly and the discretisation error cancels (as in the 2D code);
  (2) 3D domain integral I = int [sigma_ij u_i,1 - w delta_1j] q,j dV with
      q = q_2D(r) uniform in z (the smooth radial plateau of the 2D code),
      three annuli (0.20, 0.40), (0.35, 0.65), (0.50, 0.90) x min(a, W - a);
      the free face z = 0 and the symmetry planes carry no boundary term.
  G(z) along the front: q = q_2D(r) psi_k(z), psi_k the piecewise linear hat
  of layer node z_k; G(z_k) = 2 I_q[psi_k] / int_0^{T/2} psi_k dz (the hats
  sum to 1, so their weighted mean is G_avg exactly).
Critical load for G0 = 200 J/m^2: P_c/T = (P/T) sqrt(G0/G_avg), Delta_c =
sqrt(G0/G_avg) (G_avg = G_J of the main domain).
Bounds: plane stress and plane strain from the 2D code (lefm_fem, same level
as reference_sent.json) and from the committed reference.

Run:  python3 fem_sent3d.py     (writes reference_sent3d.json next to this file)
"""
import argparse
import json
import os
import platform
import resource
import time

import numpy as np
import scipy
import scipy.sparse.linalg as sla

import skfem
from skfem import (Basis, ElementTetP2, ElementVector, MeshTet, MeshTri1, asm)

from lefm_fem import (_a_div, _a_sym, graded_lines, point_size_field,
                      refine_to_size, smooth_step_q, structured_tri,
                      uniform_lines)

W = 0.1
L = 0.2
A_CRACK = 0.05
E = 30e9
G0 = 200.0
H0 = 0.025
TIP_FLOOR = 1e-3 * W       # in 2D this floor changes G_J by < 3e-6 (tested)
CORNER_FLOOR = 1e-4 * W
DELTA_A = 1e-4 * W
DOMAINS = [(0.20, 0.40), (0.35, 0.65), (0.50, 0.90)]
MAIN_DOMAIN = 1
DEPTHS = [0.02, 0.03, 0.04]
NUS = [("nu_1/4", 0.25), ("nu_1/3", 1.0 / 3.0)]
# mesh levels: in-plane alpha, number of z layers in [0, T/2], first layer / (T/2)
LEVELS = {0: dict(alpha=1.4, dz0=1e-2, dzmax=0.4),
          1: dict(alpha=1.0, dz0=2.5e-3, dzmax=0.25)}
PCG_RTOL = 1e-13


def lame3d(nu):
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def maxrss_gb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6


# --------------------------------------------------------------------- mesh
def section_mesh(alpha):
    xs = np.concatenate([uniform_lines(0, A_CRACK, H0)[:-1], uniform_lines(A_CRACK, W, H0)])
    ys = uniform_lines(0, L / 2, H0)
    p, t = structured_tri(xs, ys, lambda xc, yc: yc > 0)
    m = MeshTri1(p, t)
    sf = point_size_field([(A_CRACK, 0.0), (0, L / 2), (W, L / 2)], [alpha] * 3,
                          [TIP_FLOOR, CORNER_FLOOR, CORNER_FLOOR], alpha * W / 2)
    return refine_to_size(m, sf)


def z_fractions(dz0, dzmax):
    """Layer nodes in [0, 1] (fractions of T/2): geometric factor 2 from dz0 at z = 0 up to dzmax."""
    return graded_lines(0.0, 1.0, dz0, dzmax, growth=2.0)


def extrude(m2, zs):
    p2, t2 = m2.p, np.sort(m2.t, axis=0)
    n, nz = p2.shape[1], len(zs)
    P = np.vstack([np.tile(p2[0], nz), np.tile(p2[1], nz), np.repeat(zs, n)])
    tets = []
    for k in range(nz - 1):
        i0, i1, i2 = t2 + k * n
        j0, j1, j2 = t2 + (k + 1) * n
        # diagonal of every quad face from the lower-index bottom vertex to the
        # higher-index top vertex: conforming between neighbouring prisms
        tets += [np.vstack([i0, i1, i2, j2]), np.vstack([i0, i1, j1, j2]),
                 np.vstack([i0, j0, j1, j2])]
    return MeshTet(P, np.hstack(tets))


def morph(mesh, da):
    ell = min(A_CRACK, W - A_CRACK)
    p = mesh.p.copy()
    r = np.hypot(p[0] - A_CRACK, p[1])
    p[0] += da * smooth_step_q(r, 0.25 * ell, 0.5 * ell)
    return MeshTet(p, mesh.t)


class Model3D:
    def __init__(self, mesh):
        self.mesh = mesh
        self.basis = Basis(mesh, ElementVector(ElementTetP2()), intorder=2)
        self.K_div = asm(_a_div, self.basis).tocsr()
        self.K_sym = asm(_a_sym, self.basis).tocsr()

    def K(self, nu):
        lam, mu = lame3d(nu)
        return (lam * self.K_div + 2 * mu * self.K_sym).tocsr()


def dirichlet(model, T, plane_strain):
    m, b = model.mesh, model.basis
    tol = 1e-9
    top = b.get_dofs(facets=m.facets_satisfying(lambda x: np.abs(x[1] - L / 2) < tol))
    lig = b.get_dofs(facets=m.facets_satisfying(
        lambda x: (np.abs(x[1]) < tol) & (x[0] > A_CRACK + 1e-12)))
    mid = b.get_dofs(facets=m.facets_satisfying(lambda x: np.abs(x[2] - T / 2) < tol * T))
    fixed = {}
    for c in ("u^1", "u^3"):
        for d in top.all(c):
            fixed[int(d)] = 0.0
    for d in top.all("u^2"):
        fixed[int(d)] = 0.5
    for d in lig.all("u^2"):
        fixed[int(d)] = 0.0
    for d in mid.all("u^3"):
        fixed[int(d)] = 0.0
    if plane_strain:
        face = b.get_dofs(facets=m.facets_satisfying(lambda x: np.abs(x[2]) < tol * T))
        for d in face.all("u^3"):
            fixed[int(d)] = 0.0
    D = np.array(sorted(fixed), dtype=np.int64)
    vals = np.array([fixed[d] for d in D])
    return D, vals, np.asarray(top.all("u^2"))


class Solver:
    """LU of one condensed matrix, used as the preconditioner of PCG solves."""

    def __init__(self, K, D):
        self.N = K.shape[0]
        free = np.ones(self.N, bool)
        free[D] = False
        self.I = np.nonzero(free)[0]
        t0 = time.time()
        A = K[self.I][:, self.I].tocsc()
        self.lu = sla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options=dict(SymmetricMode=True))
        self.t_fact = time.time() - t0
        self.nnz_lu = int(self.lu.L.nnz + self.lu.U.nnz)

    def solve(self, K, D, vals):
        x = np.zeros(self.N)
        x[D] = vals
        A = K[self.I][:, self.I].tocsr()
        rhs = -(K[self.I] @ x)
        u = self.lu.solve(rhs)
        r = rhs - A @ u
        z = self.lu.solve(r)
        p = z.copy()
        rz = r @ z
        nb = np.linalg.norm(rhs)
        it = 0
        while np.linalg.norm(r) > PCG_RTOL * nb and it < 200:
            Ap = A @ p
            al = rz / (p @ Ap)
            u += al * p
            r -= al * Ap
            z = self.lu.solve(r)
            rz2 = r @ z
            p = z + rz2 / rz * p
            rz = rz2
            it += 1
        x[self.I] = u
        return x, it, float(np.linalg.norm(r) / nb)


# --------------------------------------------------------------- integrals
def domain_integrals(model, u, nu, T, zs, r1, r2, hats=True, intorder=3):
    """I_q over the quarter for q = q2D(r) and q = q2D(r) psi_k(z)."""
    lam, mu = lame3d(nu)
    m = model.mesh
    p, t = m.p, m.t
    dv = np.hypot(p[0] - A_CRACK, p[1])[t]
    h = np.max([np.linalg.norm(p[:, t[i]] - p[:, t[j]], axis=0)
                for i in range(4) for j in range(i + 1, 4)], axis=0)
    elems = np.nonzero(dv.min(axis=0) < r2 + h)[0]
    vb = Basis(m, model.basis.elem, intorder=intorder, elements=elems)
    sb = vb.with_element(ElementTetP2())
    gu = vb.interpolate(u).grad                      # (3, 3, ne, nq)
    eps = 0.5 * (gu + np.swapaxes(gu, 0, 1))
    tr = eps[0, 0] + eps[1, 1] + eps[2, 2]
    sig = 2 * mu * eps
    for i in range(3):
        sig[i, i] += lam * tr
    w = 0.5 * np.einsum("ijen,ijen->en", sig, eps)
    S = np.einsum("ijen,ien->jen", sig, gu[:, 0])   # sigma_ij u_i,1
    S[0] -= w
    dx = vb.dx
    X = sb.doflocs
    qr = smooth_step_q(np.hypot(X[0] - A_CRACK, X[1]), r1, r2)

    def integ(qd):
        gq = sb.interpolate(qd).grad
        return float(np.sum(dx * np.einsum("jen,jen->en", S, gq)))

    out = dict(I_uniform=integ(qr))
    if hats:
        zq = X[2]
        Ik, wk = [], []
        for k in range(len(zs)):
            psi = np.zeros_like(zq)
            if k > 0:
                s = (zq >= zs[k - 1]) & (zq <= zs[k])
                psi[s] = (zq[s] - zs[k - 1]) / (zs[k] - zs[k - 1])
            if k < len(zs) - 1:
                s = (zq >= zs[k]) & (zq <= zs[k + 1])
                psi[s] = (zs[k + 1] - zq[s]) / (zs[k + 1] - zs[k])
            Ik.append(integ(qr * psi))
            wk.append(0.5 * ((zs[k] - zs[k - 1]) if k > 0 else 0)
                      + 0.5 * ((zs[k + 1] - zs[k]) if k < len(zs) - 1 else 0))
        out["I_hats"] = Ik
        out["hat_widths"] = wk
    return out


# --------------------------------------------------------------------- cases
def run_mesh(level, T, nus, plane_strain=False, compliance=True, log=print):
    lv = LEVELS[level]
    t0 = time.time()
    m2 = section_mesh(lv["alpha"])
    zs = z_fractions(lv["dz0"], lv["dzmax"]) * T / 2
    mesh = extrude(m2, zs)
    models = {0: Model3D(mesh)}
    if compliance:
        for k in (-1, 1):
            models[k] = Model3D(morph(mesh, k * DELTA_A))
    t_asm = time.time() - t0
    D, vals, topy = dirichlet(models[0], T, plane_strain)
    solver = Solver(models[0].K(0.25), D)
    N = models[0].basis.N
    log(f"  level {level} T={T} {'PLANE-STRAIN CHECK ' if plane_strain else ''}"
        f"2D verts={m2.p.shape[1]} z layers={len(zs) - 1} (first {zs[1]:.3e} m) tets={mesh.t.shape[1]} "
        f"ndofs={N} free={len(solver.I)}; assembly {t_asm:.1f}s, LU {solver.t_fact:.1f}s "
        f"(nnz L+U {solver.nnz_lu / 1e6:.0f}M), maxrss {maxrss_gb():.2f} GB", flush=True)
    ell = min(A_CRACK, W - A_CRACK)
    recs = {}
    for key, nu in nus:
        t1 = time.time()
        Pq, info = {}, {}
        for k, mdl in models.items():
            K = mdl.K(nu)
            u, it, res = solver.solve(K, D, vals)
            r = K @ u
            Pq[k] = float(r[topy].sum())
            info[k] = (it, res)
            if k == 0:
                u0, U_q = u, 0.5 * float(u @ r)
        t_solve = time.time() - t1
        P = 2 * Pq[0]
        rec = dict(T=T, nu=nu, level=level, ndofs=int(N), n_tets=int(mesh.t.shape[1]),
                   n_section_vertices=int(m2.p.shape[1]), n_z_layers=len(zs) - 1,
                   z_nodes=zs.tolist(), alpha=lv["alpha"], plane_strain_check=plane_strain,
                   P_per_unit_delta=P, P_per_unit_delta_per_depth=P / T,
                   P_from_energy_check=8 * U_q,
                   pcg_iterations={str(k): v[0] for k, v in info.items()},
                   pcg_rel_residual=max(v[1] for v in info.values()))
        if compliance:
            dPq = (Pq[1] - Pq[-1]) / (2 * DELTA_A)
            rec["G_compliance"] = -dPq / T
        t2 = time.time()
        Js, Gz = [], None
        for d, (f1, f2) in enumerate(DOMAINS):
            di = domain_integrals(models[0], u0, nu, T, zs, f1 * ell, f2 * ell,
                                  hats=(d == MAIN_DOMAIN))
            Js.append(4 * di["I_uniform"] / T)
            if d == MAIN_DOMAIN:
                Gz = [2 * I / wk for I, wk in zip(di["I_hats"], di["hat_widths"])]
                Gz_mean = 2 * sum(di["I_hats"]) / (T / 2)
        rec["G_J_domains"] = Js
        rec["G_J"] = Js[MAIN_DOMAIN]
        rec["G_z"] = dict(z=zs.tolist(), z_over_T=(zs / T).tolist(), G=Gz,
                          G_over_G_avg=(np.array(Gz) / Js[MAIN_DOMAIN]).tolist(),
                          hats_mean_check=Gz_mean)
        G = rec["G_J"]
        rec["P_c_per_depth"] = P / T * np.sqrt(G0 / G)
        rec["delta_c"] = float(np.sqrt(G0 / G))
        if compliance:
            rec["rel_diff_G_compliance_vs_J"] = rec["G_compliance"] / G - 1
        rec["t_solve"] = t_solve
        rec["t_J"] = time.time() - t2
        rec["t_assembly"] = t_asm
        rec["t_factorisation"] = solver.t_fact
        rec["nnz_LU"] = solver.nnz_lu
        rec["maxrss_GB_so_far"] = maxrss_gb()
        spread = (max(Js) - min(Js)) / G
        log(f"    {key}: P/(Delta T)={P / T:.9e} N/m/m  (8U_q/P-1={rec['P_from_energy_check'] / P - 1:+.1e})"
            f"  G_compl={rec.get('G_compliance', float('nan')):.7e} G_J={G:.7e} "
            f"(C-J)/J={rec.get('rel_diff_G_compliance_vs_J', float('nan')):+.1e} J-domain spread {spread:.1e}"
            f"  P_c/T={rec['P_c_per_depth'] / 1e3:.3f} kN/m delta_c={rec['delta_c']:.6e} m"
            f"  PCG its {rec['pcg_iterations']} res {rec['pcg_rel_residual']:.0e}"
            f"  [{t_solve:.0f}s solve, {rec['t_J']:.0f}s J]", flush=True)
        log("      G(z)/G_avg at z/T = " + ", ".join(
            f"{zt:.4f}:{g:.4f}" for zt, g in zip(rec["G_z"]["z_over_T"], rec["G_z"]["G_over_G_avg"]))
            + f"  (hat mean / G_J - 1 = {Gz_mean / G - 1:+.1e})", flush=True)
        recs[key] = rec
    del solver
    return recs


def bounds_2d(log=print):
    """Plane stress / plane strain at a/W = 0.5 from the 2D code (level 1, as reference_sent.json)."""
    import fem_sent as fs
    out = {}
    for key, nu in NUS:
        for plane in ("stress", "strain"):
            mat = dict(key=f"plane_{plane}_{key}", plane=plane, nu=nu)
            r = fs.analyse_a(A_CRACK, 1, [mat])[0]
            G = r["G_J"]
            out[mat["key"]] = dict(P_per_unit_delta=r["P"], G_J=G, G_compliance=r["G_compliance_2pt"],
                                   P_c_per_depth=r["P"] * np.sqrt(G0 / G), delta_c=float(np.sqrt(G0 / G)),
                                   level=1, ndofs=r["ndofs"])
            log(f"  2D {mat['key']}: P={r['P']:.9e} G_J={G:.7e} P_c={out[mat['key']]['P_c_per_depth'] / 1e3:.3f} kN/m", flush=True)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--level", type=int, default=1)
    ap.add_argument("--conv-level", type=int, default=0, help="coarser level for the convergence check")
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                  "reference_sent3d.json"))
    ap.add_argument("--depths", type=float, nargs="+", default=DEPTHS,
                    help="bar depths T [m] (the first also for the checks)")
    args = ap.parse_args()
    depths = args.depths
    T0 = time.time()
    print(f"3D SENT bar, W={W} L={L} a={A_CRACK} E={E:.3g}; clamped grips; quarter model; per unit Delta")
    print(f"python {platform.python_version()}, skfem {skfem.__version__}, numpy {np.__version__}, scipy {scipy.__version__}")
    print("\n== 2D bounds (lefm_fem, level 1)")
    b2 = bounds_2d()

    print(f"\n== plane-strain check (u_z = 0 on z = 0 and z = T/2), level {args.level}")
    pe = run_mesh(args.level, depths[0], NUS, plane_strain=True)
    for key, _ in NUS:
        ref = b2[f"plane_strain_{key}"]
        r = pe[key]
        r["vs_2D"] = dict(P=r["P_per_unit_delta_per_depth"] / ref["P_per_unit_delta"] - 1,
                          G_J=r["G_J"] / ref["G_J"] - 1,
                          G_compliance=r["G_compliance"] / ref["G_J"] - 1,
                          P_c=r["P_c_per_depth"] / ref["P_c_per_depth"] - 1)
        print(f"    {key}: 3D/2D - 1: P {r['vs_2D']['P']:+.1e}, G_J {r['vs_2D']['G_J']:+.1e}, "
              f"G_compl {r['vs_2D']['G_compliance']:+.1e}, P_c {r['vs_2D']['P_c']:+.1e}")

    print(f"\n== 3D bar, free faces, level {args.level}")
    res = {}
    for T in depths:
        res[f"T_{T}"] = run_mesh(args.level, T, NUS)

    print(f"\n== mesh convergence at T = {depths[0]}: level {args.conv_level} vs {args.level}")
    conv = run_mesh(args.conv_level, depths[0], NUS)
    for key, _ in NUS:
        f, c = res[f"T_{depths[0]}"][key], conv[key]
        print(f"    {key}: level {args.conv_level} -> {args.level}: P {f['P_per_unit_delta'] / c['P_per_unit_delta'] - 1:+.2e}, "
              f"G_J {f['G_J'] / c['G_J'] - 1:+.2e}, G_compl {f['G_compliance'] / c['G_compliance'] - 1:+.2e}, "
              f"P_c {f['P_c_per_depth'] / c['P_c_per_depth'] - 1:+.2e}")

    print("\n== summary: P_c/T [kN/m] (G0 = 200 J/m^2)")
    print(" nu     T [m]  P/(Delta T) [N/m/m]  G_compl [J/m2]   G_J [J/m2]       (C-J)/J   P_c/T   Delta_c [m]   "
          "G(z=0)/G_avg G(T/2)/G_avg  vs PS    vs PE   between")
    for key, nu in NUS:
        ps, pe2 = b2[f"plane_stress_{key}"]["P_c_per_depth"], b2[f"plane_strain_{key}"]["P_c_per_depth"]
        for T in depths:
            r = res[f"T_{T}"][key]
            pc = r["P_c_per_depth"]
            r["between_plane_stress_and_strain"] = bool(min(ps, pe2) < pc < max(ps, pe2))
            r["vs_plane_stress"] = pc / ps - 1
            r["vs_plane_strain"] = pc / pe2 - 1
            gz = r["G_z"]["G_over_G_avg"]
            print(f" {key} {T:.2f}   {r['P_per_unit_delta_per_depth']:.9e}  {r['G_compliance']:.7e}  {r['G_J']:.7e}  "
                  f"{r['rel_diff_G_compliance_vs_J']:+.1e}  {pc / 1e3:.2f}  {r['delta_c']:.5e}  {gz[0]:.4f}       "
                  f"{gz[-1]:.4f}       {r['vs_plane_stress']:+.2%}  {r['vs_plane_strain']:+.2%}  {r['between_plane_stress_and_strain']}")
        print(f" {key} plane stress {ps / 1e3:.2f} kN/m, plane strain {pe2 / 1e3:.2f} kN/m (2D, level 1)")
    dmax = max(abs(res[f"T_{T}"][k]["rel_diff_G_compliance_vs_J"]) for T in depths for k, _ in NUS)
    print(f" max |G_compliance/G_J - 1| over the 3D cases = {dmax:.1e}")

    out = dict(
        description="LEFM reference for the clamped 3D SENT bar (through crack a/W = 0.5), scikit-fem P2 "
                    "tetrahedra, quarter model; dhpd validation/fracture problem E",
        inputs=dict(W=W, L=L, a=A_CRACK, depths=depths, E=E, nus=dict(NUS), G0=G0,
                    grips="clamped: face y=-L/2 u=(0,0,0); face y=+L/2 u=(0,Delta,0); faces x=0, x=W, z=0, z=T free",
                    units="SI; all values per unit grip displacement Delta = 1 m; P_c_per_depth in N/m",
                    model="quarter y>=0, z in [0,T/2]: top u=(0,1/2,0), ligament u_y=0, mid-plane u_z=0; "
                          "P = 2 P_quarter, G_avg = -(1/T) dP_quarter/da = 4 I_quarter/T",
                    levels=LEVELS, level=args.level, conv_level=args.conv_level,
                    mesh="extruded 2D RGB-refined section, h = min(alpha W/2, alpha d) around tip (floor 1e-3 W) and "
                         "grip corners (floor 1e-4 W); z layers geometric (x2) toward z=0; prisms split in 3 tets; P2",
                    delta_a_compliance=DELTA_A,
                    J_domains_times_min_a_W_minus_a=DOMAINS, main_domain=MAIN_DOMAIN,
                    G_used_for_Pc="G_J (main domain, q uniform in z)"),
        software=dict(python=platform.python_version(), skfem=skfem.__version__,
                      numpy=np.__version__, scipy=scipy.__version__),
        bounds_2d_level1=b2,
        bounds_2d_committed_reference_sent_json=dict(
            plane_stress_nu_1_3_P_c=476.38e3, plane_stress_nu_1_4_P_c=476.03e3, plane_strain_nu_1_4_P_c=492.00e3),
        plane_strain_check=pe,
        results=res,
        convergence=dict(level_coarse=conv, level_main={k: res[f"T_{depths[0]}"][k] for k, _ in NUS}),
        runtime_s=time.time() - T0,
    )
    with open(args.out, "w") as fh:
        json.dump(out, fh, indent=1)
    print(f"\nwrote {args.out} (total runtime {time.time() - T0:.1f} s)")


if __name__ == "__main__":
    main()
