#!/usr/bin/env python3
"""FEM/LEFM reference for the centre-cracked tension (CCT) panel (problem D).

Setup (same plate, material and grips as problem A of fem_sent.py):
  body x in [0, W], y in [-L/2, L/2], W = 0.1 m, L = 0.2 m, thickness t = 1
  (forces are N per m of thickness), E = 30 GPa, plane stress nu = 1/3,
  linear elastic, no contact (traction-free crack faces).
  Clamped grips: u = (0, 0) on the whole bottom edge y = -L/2, u = (0, Delta)
  on the whole top edge y = +L/2 (both components on every node); left and
  right edges free.
  Straight centre crack on y = 0 from x = W/2 - a to x = W/2 + a (a = HALF
  length, total crack length 2a, two tips T- = (W/2 - a, 0), T+ = (W/2 + a, 0)).
  Sweep a/W = 0.100, 0.125, ..., 0.300 (9 values, including 0.2).
  All results are per unit grip displacement Delta = 1 m (linear problem).

Energy release rate: per tip, per unit thickness.
  Both tips grow together (symmetric problem), so the crack AREA grows by
  dA = 2 t da when the half-length grows by da.  With U = P^2 C / 2 the energy
  released per unit new crack area, i.e. the G at EACH tip, is
      G = (P^2 / (2 t)) dC/d(2a) = (P^2 / (4 t)) dC/da          (a = half length).
  The G of a single tip is also obtained by moving that tip alone (the other
  one fixed): G_tip = (P^2 / (2 t)) dC/da_tip.  The symmetric and the two
  one-tip values must agree (and agree with the domain J at each tip).

Method (scikit-fem, shared code in lefm_fem.py, unchanged):
  * mesher: structured base grid with grid lines x = W/2 - a, W/2, W/2 + a and
    y = 0 (crack on element edges), diagonals chosen so that the base grid is
    mirror symmetric about x = W/2 and about y = 0; conforming
    red-green-blue refinement to h = min(alpha W/2, alpha d) around both tips
    (floor 1e-5 W) and the four grip corners (floor 1e-4 W),
    alpha = 0.7 * 2^(-level/2); the crack is opened by duplicating the nodes
    on y = 0, W/2 - a < x < W/2 + a (tips not duplicated);
  * P2 displacements, condense + solve (SuperLU); reaction of the top grip
    from the residual K u (checked against 2 x strain energy); C = Delta/P;
  * G by two independent methods:
      (1) compliance, central differences with step delta = 1e-4 W; the
          meshes at a +- delta are the mesh of a with the nodes near the
          moved tip(s) shifted rigidly by +-delta * phi(r) (phi = 1 for
          r < 0.25 l, 0 beyond 0.5 l, l = min(a, W/2 - a)), so the topology
          is unchanged and the discretisation error cancels in the
          difference.  (1a) both tips moved (half-length a +- delta),
          (1b) T+ alone, (1c) T- alone;
      (2) domain J-integral at each tip, q = P2 interpolant of a C2 radial
          plateau on three annuli (r1, r2) = (0.20, 0.40), (0.35, 0.65),
          (0.50, 0.90) x l, l = min(a, W/2 - a): the domain never reaches
          the free edges (distance W/2 - a) or the other tip (distance 2a);
          the middle annulus is reported as G_J;
  * K_I = sqrt(G_J E') and, independently, K_I, K_II from the interaction
    integral (Williams auxiliary fields) at each tip; symmetry check K_II = 0
    and T+ = T-;
  * geometry factor F_clamped = K_I / (sigma sqrt(pi a)), sigma = P/(W t),
    compared with the handbook CCT factors for a long strip under uniform
    remote stress (Feddersen sqrt(sec(pi a/W)), Tada/Isida
    (1 - 0.025 b^2 + 0.06 b^4) sqrt(sec(pi b/2)), b = 2a/W); these do NOT
    apply to the short clamped panel, they are shown for orientation only;
  * the uncracked clamped panel: the clamped grips make sigma_yy non-uniform
    across the width; on y = 0 it is 1.1 % above P/(W t) at x = W/2 and 1.3 %
    below at the free edges; the centre value is the a -> 0 limit of
    F_clamped / F_Tada;
  * LEFM critical point for G_c = 200 J/m^2: P_c = P(1) sqrt(G_c/G_J),
    Delta_c = sqrt(G_c/G_J) = C P_c (both tips reach G_c together);
  * global checks over the a-grid (independently generated meshes): cubic
    spline of ln C -> G = (P^2/(4t)) dC/da; P(a0) - P(a) = 4 t int G_J da at
    Delta = 1 (dU/da = -2 t G at fixed Delta, U = P Delta/2); energy balance
    int P_c dDelta_c = 2 G_c t (a - a0) + U(a) - U(a0) along the LEFM path;
  * mesh convergence at a/W = 0.2 (levels 0-4, compliance with 2-point,
    4-point and 10-delta stencils) and at a/W = 0.1 and 0.3 (levels 0-3).

Run:  python3 fem_cct.py      (writes reference_cct.json next to this file)
"""
import argparse
import json
import os
import platform
import time

import numpy as np
import scipy
from scipy.interpolate import CubicSpline
from scipy.spatial import cKDTree

import skfem
from skfem import MeshTri1

from lefm_fem import (Model, displacement_correlation, e_prime, lame,
                      mesh_quality, point_size_field, refine_to_size,
                      smooth_step_q, solve_grips, split_crack,
                      structured_tri, tip_integrals, uniform_lines)

W = 0.1            # width [m]
L = 0.2            # grip-to-grip length [m]
THICK = 1.0        # thickness [m]
E = 30e9           # Young's modulus [Pa]
NU = 1.0 / 3.0
PLANE = "stress"
MAT_KEY = "plane_stress_nu_1/3"
GC = 200.0         # fracture energy [J/m^2]
XC = W / 2         # crack centre x
H0 = 0.025         # base grid spacing [m]
TIP_FLOOR = 1e-5 * W
CORNER_FLOOR = 1e-4 * W
DELTA_A = 1e-4 * W  # crack-length step of the compliance derivative [m]
DOMAINS = [(0.20, 0.40), (0.35, 0.65), (0.50, 0.90)]   # x min(a, W/2 - a)
MAIN_DOMAIN = 1
TIPS = ("T+", "T-")  # T+ = (W/2 + a, 0), e1 = +x; T- = (W/2 - a, 0), e1 = -x


def alpha_of(level):
    return 0.7 * 2.0 ** (-level / 2.0)


def ell_of(a):
    """Length scale of the J domains and the morph: min(a, W/2 - a)."""
    return min(a, XC - a)


def tip_geometry(a):
    return {"T+": (np.array([XC + a, 0.0]), np.array([1.0, 0.0])),
            "T-": (np.array([XC - a, 0.0]), np.array([-1.0, 0.0]))}


def cct_mesh(a, level):
    """Cracked CCT mesh; returns (MeshTri1, faces) with faces = (+y row, -y row)
    ordered by x (the -y row holds the duplicated nodes)."""
    alpha = alpha_of(level)
    xs = np.concatenate([uniform_lines(0, XC - a, H0)[:-1], uniform_lines(XC - a, XC, H0)[:-1],
                         uniform_lines(XC, XC + a, H0)[:-1], uniform_lines(XC + a, W, H0)])
    ys = np.concatenate([uniform_lines(-L / 2, 0, H0)[:-1], uniform_lines(0, L / 2, H0)])
    # "/" where (x - W/2) y > 0: the base grid is mirror symmetric about x = W/2 and y = 0
    p, t = structured_tri(xs, ys, lambda xc, yc: (xc - XC) * yc > 0)
    m = MeshTri1(p, t)
    corners = [(0, -L / 2), (W, -L / 2), (0, L / 2), (W, L / 2)]
    tips = [(XC - a, 0.0), (XC + a, 0.0)]
    sf = point_size_field(tips + corners, [alpha] * 6,
                          [TIP_FLOOR] * 2 + [CORNER_FLOOR] * 4, alpha * W / 2)
    m = refine_to_size(m, sf)
    p2, t2, faces = split_crack(m.p, m.t, [((XC - a, 0.0), (XC + a, 0.0))], tips)
    return MeshTri1(p2, t2), faces[0]


def mesh_symmetry(mesh):
    """Largest distance between a vertex / element centroid and the nearest
    vertex / centroid of the mesh mirrored about x = W/2 and about y = 0."""
    out = {}
    cen = mesh.p[:, mesh.t].mean(axis=1)
    for name, pts in (("vertices", mesh.p), ("centroids", cen)):
        tree = cKDTree(pts.T)
        for ax, mir in (("x=W/2", np.vstack([W - pts[0], pts[1]])),
                        ("y=0", np.vstack([pts[0], -pts[1]]))):
            d, _ = tree.query(mir.T)
            out[f"{name}_mirror_{ax}"] = float(d.max())
    return out


def morph(mesh, a, da_minus, da_plus):
    """Extend T+ by da_plus (moves +x) and T- by da_minus (moves -x):
    x += da_plus phi(|x - T+|) - da_minus phi(|x - T-|), phi = 1 near the tip."""
    ell = ell_of(a)
    p = mesh.p.copy()
    rp = np.hypot(p[0] - (XC + a), p[1])
    rm = np.hypot(p[0] - (XC - a), p[1])
    p[0] += (da_plus * smooth_step_q(rp, 0.25 * ell, 0.5 * ell)
             - da_minus * smooth_step_q(rm, 0.25 * ell, 0.5 * ell))
    return MeshTri1(p, mesh.t)


def f_feddersen(a_over_W):
    return np.sqrt(1.0 / np.cos(np.pi * np.asarray(a_over_W, float)))


def f_tada_cct(a_over_W):
    b = 2.0 * np.asarray(a_over_W, float)      # a / (W/2)
    return (1 - 0.025 * b ** 2 + 0.06 * b ** 4) * np.sqrt(1.0 / np.cos(np.pi * b / 2))


def uncracked_panel(level):
    """Clamped panel without a crack: P and sigma_yy on the mid-plane y = 0
    (at x = W/2 and x = 0), relative to the mean P/(W t).  Explains why F_clamped
    differs from the long-strip handbook value as a -> 0."""
    alpha = alpha_of(level)
    xs = np.concatenate([uniform_lines(0, XC, H0)[:-1], uniform_lines(XC, W, H0)])
    ys = np.concatenate([uniform_lines(-L / 2, 0, H0)[:-1], uniform_lines(0, L / 2, H0)])
    p, t = structured_tri(xs, ys, lambda xc, yc: (xc - XC) * yc > 0)
    corners = [(0, -L / 2), (W, -L / 2), (0, L / 2), (W, L / 2)]
    m = refine_to_size(MeshTri1(p, t), point_size_field(corners, [alpha] * 4, [CORNER_FLOOR] * 4,
                                                        alpha * W / 2))
    mdl = Model(m)
    r = solve_grips(mdl, E, NU, PLANE, W, L, 0.0, 1.0)
    h = 1e-6 * W

    def sig_yy(x, y):
        pts = np.array([[x + h, x - h, x, x], [y, y, y + h, y - h]])
        pts[0] = np.clip(pts[0], 0.0, W)
        ux, uy = (mdl.basis.probes(pts) @ r["u"]).reshape(2, 4)   # (u_x, u_y) at the 4 points
        exx = (ux[0] - ux[1]) / (pts[0, 0] - pts[0, 1])
        eyy = (uy[2] - uy[3]) / (2 * h)
        return r["lam"] * (exx + eyy) + 2 * r["mu"] * eyy

    smean = r["Py"] / (W * THICK)
    return dict(level=level, ndofs=mdl.ndofs, P_per_unit_delta=r["Py"], sigma_mean=smean,
                sigma_yy_centre_over_mean=float(sig_yy(XC, 0.0) / smean),
                sigma_yy_free_edge_over_mean=float(sig_yy(0.0, 0.0) / smean))


def analyse_a(a, level, stencil=(-1, 1), tip_stencil=(-1, 1), delta=DELTA_A, dc=False):
    """One crack half-length a: solve, compliance derivatives, J and K at both tips."""
    t0 = time.time()
    mesh, faces = cct_mesh(a, level)
    tmesh = time.time() - t0
    lam, mu = lame(E, NU, PLANE)
    base = Model(mesh)
    r0 = solve_grips(base, E, NU, PLANE, W, L, 0.0, 1.0)
    P = r0["Py"]
    C = {("both", 0): 1.0 / P}
    # morphed meshes: both tips (half-length a + k delta) and each tip alone
    jobs = [("both", k, k * delta, k * delta) for k in stencil if k != 0]
    jobs += [("T+", k, 0.0, k * delta) for k in tip_stencil if k != 0]
    jobs += [("T-", k, k * delta, 0.0) for k in tip_stencil if k != 0]
    for name, k, dm, dp in jobs:
        mdl = Model(morph(mesh, a, dm, dp))
        C[(name, k)] = 1.0 / solve_grips(mdl, E, NU, PLANE, W, L, 0.0, 1.0)["Py"]
        del mdl
    C[("T+", 0)] = C[("T-", 0)] = C[("both", 0)]
    # per tip: G = P^2/(2t) dC/d(2a) = P^2/(4t) dC/da when both tips move,
    #          G = P^2/(2t) dC/da_tip when one tip moves
    dCda = (C[("both", 1)] - C[("both", -1)]) / (2 * delta)
    rec = dict(a=a, a_over_W=a / W, level=level, alpha=alpha_of(level),
               ndofs=base.ndofs, nelems=int(mesh.t.shape[1]),
               P=P, P_from_energy=2 * r0["energy"], Px=r0["Px"], C=C[("both", 0)],
               dC_da_half_length=dCda,
               G_compliance_2pt=0.25 * P ** 2 / THICK * dCda)
    for tp in TIPS:
        dCt = (C[(tp, 1)] - C[(tp, -1)]) / (2 * delta)
        rec[f"G_compliance_{tp}_alone"] = 0.5 * P ** 2 / THICK * dCt
    if ("both", 2) in C:
        d4 = (C[("both", -2)] - 8 * C[("both", -1)] + 8 * C[("both", 1)] - C[("both", 2)]) / (12 * delta)
        rec["G_compliance_4pt"] = 0.25 * P ** 2 / THICK * d4
    if ("both", 10) in C:
        rec["G_compliance_2pt_10delta"] = (0.25 * P ** 2 / THICK
                                           * (C[("both", 10)] - C[("both", -10)]) / (20 * delta))
    # J, K at both tips
    ell = ell_of(a)
    tg = tip_geometry(a)
    rec["tips"] = {}
    for tp in TIPS:
        T, e1 = tg[tp]
        res = [tip_integrals(base, r0["u"], T, e1, lam, mu, PLANE, NU, E, f1 * ell, f2 * ell)
               for f1, f2 in DOMAINS]
        d = dict(position=T.tolist(), e1=e1.tolist(),
                 G_J_domains=[x["J"] for x in res],
                 KI_int_domains=[x["KI"] for x in res],
                 KII_int_domains=[x["KII"] for x in res],
                 G_J=res[MAIN_DOMAIN]["J"])
        if dc:
            # +e2 face: y > 0 row for T+ (e2 = +y), y < 0 row for T- (e2 = -y)
            fp, fm = (faces[0], faces[1]) if tp == "T+" else (faces[1], faces[0])
            dd = displacement_correlation(mesh, r0["u"], base.basis, fp, fm, T, e1,
                                          E, NU, PLANE, 0.05 * ell)
            d["KI_dc"], d["KII_dc"] = dd["KI"], dd["KII"]
        rec["tips"][tp] = d
    rec["G_J"] = 0.5 * (rec["tips"]["T+"]["G_J"] + rec["tips"]["T-"]["G_J"])
    # crack-face opening (vertex nodes, +y face minus -y face): no contact needed if >= 0
    nd = base.basis.nodal_dofs
    jy = r0["u"][nd[1, faces[0]]] - r0["u"][nd[1, faces[1]]]
    jx = r0["u"][nd[0, faces[0]]] - r0["u"][nd[0, faces[1]]]
    rec["crack_face_opening_min"] = float(jy.min())
    rec["crack_face_opening_max"] = float(jy.max())
    rec["crack_face_sliding_max_abs"] = float(np.abs(jx).max())
    xf = mesh.p[0, faces[0]]
    rec["crack_opening_at_centre"] = float(np.interp(XC, xf, jy))
    rec["mesh_symmetry"] = mesh_symmetry(mesh)
    rec["min_angle_deg"], rec["h_min"], rec["h_max"] = mesh_quality(mesh)
    rec["t_mesh"] = tmesh
    rec["t_total"] = time.time() - t0
    return rec


def fmt_tip(rec, tp):
    d = rec["tips"][tp]
    return (f"{tp}: G_J=[{', '.join(f'{g:.9e}' for g in d['G_J_domains'])}] "
            f"KI_int={d['KI_int_domains'][MAIN_DOMAIN]:.9e} KII_int={d['KII_int_domains'][MAIN_DOMAIN]:+.2e}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--level", type=int, default=2, help="mesh level of the a/W sweep")
    ap.add_argument("--conv-levels", type=int, nargs="*", default=[0, 1, 2, 3, 4])
    ap.add_argument("--conv-levels-ends", type=int, nargs="*", default=[0, 1, 2, 3])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                  "reference_cct.json"))
    args = ap.parse_args()
    T0 = time.time()
    Ep = e_prime(E, NU, PLANE)
    print(f"CCT (problem D), W={W} L={L} E={E:.3g} nu={NU:.6f} plane {PLANE} t={THICK}; "
          f"centre crack y=0, x in [W/2-a, W/2+a]; clamped grips, top u=(0,1); per unit grip displacement")
    print(f"python {platform.python_version()}, skfem {skfem.__version__}, numpy {np.__version__}, scipy {scipy.__version__}")
    print("G is per tip and per unit thickness: G = P^2/(2t) dC/d(2a) = P^2/(4t) dC/da (both tips moved), "
          "G_tip = P^2/(2t) dC/da_tip (one tip moved)")

    # ------------------------------------------------------------------ sweep
    aw = np.round(np.arange(0.1, 0.3 + 1e-9, 0.025), 6)
    assert np.any(aw == 0.2)
    print(f"\n== D: a/W sweep (a = half length), level {args.level} (alpha={alpha_of(args.level):.4f}), "
          f"central differences, delta_a = {DELTA_A:.1e} m")
    recs = []
    for x in aw:
        r = analyse_a(x * W, args.level)
        recs.append(r)
        Jp, Jm = r["tips"]["T+"]["G_J"], r["tips"]["T-"]["G_J"]
        Js = r["tips"]["T+"]["G_J_domains"]
        print(f"a/W={x:.3f} ndofs={r['ndofs']:7d} P={r['P']:.9e} C={r['C']:.9e} "
              f"G_C={r['G_compliance_2pt']:.7e} (T+ alone {r['G_compliance_T+_alone']:.7e}, "
              f"T- alone {r['G_compliance_T-_alone']:.7e}) G_J(T+)={Jp:.7e} G_J(T-)={Jm:.7e} "
              f"(C-J)/J={r['G_compliance_2pt'] / r['G_J'] - 1:+.1e} T-/T+-1={Jm / Jp - 1:+.0e} "
              f"J-domain spread {(max(Js) - min(Js)) / Jp:.1e} "
              f"KII/KI={r['tips']['T+']['KII_int_domains'][1] / r['tips']['T+']['KI_int_domains'][1]:+.0e}, "
              f"{r['tips']['T-']['KII_int_domains'][1] / r['tips']['T-']['KI_int_domains'][1]:+.0e} "
              f"Px={r['Px']:+.1e} [{r['t_total']:.1f}s]", flush=True)

    a = np.array([r["a"] for r in recs])
    P = np.array([r["P"] for r in recs])
    C = np.array([r["C"] for r in recs])
    GJ = np.array([r["G_J"] for r in recs])
    GJp = np.array([r["tips"]["T+"]["G_J"] for r in recs])
    GJm = np.array([r["tips"]["T-"]["G_J"] for r in recs])
    GCo = np.array([r["G_compliance_2pt"] for r in recs])
    GCp = np.array([r["G_compliance_T+_alone"] for r in recs])
    GCm = np.array([r["G_compliance_T-_alone"] for r in recs])
    KI_J = np.sqrt(GJ * Ep)
    KIp = np.array([r["tips"]["T+"]["KI_int_domains"][MAIN_DOMAIN] for r in recs])
    KIm = np.array([r["tips"]["T-"]["KI_int_domains"][MAIN_DOMAIN] for r in recs])
    KIIp = np.array([r["tips"]["T+"]["KII_int_domains"][MAIN_DOMAIN] for r in recs])
    KIIm = np.array([r["tips"]["T-"]["KII_int_domains"][MAIN_DOMAIN] for r in recs])
    sigma = P / (W * THICK)
    F = KI_J / (sigma * np.sqrt(np.pi * a))
    res = dict(
        plane=PLANE, nu=NU, E_prime=Ep,
        G_definition="per crack tip and per unit thickness: G = P^2/(2t) dC/d(2a) = P^2/(4t) dC/da "
                     "(a = half length, both tips grow, crack area 2 a t); total energy release "
                     "rate of the specimen per unit half-length growth = 2 t G",
        a_over_W=(a / W).tolist(), a=a.tolist(),
        compliance=C.tolist(), P_per_unit_delta=P.tolist(),
        P_from_energy=[r["P_from_energy"] for r in recs],
        Px_per_unit_delta=[r["Px"] for r in recs],
        dC_da_half_length=[r["dC_da_half_length"] for r in recs],
        G_compliance=GCo.tolist(),
        G_compliance_T_plus_alone=GCp.tolist(), G_compliance_T_minus_alone=GCm.tolist(),
        G_J=GJ.tolist(), G_J_T_plus=GJp.tolist(), G_J_T_minus=GJm.tolist(),
        G_J_domains_T_plus=[r["tips"]["T+"]["G_J_domains"] for r in recs],
        G_J_domains_T_minus=[r["tips"]["T-"]["G_J_domains"] for r in recs],
        rel_diff_G_compliance_vs_J=(GCo / GJ - 1).tolist(),
        rel_diff_G_J_T_minus_vs_T_plus=(GJm / GJp - 1).tolist(),
        K_I=KI_J.tolist(),
        K_I_interaction_T_plus=KIp.tolist(), K_I_interaction_T_minus=KIm.tolist(),
        K_II_interaction_T_plus=KIIp.tolist(), K_II_interaction_T_minus=KIIm.tolist(),
        sigma_mean=sigma.tolist(),
        F_clamped=F.tolist(), F_feddersen=f_feddersen(a / W).tolist(),
        F_tada=f_tada_cct(a / W).tolist(),
        ratio_F_clamped_over_F_tada=(F / f_tada_cct(a / W)).tolist(),
        F_note="F = K_I / (sigma sqrt(pi a)), sigma = P/(W t); Feddersen and Tada are for a long "
               "strip under uniform remote stress, not for the short clamped panel",
        crack_opening_at_centre=[r["crack_opening_at_centre"] for r in recs],
        crack_face_opening_min=[r["crack_face_opening_min"] for r in recs],
        ndofs=[r["ndofs"] for r in recs],
    )
    # independent global checks over the a grid (separately generated meshes)
    cs = CubicSpline(a, np.log(C))
    res["G_spline_of_C_grid"] = (0.25 * P ** 2 / THICK * C * cs(a, 1)).tolist()
    csG = CubicSpline(a, np.log(GJ))
    fine = np.linspace(a[0], a[-1], 4001)
    gf = np.exp(csG(fine))
    integ = np.concatenate([[0.0], np.cumsum(0.5 * (gf[1:] + gf[:-1]) * np.diff(fine))])
    res["check_P_drop_vs_integral_of_G_J"] = dict(
        relation="at Delta = 1: U = P/2 and dU/da = -2 t G (two tips) => P(a0) - P(a) = 4 t int_a0^a G da",
        P_a0_minus_P_a=(P[0] - P).tolist(),
        four_t_integral_G_J=(4 * THICK * np.interp(a, fine, integ)).tolist())
    # LEFM critical point
    Pc = P * np.sqrt(GC / GJ)
    dc = C * Pc
    res["G_c"] = GC
    res["K_c"] = float(np.sqrt(GC * Ep))
    res["P_c"] = Pc.tolist()
    res["delta_c"] = dc.tolist()
    res["elastic_energy"] = (0.5 * Pc * dc).tolist()
    res["sigma_c"] = (Pc / (W * THICK)).tolist()

    # ---------------------------------------------------------------- report
    print(f"\n-- {MAT_KEY}: E'={Ep:.6e}; G per tip [J/m^2] per unit Delta")
    print(" a/W    C [m/N]          P [N/m]          G_compl [J/m2]   G_compl T+ alone G_compl T- alone "
          "G_J T+           G_J T-           C-vs-J    T-/T+     K_I [Pa m^0.5]   KI_int/KI_J-1 "
          "KII/KI (T+, T-)    F_clamped  F_Fedd   F_Tada   F/F_Tada")
    for i, x in enumerate(res["a_over_W"]):
        print(f" {x:.3f}  {C[i]:.9e}  {P[i]:.9e}  {GCo[i]:.9e}  {GCp[i]:.9e}  {GCm[i]:.9e}  "
              f"{GJp[i]:.9e}  {GJm[i]:.9e}  {GCo[i] / GJ[i] - 1:+.1e}  {GJm[i] / GJp[i] - 1:+.1e}  "
              f"{KI_J[i]:.9e}  {KIp[i] / KI_J[i] - 1:+.1e}       {KIIp[i] / KIp[i]:+.0e}, {KIIm[i] / KIm[i]:+.0e}  "
              f"{F[i]:.6f}  {res['F_feddersen'][i]:.4f}  {res['F_tada'][i]:.4f}  {res['ratio_F_clamped_over_F_tada'][i]:.4f}")
    d_all = np.concatenate([GCo / GJ - 1, GCp / GJp - 1, GCm / GJm - 1])
    print(f" max |G_compliance/G_J - 1| = {np.max(np.abs(GCo / GJ - 1)):.2e} (both tips moved); "
          f"incl. one-tip compliance vs that tip's J: {np.max(np.abs(d_all)):.2e}; "
          f"max |G_compl(T+ alone)/G_compl(both) - 1| = {np.max(np.abs(GCp / GCo - 1)):.1e}, "
          f"T- alone: {np.max(np.abs(GCm / GCo - 1)):.1e}")
    print(f" symmetry: max |G_J(T-)/G_J(T+) - 1| = {np.max(np.abs(GJm / GJp - 1)):.1e}, "
          f"max |K_II/K_I| = {max(np.max(np.abs(KIIp / KIp)), np.max(np.abs(KIIm / KIm))):.1e}, "
          f"max |Px/P| = {np.max(np.abs(np.array(res['Px_per_unit_delta']) / P)):.1e}, "
          f"max |KI_int/sqrt(G_J E') - 1| = {max(np.max(np.abs(KIp / KI_J - 1)), np.max(np.abs(KIm / KI_J - 1))):.1e}, "
          f"max |2U/P - 1| = {np.max(np.abs(np.array(res['P_from_energy']) / P - 1)):.1e}")
    dsp = np.array(res["G_spline_of_C_grid"]) / GJ - 1
    print(f" spline-of-C-grid derivative vs G_J: max |rel diff| = {np.max(np.abs(dsp)):.2e} "
          f"(interior points 0.15..0.25: {np.max(np.abs(dsp[2:-2])):.2e})")
    chk = res["check_P_drop_vs_integral_of_G_J"]
    print(f" P(0.1W) - P(0.3W) = {chk['P_a0_minus_P_a'][-1]:.9e}, 4 t int G_J da = "
          f"{chk['four_t_integral_G_J'][-1]:.9e} (rel {chk['four_t_integral_G_J'][-1] / chk['P_a0_minus_P_a'][-1] - 1:+.1e})")
    print(" crack faces open everywhere: min opening over the sweep "
          f"{min(r['crack_face_opening_min'] for r in recs):.3e} m per m of Delta (tip nodes excluded)")
    sym_worst = max(max(r["mesh_symmetry"].values()) for r in recs)
    print(f" mesh mirror symmetry (x = W/2 and y = 0; vertices and centroids): worst mismatch {sym_worst:.1e} m")

    unc = [uncracked_panel(lev) for lev in (args.level, args.level + 1)]
    for u_ in unc:
        print(f" uncracked clamped panel, level {u_['level']}: P = {u_['P_per_unit_delta']:.9e} N/m, "
              f"sigma_yy/(P/(W t)) on y = 0: {u_['sigma_yy_centre_over_mean']:.6f} at x = W/2, "
              f"{u_['sigma_yy_free_edge_over_mean']:.6f} at the free edge (F_clamped/F_Tada -> this centre "
              f"value as a -> 0)")

    aW = np.array(res["a_over_W"])
    U = np.array(res["elastic_energy"])
    print(f"\n-- LEFM critical point, G_c={GC} J/m^2 at each tip, K_c=sqrt(G_c E')={res['K_c']:.6e} Pa m^0.5")
    print(" a/W    P_c [N/m]        sigma_c [Pa]     delta_c [m]      U=P_c delta_c/2 [J/m]  d(delta_c)/da sign")
    ddc = np.gradient(dc, aW * W)
    for i in range(len(aW)):
        print(f" {aW[i]:.3f}  {Pc[i]:.9e}  {Pc[i] / W:.9e}  {dc[i]:.9e}  {U[i]:.9e}         {'-' if ddc[i] < 0 else '+'}")
    csGa = CubicSpline(aW, np.log(GJ))
    fine = np.linspace(aW[0], aW[-1], 20001)
    dec = csGa(fine, 1) > 0
    res["stability"] = dict(
        note="Delta_c = sqrt(G_c/G(a)) at unit Delta; Delta_c decreases with a (unstable growth "
             "under grip-displacement control, snap-back) where G at fixed Delta increases with a",
        delta_c_decreasing_everywhere_on_grid=bool(np.all(dec)),
        fraction_of_grid_with_delta_c_decreasing=float(np.mean(dec)))
    print(f" G at fixed Delta increases with a on {100 * np.mean(dec):.0f} % of a/W in "
          f"[{aW[0]:.3f}, {aW[-1]:.3f}] -> Delta_c decreases with a there (snap-back: growth unstable "
          f"under grip-displacement control)")
    csP = CubicSpline(aW, Pc)
    csD = CubicSpline(aW, dc)
    work = np.trapezoid(csP(fine) * csD(fine, 1), fine)
    rhs = 2 * GC * THICK * (aW[-1] - aW[0]) * W + U[-1] - U[0]
    res["energy_balance_check"] = dict(
        a_over_W_from=float(aW[0]), a_over_W_to=float(aW[-1]),
        work_int_P_ddelta=float(work), two_Gc_t_da_plus_dU=float(rhs),
        note="int P_c d(delta_c) = 2 G_c t (a - a0) + U(a) - U(a0) (two tips); cubic splines over the a/W grid")
    print(f" energy balance a/W {aW[0]:.3f} -> {aW[-1]:.3f}: int P_c d(delta_c) = {work:.6e} J/m, "
          f"2 G_c t (a - a0) + U(a) - U(a0) = {rhs:.6e} J/m (rel {work / rhs - 1:+.1e})")

    # ------------------------------------------------------------ convergence
    conv = {}
    print(f"\n== convergence at a/W = 0.2; compliance derivative (both tips): 2-point (delta), "
          f"4-point (delta), 2-point (10 delta); one-tip 2-point")
    rows = []
    for lev in args.conv_levels:
        rec = analyse_a(0.2 * W, lev, stencil=(-10, -2, -1, 1, 2, 10), dc=True)
        rows.append(rec)
        print(f"level {lev} alpha={alpha_of(lev):.4f} ndofs={rec['ndofs']:8d} min angle {rec['min_angle_deg']:.1f} "
              f"h_min={rec['h_min']:.1e} h_max={rec['h_max']:.1e} mesh symmetry {max(rec['mesh_symmetry'].values()):.0e}\n"
              f"   P={rec['P']:.10e} (2U={rec['P_from_energy']:.10e}) Px={rec['Px']:+.1e}\n"
              f"   G_compl 2pt={rec['G_compliance_2pt']:.9e} 4pt={rec['G_compliance_4pt']:.9e} "
              f"2pt(10delta)={rec['G_compliance_2pt_10delta']:.9e} T+ alone={rec['G_compliance_T+_alone']:.9e} "
              f"T- alone={rec['G_compliance_T-_alone']:.9e}\n"
              f"   {fmt_tip(rec, 'T+')} KI_dc={rec['tips']['T+']['KI_dc']:.6e}\n"
              f"   {fmt_tip(rec, 'T-')} KI_dc={rec['tips']['T-']['KI_dc']:.6e}  [{rec['t_total']:.1f}s]",
              flush=True)
    conv["a_over_W_0.2"] = rows
    f, g = rows[-1], rows[-2]
    print(f" change between the two finest levels: P {f['P'] / g['P'] - 1:+.1e}, "
          f"G_J {f['G_J'] / g['G_J'] - 1:+.1e}, G_compliance {f['G_compliance_2pt'] / g['G_compliance_2pt'] - 1:+.1e}, "
          f"K_I(int, T+) {f['tips']['T+']['KI_int_domains'][1] / g['tips']['T+']['KI_int_domains'][1] - 1:+.1e}")
    print(f" finest level: G_compl/G_J - 1 = {f['G_compliance_2pt'] / f['G_J'] - 1:+.1e}, "
          f"4pt vs 2pt {f['G_compliance_4pt'] / f['G_compliance_2pt'] - 1:+.1e}, "
          f"10 delta vs delta {f['G_compliance_2pt_10delta'] / f['G_compliance_2pt'] - 1:+.1e}, "
          f"J domain spread {(max(f['tips']['T+']['G_J_domains']) - min(f['tips']['T+']['G_J_domains'])) / f['G_J']:.1e}")
    sl = [r for r in rows if r["level"] == args.level]
    if sl:
        s = sl[0]
        print(f" sweep level {args.level} vs finest: P {s['P'] / f['P'] - 1:+.1e}, G_J {s['G_J'] / f['G_J'] - 1:+.1e}, "
              f"G_compliance {s['G_compliance_2pt'] / f['G_J'] - 1:+.1e} (vs finest G_J), "
              f"P_c {(s['P'] / np.sqrt(s['G_J'])) / (f['P'] / np.sqrt(f['G_J'])) - 1:+.1e}")
    for x in (0.1, 0.3):
        rows_e = []
        for lev in args.conv_levels_ends:
            rec = analyse_a(x * W, lev)
            rows_e.append(rec)
            print(f"a/W={x} level {lev} ndofs={rec['ndofs']:8d} P={rec['P']:.10e} "
                  f"G_J(T+)=[{', '.join(f'{g_:.9e}' for g_ in rec['tips']['T+']['G_J_domains'])}] "
                  f"G_compl={rec['G_compliance_2pt']:.9e}  [{rec['t_total']:.1f}s]", flush=True)
        conv[f"a_over_W_{x}"] = rows_e
        f, g = rows_e[-1], rows_e[-2]
        print(f" a/W={x}: change between the two finest levels: P {f['P'] / g['P'] - 1:+.1e}, "
              f"G_J {f['G_J'] / g['G_J'] - 1:+.1e}, G_compliance {f['G_compliance_2pt'] / g['G_compliance_2pt'] - 1:+.1e}")

    out = dict(
        description="LEFM reference for the clamped-grip centre-cracked tension panel (dhpd "
                    "validation/fracture, problem D); scikit-fem P2; per unit grip displacement",
        inputs=dict(W=W, L=L, thickness=THICK, E=E, nu=NU, plane=PLANE, G_c=GC,
                    materials=[dict(key=MAT_KEY, plane=PLANE, nu=NU)],
                    crack="straight, y = 0, x from W/2 - a to W/2 + a (a = half length); two tips "
                          "T+ = (W/2 + a, 0) with e1 = +x and T- = (W/2 - a, 0) with e1 = -x",
                    grips="clamped: bottom edge u=(0,0); top edge u=(0, Delta) on every node; "
                          "left/right edges free",
                    load="top u = (0, 1 m)",
                    units="SI; forces per m of thickness; all values per unit grip displacement Delta = 1 m; "
                          "G per crack tip",
                    mesh_level_sweep=args.level, alpha_sweep=alpha_of(args.level),
                    mesh="RGB-refined structured grid (mirror symmetric about x = W/2 and y = 0), "
                         "h = min(alpha W/2, alpha d) around both tips and the grip corners, "
                         "alpha = 0.7*2^(-level/2), tip floor 1e-5 W, corner floor 1e-4 W; P2",
                    delta_a_compliance=DELTA_A,
                    J_domains_times_min_a_W_over_2_minus_a=DOMAINS, main_domain=MAIN_DOMAIN,
                    G_used_for_K_F_Pc="G_J (main domain, mean of the two tips)"),
        software=dict(python=platform.python_version(), skfem=skfem.__version__,
                      numpy=np.__version__, scipy=scipy.__version__),
        materials={MAT_KEY: res},
        uncracked_panel=unc,
        convergence=conv,
        runtime_s=time.time() - T0,
    )
    with open(args.out, "w") as fh:
        json.dump(out, fh, indent=1)
    print(f"\nwrote {args.out} (total runtime {time.time() - T0:.1f} s)")


if __name__ == "__main__":
    main()
