#!/usr/bin/env python3
"""FEM/LEFM reference for an inclined centre crack in the clamped plate (problem C).

Setup:
  body x in [0, W], y in [-L/2, L/2], W = 0.1 m, L = 0.2 m, thickness t = 1,
  E = 30 GPa, nu = 1/3, plane stress, linear elastic, no contact.
  Clamped grips: u = (0, 0) on the bottom edge, u = (0, Delta) on the top edge
  (both components prescribed on every node of the edge), Delta = 1 m.
  Straight crack through (W/2, 0) at beta = 45 deg to the x axis, half-length
  c = 0.015 m: tips T- = (W/2 - c cos beta, -c sin beta) and
  T+ = (W/2 + c cos beta, +c sin beta).

Method (scikit-fem, see lefm_fem.py):
  * own crack mesher: tensor grid whose central block [W/2 - c cos b, W/2 +
    c cos b] x [-c sin b, c sin b] has 2m x 2m cells of size (c cos b / m) x
    (c sin b / m), all cut by the "/" diagonal, so the crack is a chain of cell
    diagonals; conforming red-green-blue refinement to h = min(alpha W/2,
    alpha * distance) around both tips and the four grip corners; crack opened
    by duplicating its interior nodes; alpha = 0.7 * 2^(-level/2);
  * P2 displacements, condense + solve;
  * at each tip, local frame e1 = direction of crack extension (outward along
    the crack), e2 = e1 rotated +90 deg: K_I, K_II from the interaction
    integral with Williams auxiliary fields on three annuli (r1, r2) =
    (0.20, 0.40), (0.35, 0.65), (0.50, 0.90) x c, domain J for comparison, and
    the displacement-correlation estimate from the crack-face jump;
  * MTS kink angle theta_c = 2 arctan[(K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)]
    (from e1, counter-clockwise positive) and the kink direction in x-y;
  * comparison with the infinite plate under remote sigma = P / (W t):
    K_I = sigma sqrt(pi c) sin^2 gamma, K_II = sigma sqrt(pi c) sin gamma cos gamma,
    gamma = angle between crack and load axis y (= 90 deg - beta);
  * mesh convergence over levels 0..5; the finest level is the reference.

Run:  python3 fem_inclined.py    (writes reference_inclined.json next to this file)
"""
import argparse
import json
import os
import platform
import time

import numpy as np
import scipy

import skfem
from skfem import MeshTri1

from lefm_fem import (Model, displacement_correlation, e_prime, hoop_stress,
                      mesh_quality, mts_angle, point_size_field,
                      graded_lines, refine_to_size, solve_grips,
                      split_crack, structured_tri, tip_integrals)

W = 0.1
L = 0.2
THICK = 1.0
E = 30e9
NU = 1.0 / 3.0
PLANE = "stress"
BETA_DEG = 45.0
C_HALF = 0.015
H0 = 0.0125
TIP_FLOOR = 1e-5 * W
CORNER_FLOOR = 1e-4 * W
DOMAINS = [(0.20, 0.40), (0.35, 0.65), (0.50, 0.90)]   # x c
MAIN_DOMAIN = 1


def alpha_of(level):
    return 0.7 * 2.0 ** (-level / 2.0)


def inclined_crack_mesh(Wp, Lp, xc, yc, c, beta, level, m_block=1, h0=H0,
                        corners=True, hmax=None, tip_floor=TIP_FLOOR,
                        corner_floor=CORNER_FLOOR):
    """Rectangle x in [0, Wp], y in [-Lp/2, Lp/2] with a straight crack of
    half-length c through (xc, yc) at angle beta (0 < beta < pi/2) to x.

    Central block of 2m x 2m cells (c cos b / m) x (c sin b / m) cut along "/"
    so that the crack is a chain of cell diagonals; outside the block the grid
    lines grow geometrically (factor <= 1.3) from the block cell size to h0.
    Size field alpha * distance around both tips (and the four corners of the
    rectangle if corners=True), capped at hmax (default alpha * Wp / 2).
    Returns (mesh, tips, faces) with tips = [T-, T+] and faces = (plus, minus)
    node rows, plus = left of T- -> T+.
    """
    dxb, dyb = c * np.cos(beta), c * np.sin(beta)
    alpha = alpha_of(level)
    if hmax is None:
        hmax = 0.5 * alpha * Wp
    bx = xc + dxb * np.arange(-m_block, m_block + 1) / m_block
    by = yc + dyb * np.arange(-m_block, m_block + 1) / m_block
    hbx, hby = dxb / m_block, dyb / m_block
    xs = np.concatenate([graded_lines(bx[0], 0.0, hbx, h0)[::-1][:-1], bx,
                         graded_lines(bx[-1], Wp, hbx, h0)[1:]])
    ys = np.concatenate([graded_lines(by[0], -Lp / 2, hby, h0)[::-1][:-1], by,
                         graded_lines(by[-1], Lp / 2, hby, h0)[1:]])
    p, t = structured_tri(xs, ys, lambda x_, y_: np.ones_like(x_, bool))
    m = MeshTri1(p, t)
    Tm = (xc - dxb, yc - dyb)
    Tp = (xc + dxb, yc + dyb)
    pts = [Tm, Tp]
    al = [alpha, alpha]
    fl = [tip_floor] * 2
    if corners:
        pts += [(0, -Lp / 2), (Wp, -Lp / 2), (0, Lp / 2), (Wp, Lp / 2)]
        al += [alpha] * 4
        fl += [corner_floor] * 4
    m = refine_to_size(m, point_size_field(pts, al, fl, hmax))
    p2, t2, faces = split_crack(m.p, m.t, [(Tm, Tp)], [Tm, Tp])
    return MeshTri1(p2, t2), [np.array(Tm), np.array(Tp)], faces[0]


def analyse_level(level):
    t0 = time.time()
    beta = np.radians(BETA_DEG)
    mesh, tips, faces = inclined_crack_mesh(W, L, W / 2, 0.0, C_HALF, beta, level)
    model = Model(mesh)
    r = solve_grips(model, E, NU, PLANE, W, L, 0.0, 1.0)
    lam, mu = r["lam"], r["mu"]
    d = np.array([np.cos(beta), np.sin(beta)])
    nrm = np.array([-d[1], d[0]])
    nd = model.basis.nodal_dofs
    jx = r["u"][nd[0, faces[0]]] - r["u"][nd[0, faces[1]]]
    jy = r["u"][nd[1, faces[0]]] - r["u"][nd[1, faces[1]]]
    gap = nrm[0] * jx + nrm[1] * jy
    out_gap = (float(gap.min()), float(gap.max()))
    out = dict(crack_face_normal_gap_min=out_gap[0], crack_face_normal_gap_max=out_gap[1],level=level, alpha=alpha_of(level), ndofs=model.ndofs, nelems=int(mesh.t.shape[1]),
               Py=r["Py"], Px=r["Px"], P_from_energy=2 * r["energy"], tips={})
    out["min_angle_deg"], out["h_min"], out["h_max"] = mesh_quality(mesh)
    for name, T, e1, (fp, fm) in (("T+", tips[1], d, faces), ("T-", tips[0], -d, faces[::-1])):
        res = [tip_integrals(model, r["u"], T, e1, lam, mu, PLANE, NU, E, f1 * C_HALF, f2 * C_HALF)
               for f1, f2 in DOMAINS]
        dc = displacement_correlation(mesh, r["u"], model.basis, fp, fm, T, e1, E, NU, PLANE,
                                      0.05 * C_HALF)
        out["tips"][name] = dict(
            position=T.tolist(), e1=e1.tolist(),
            KI_domains=[x["KI"] for x in res], KII_domains=[x["KII"] for x in res],
            J_domains=[x["J"] for x in res], J_from_K_domains=[x["J_from_K"] for x in res],
            KI_dc=dc["KI"], KII_dc=dc["KII"])
    out["t"] = time.time() - t0
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--levels", type=int, nargs="*", default=[0, 1, 2, 3, 4, 5])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                  "reference_inclined.json"))
    args = ap.parse_args()
    T0 = time.time()
    beta = np.radians(BETA_DEG)
    gamma = np.pi / 2 - beta
    Ep = e_prime(E, NU, PLANE)
    print(f"Inclined centre crack, W={W} L={L} E={E:.3g} nu={NU:.6f} plane {PLANE}, beta={BETA_DEG} deg, "
          f"c={C_HALF}; clamped grips, top u=(0,1)")
    print(f"python {platform.python_version()}, skfem {skfem.__version__}, numpy {np.__version__}, scipy {scipy.__version__}")
    rows = []
    for lev in args.levels:
        o = analyse_level(lev)
        rows.append(o)
        print(f"level {lev} alpha={o['alpha']:.4f} ndofs={o['ndofs']:8d} min angle {o['min_angle_deg']:.1f} "
              f"h_min={o['h_min']:.1e}: Py={o['Py']:.10e} Px={o['Px']:+.6e} (2U={o['P_from_energy']:.10e})  [{o['t']:.1f}s]")
        for name, tp in o["tips"].items():
            print(f"   {name}: KI=[{', '.join(f'{k:.9e}' for k in tp['KI_domains'])}]\n"
                  f"       KII=[{', '.join(f'{k:.9e}' for k in tp['KII_domains'])}]\n"
                  f"       J=[{', '.join(f'{k:.9e}' for k in tp['J_domains'])}] J(K)={tp['J_from_K_domains'][MAIN_DOMAIN]:.9e}"
                  f"  DC: KI={tp['KI_dc']:.6e} KII={tp['KII_dc']:.6e}", flush=True)
    f, g = rows[-1], rows[-2]
    print("change between the two finest levels: "
          f"Py {f['Py'] / g['Py'] - 1:+.1e}, "
          + ", ".join(f"{n} KI {f['tips'][n]['KI_domains'][MAIN_DOMAIN] / g['tips'][n]['KI_domains'][MAIN_DOMAIN] - 1:+.1e} "
                      f"KII {f['tips'][n]['KII_domains'][MAIN_DOMAIN] / g['tips'][n]['KII_domains'][MAIN_DOMAIN] - 1:+.1e}"
                      for n in ("T+", "T-")))

    sigma = f["Py"] / (W * THICK)
    K0 = sigma * np.sqrt(np.pi * C_HALF)
    KI_inf = K0 * np.sin(gamma) ** 2
    KII_inf = K0 * np.sin(gamma) * np.cos(gamma)
    th_inf = mts_angle(KI_inf, KII_inf)
    tips_out = {}
    print(f"\nfinest level {f['level']}: P = {f['Py']:.9e} N/m per m, sigma = P/(W t) = {sigma:.9e} Pa, "
          f"horizontal grip reaction Px = {f['Px']:+.6e} N/m")
    print(f"infinite plate (same sigma): K_I = {KI_inf:.9e}, K_II = {KII_inf:.9e}, "
          f"MTS theta_c = {np.degrees(th_inf):.4f} deg")
    for name, tp in f["tips"].items():
        KI = tp["KI_domains"][MAIN_DOMAIN]
        KII = tp["KII_domains"][MAIN_DOMAIN]
        th = mts_angle(KI, KII)
        e1 = np.array(tp["e1"])
        phi_e1 = np.degrees(np.arctan2(e1[1], e1[0]))
        phi_k = phi_e1 + np.degrees(th)
        phi_k = (phi_k + 180.0) % 360.0 - 180.0
        kdir = [float(np.cos(np.radians(phi_k))), float(np.sin(np.radians(phi_k)))]
        phi_inf = (phi_e1 + np.degrees(th_inf) + 180.0) % 360.0 - 180.0
        Ks = np.array(tp["KI_domains"])
        Kss = np.array(tp["KII_domains"])
        tips_out[name] = dict(
            position=tp["position"], crack_direction_e1=tp["e1"],
            crack_direction_angle_deg_from_x=float(phi_e1),
            K_I=KI, K_II=KII, K_I_domains=tp["KI_domains"], K_II_domains=tp["KII_domains"],
            J_domains=tp["J_domains"], J_from_K=(KI ** 2 + KII ** 2) / Ep,
            K_I_displacement_correlation=tp["KI_dc"], K_II_displacement_correlation=tp["KII_dc"],
            K_II_over_K_I=KII / KI,
            mts_kink_angle_deg_from_e1=float(np.degrees(th)),
            kink_direction_angle_deg_from_x=float(phi_k),
            kink_direction_vector=kdir,
            K_I_over_infinite_plate=KI / KI_inf, K_II_over_infinite_plate=KII / KII_inf,
            infinite_plate_kink_direction_angle_deg_from_x=float(phi_inf),
            domain_spread_K_I=float((Ks.max() - Ks.min()) / abs(KI)),
            domain_spread_K_II=float((Kss.max() - Kss.min()) / abs(KII)),
            K_eq_mts_per_unit_delta=float(hoop_stress(th, KI, KII)),
        )
        print(f" {name} at ({tp['position'][0]:.6f}, {tp['position'][1]:+.6f}), e1 at {phi_e1:.1f} deg from +x:\n"
              f"    K_I = {KI:.9e}  K_II = {KII:.9e}  K_II/K_I = {KII / KI:.6f}  (domain spread {tips_out[name]['domain_spread_K_I']:.1e}, "
              f"{tips_out[name]['domain_spread_K_II']:.1e}); DC: {tp['KI_dc']:.6e}, {tp['KII_dc']:.6e}\n"
              f"    J = {tp['J_domains'][MAIN_DOMAIN]:.9e} vs (K_I^2+K_II^2)/E' = {(KI ** 2 + KII ** 2) / Ep:.9e}\n"
              f"    K_I/K_I,inf = {KI / KI_inf:.6f}, K_II/K_II,inf = {KII / KII_inf:.6f}\n"
              f"    MTS theta_c = {np.degrees(th):.4f} deg from e1 -> kink direction {phi_k:.4f} deg from +x, "
              f"vector ({kdir[0]:.6f}, {kdir[1]:.6f}); infinite plate: {phi_inf:.4f} deg")
    print(f"crack-face normal gap along the crack (vertex nodes): min {f['crack_face_normal_gap_min']:.6e} m, "
          f"max {f['crack_face_normal_gap_max']:.6e} m (positive = open, no interpenetration if min > 0)")
    GC = 200.0
    Kc = np.sqrt(GC * Ep)
    tp = tips_out["T+"]
    ini = dict(note="LEFM crack initiation for G_c = 200 J/m^2, K_c = sqrt(G_c E'): (a) energy criterion J = G_c; "
                    "(b) MTS criterion K_eq = cos(theta_c/2)[K_I cos^2(theta_c/2) - 1.5 K_II sin theta_c] = K_c "
                    "(both tips identical by symmetry)",
               G_c=GC, delta_c_J=float(np.sqrt(GC / tp["J_domains"][MAIN_DOMAIN])),
               delta_c_mts=float(Kc / tp["K_eq_mts_per_unit_delta"]))
    ini["P_c_J"] = float(f["Py"] * ini["delta_c_J"])
    ini["P_c_mts"] = float(f["Py"] * ini["delta_c_mts"])
    print(f"initiation for G_c = {GC}: J = G_c at delta = {ini['delta_c_J']:.6e} m (P = {ini['P_c_J']:.6e} N/m); "
          f"MTS K_eq = K_c at delta = {ini['delta_c_mts']:.6e} m (P = {ini['P_c_mts']:.6e} N/m)")
    sym = abs(f["tips"]["T+"]["KI_domains"][MAIN_DOMAIN] / f["tips"]["T-"]["KI_domains"][MAIN_DOMAIN] - 1)
    print(f"point symmetry (180 deg rotation about (W/2, 0)): |K_I(T+)/K_I(T-) - 1| = {sym:.1e}")
    out = dict(
        description="LEFM reference: inclined centre crack in the clamped-grip plate (dhpd "
                    "validation/fracture, problem C); scikit-fem P2; per unit grip displacement",
        inputs=dict(W=W, L=L, thickness=THICK, E=E, nu=NU, plane=PLANE, beta_deg=BETA_DEG,
                    c=C_HALF, crack_centre=[W / 2, 0.0],
                    grips="clamped: bottom edge u=(0,0); top edge u=(0, Delta) on every node, Delta = 1 m",
                    units="SI; forces per m of thickness; per unit grip displacement",
                    mesh_level=f["level"], alpha=f["alpha"], ndofs=f["ndofs"],
                    J_domains_times_c=DOMAINS, main_domain=MAIN_DOMAIN,
                    sign_convention="local frame at each tip: e1 = crack extension direction, e2 = e1 "
                                    "rotated +90 deg; Williams convention (K_II > 0: +e2 face slides "
                                    "in +e1 relative to the -e2 face); theta measured from e1, CCW positive"),
        software=dict(python=platform.python_version(), skfem=skfem.__version__,
                      numpy=np.__version__, scipy=scipy.__version__),
        crack_face_normal_gap_min=f["crack_face_normal_gap_min"],
        crack_face_normal_gap_max=f["crack_face_normal_gap_max"],
        P_per_unit_delta=f["Py"], Px_per_unit_delta=f["Px"], sigma_mean=sigma,
        infinite_plate=dict(K_I=KI_inf, K_II=KII_inf, gamma_deg=float(np.degrees(gamma)),
                            mts_kink_angle_deg_from_e1=float(np.degrees(th_inf)),
                            formula="K_I = sigma sqrt(pi c) sin^2 gamma, K_II = sigma sqrt(pi c) sin gamma cos gamma, sigma = P/(W t)"),
        tips=tips_out,
        initiation_Gc_200=ini,
        convergence=rows,
        runtime_s=time.time() - T0,
    )
    with open(args.out, "w") as fh:
        json.dump(out, fh, indent=1)
    print(f"\nwrote {args.out} (total runtime {time.time() - T0:.1f} s)")


if __name__ == "__main__":
    main()
