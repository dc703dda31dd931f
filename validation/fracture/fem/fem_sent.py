#!/usr/bin/env python3
"""FEM/LEFM reference for the single-edge-notched tension (SENT) plate.

Setup (problems A and B of the dhpd fracture validation):
  body x in [0, W], y in [-L/2, L/2], W = 0.1 m, L = 0.2 m, thickness t = 1
  (forces are N per m of thickness), E = 30 GPa, linear elastic, no contact;
  straight edge crack along y = 0 from x = 0 to x = a.
  Clamped grips: u = (0, 0) on the whole bottom edge y = -L/2, u prescribed
  on the whole top edge y = +L/2 (both components).
  A: top u = (0, Delta), mode I, a/W = 0.200, 0.225, ..., 0.900, three
     materials: plane stress nu = 1/3 (main), plane stress nu = 1/4,
     plane strain nu = 1/4.
  B: a/W = 0.5, top u = (Delta, 0) (shear grip), plane stress nu = 1/3.
  All results are per unit grip displacement Delta = 1 m (linear problem).

Method (scikit-fem, see lefm_fem.py):
  * own crack mesher: structured base grid with the crack on grid lines,
    conforming red-green-blue refinement to the size field
    h = min(h_max, alpha * distance) around the crack tip and the four grip
    corners (clamped/free corners are weakly singular), then the crack is
    opened by duplicating the nodes on y = 0, 0 <= x < a (tip not duplicated);
    mesh level l: alpha = 0.7 * 2^(-l/2), h_max = alpha * W / 2, distance
    floor of the size field 1e-5 W at the tip and 1e-4 W at the grip corners;
  * P2 displacements (ElementVector(ElementTriP2)), condense + solve (SuperLU);
  * stiffness P/Delta from the reaction (residual K u summed over the top-edge
    DOFs; checked against 2 x strain energy), compliance C = Delta / P;
  * G by two methods:
      (1) compliance: G = P^2/(2 t) dC/da, dC/da by central differences over
          a with step delta = 1e-4 W; the meshes at a +- delta are the mesh of
          a with the nodes near the tip shifted by +-delta * phi(r) (phi = 1
          near the tip, 0 beyond 0.5 min(a, W - a)), so the discretisation
          error is the same smooth function of a and cancels in the
          difference; the truncation error is measured with a 4-point
          stencil and with delta -> 10 delta in the convergence study;
      (2) domain J-integral (q = P2 interpolant of a C2 radial plateau) on
          three annuli (r1, r2) = (0.20, 0.40), (0.35, 0.65), (0.50, 0.90) x
          min(a, W - a); the middle one is reported as G_J;
  * K_I = sqrt(G_J E') and, independently, K_I, K_II from the interaction
    integral with the Williams auxiliary fields; F_clamped = K_I W t /
    (P sqrt(pi a)), compared with Tada (ends free to rotate) and
    Gross-Srawley;
  * LEFM path for G_c = 200 J/m^2 (plane stress nu = 1/3): P_c = P(1)
    sqrt(G_c / G(1)), Delta_c = C P_c, stored energy P_c Delta_c / 2;
  * B: interaction integral (three domains) and displacement correlation
    on the crack faces; MTS kink angle.
  * mesh convergence at a/W = 0.5 (levels 0-4, A and B) and at a/W = 0.2 and
    0.9 (levels 0-3, A).

Run:  python3 fem_sent.py      (writes reference_sent.json next to this file)
"""
import argparse
import json
import os
import platform
import time

import numpy as np
import scipy
from scipy.interpolate import CubicSpline

import skfem
from skfem import MeshTri1

from lefm_fem import (Model, displacement_correlation, e_prime, hoop_stress, lame,
                      mesh_quality, mts_angle, point_size_field,
                      refine_to_size, smooth_step_q, solve_grips, split_crack,
                      structured_tri, tip_integrals, uniform_lines)

W = 0.1            # width [m]
L = 0.2            # grip-to-grip length [m]
THICK = 1.0        # thickness [m]
E = 30e9           # Young's modulus [Pa]
GC = 200.0         # fracture energy for the LEFM path [J/m^2]
H0 = 0.025         # base grid spacing [m]
TIP_FLOOR = 1e-5 * W
CORNER_FLOOR = 1e-4 * W
DELTA_A = 1e-4 * W  # crack-length step of the compliance derivative [m]
DOMAINS = [(0.20, 0.40), (0.35, 0.65), (0.50, 0.90)]   # x min(a, W - a)
MAIN_DOMAIN = 1
MATERIALS = [
    dict(key="plane_stress_nu_1/3", plane="stress", nu=1.0 / 3.0),
    dict(key="plane_stress_nu_1/4", plane="stress", nu=0.25),
    dict(key="plane_strain_nu_1/4", plane="strain", nu=0.25),
]


def alpha_of(level):
    return 0.7 * 2.0 ** (-level / 2.0)


def sent_mesh(a, level):
    """Cracked SENT mesh; returns (MeshTri1, faces) with faces = (+y row, -y row)."""
    alpha = alpha_of(level)
    xs = np.concatenate([uniform_lines(0, a, H0)[:-1], uniform_lines(a, W, H0)])
    ys = np.concatenate([uniform_lines(-L / 2, 0, H0)[:-1], uniform_lines(0, L / 2, H0)])
    p, t = structured_tri(xs, ys, lambda xc, yc: yc > 0)   # mirror symmetric about y = 0
    m = MeshTri1(p, t)
    corners = [(0, -L / 2), (W, -L / 2), (0, L / 2), (W, L / 2)]
    sf = point_size_field([(a, 0.0)] + corners, [alpha] * 5,
                          [TIP_FLOOR] + [CORNER_FLOOR] * 4, alpha * W / 2)
    m = refine_to_size(m, sf)
    p2, t2, faces = split_crack(m.p, m.t, [((0.0, 0.0), (a, 0.0))], [(a, 0.0)])
    return MeshTri1(p2, t2), faces[0]


def morph(mesh, a, da):
    """Shift the crack tip by da: x += da * phi(|x - tip|), phi = 1 near the tip."""
    ell = min(a, W - a)
    p = mesh.p.copy()
    r = np.hypot(p[0] - a, p[1])
    p[0] += da * smooth_step_q(r, 0.25 * ell, 0.5 * ell)
    return MeshTri1(p, mesh.t)


def f_tada(al):
    al = np.asarray(al, float)
    return (np.sqrt(2.0 / (np.pi * al) * np.tan(np.pi * al / 2))
            * (0.752 + 2.02 * al + 0.37 * (1 - np.sin(np.pi * al / 2)) ** 3)
            / np.cos(np.pi * al / 2))


def f_gross_srawley(al):
    al = np.asarray(al, float)
    return 1.12 - 0.231 * al + 10.55 * al ** 2 - 21.72 * al ** 3 + 30.39 * al ** 4


def tip_results(model, u, a, mat, lam, mu):
    ell = min(a, W - a)
    res = [tip_integrals(model, u, (a, 0.0), (1.0, 0.0), lam, mu, mat["plane"],
                         mat["nu"], E, f1 * ell, f2 * ell) for f1, f2 in DOMAINS]
    return res


def analyse_a(a, level, materials, stencil=(-1, 1), delta=DELTA_A, dc=False,
              shear=False):
    """Solve one crack length for all materials; returns list of dicts."""
    t0 = time.time()
    mesh, faces = sent_mesh(a, level)
    tmesh = time.time() - t0
    models = {0: Model(mesh)}
    for k in stencil:
        models[k] = Model(morph(mesh, a, k * delta))
    out = []
    for mat in materials:
        lam, mu = lame(E, mat["nu"], mat["plane"])
        S = {}
        for k, mdl in models.items():
            r = solve_grips(mdl, E, mat["nu"], mat["plane"], W, L, 0.0, 1.0)
            S[k] = r["Py"]
            if k == 0:
                r0 = r
        C = {k: 1.0 / v for k, v in S.items()}
        P = S[0]
        dC2 = (C[1] - C[-1]) / (2 * delta)
        rec = dict(material=mat["key"], a=a, a_over_W=a / W, level=level,
                   ndofs=models[0].ndofs, nelems=int(mesh.t.shape[1]),
                   P=P, P_from_energy=2 * r0["energy"], Px=r0["Px"], C=C[0],
                   G_compliance_2pt=0.5 * P ** 2 / THICK * dC2)
        if 2 in C:
            dC4 = (C[-2] - 8 * C[-1] + 8 * C[1] - C[2]) / (12 * delta)
            rec["G_compliance_4pt"] = 0.5 * P ** 2 / THICK * dC4
        if 10 in C:
            rec["G_compliance_2pt_10delta"] = 0.5 * P ** 2 / THICK * (C[10] - C[-10]) / (20 * delta)
        tips = tip_results(models[0], r0["u"], a, mat, lam, mu)
        rec["G_J_domains"] = [d["J"] for d in tips]
        rec["KI_int_domains"] = [d["KI"] for d in tips]
        rec["KII_int_domains"] = [d["KII"] for d in tips]
        rec["G_J"] = tips[MAIN_DOMAIN]["J"]
        if dc:
            d = displacement_correlation(mesh, r0["u"], models[0].basis, faces[0], faces[1],
                                         (a, 0.0), (1.0, 0.0), E, mat["nu"], mat["plane"],
                                         0.05 * min(a, W - a))
            rec["KI_dc"], rec["KII_dc"] = d["KI"], d["KII"]
        if shear:
            rs = solve_grips(models[0], E, mat["nu"], mat["plane"], W, L, 1.0, 0.0)
            ts = tip_results(models[0], rs["u"], a, mat, lam, mu)
            d = displacement_correlation(mesh, rs["u"], models[0].basis, faces[0], faces[1],
                                         (a, 0.0), (1.0, 0.0), E, mat["nu"], mat["plane"],
                                         0.05 * min(a, W - a))
            nd = models[0].basis.nodal_dofs
            jump_x = rs["u"][nd[0, faces[0]]] - rs["u"][nd[0, faces[1]]]
            jump_y = rs["u"][nd[1, faces[0]]] - rs["u"][nd[1, faces[1]]]
            rec["shear"] = dict(Px=rs["Px"], Py=rs["Py"], energy=rs["energy"],
                                crack_face_opening_min=float(jump_y.min()),
                                crack_face_opening_max=float(jump_y.max()),
                                crack_face_sliding_max=float(np.abs(jump_x).max()),
                                KI_domains=[x["KI"] for x in ts],
                                KII_domains=[x["KII"] for x in ts],
                                J_domains=[x["J"] for x in ts],
                                KI_dc=d["KI"], KII_dc=d["KII"])
        out.append(rec)
    qual = mesh_quality(mesh)
    for rec in out:
        rec["min_angle_deg"], rec["h_min"], rec["h_max"] = qual
        rec["t_mesh"] = tmesh
        rec["t_total"] = time.time() - t0
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--level", type=int, default=1, help="mesh level of the a/W sweep")
    ap.add_argument("--conv-levels", type=int, nargs="*", default=[0, 1, 2, 3, 4])
    ap.add_argument("--conv-levels-ends", type=int, nargs="*", default=[0, 1, 2, 3])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                  "reference_sent.json"))
    args = ap.parse_args()
    T0 = time.time()
    print(f"SENT, W={W} L={L} E={E:.3g} t={THICK}; clamped grips; per unit grip displacement")
    print(f"python {platform.python_version()}, skfem {skfem.__version__}, numpy {np.__version__}, scipy {scipy.__version__}")

    # ------------------------------------------------------------------ sweep
    aw = np.round(np.arange(0.2, 0.9 + 1e-9, 0.025), 6)
    assert np.any(aw == 0.5)
    print(f"\n== A: a/W sweep, level {args.level} (alpha={alpha_of(args.level):.4f}), "
          f"dC/da by central differences, delta_a = {DELTA_A:.1e} m")
    sweep = {m["key"]: [] for m in MATERIALS}
    for x in aw:
        recs = analyse_a(x * W, args.level, MATERIALS)
        for rec in recs:
            sweep[rec["material"]].append(rec)
        r = recs[0]
        Js = r["G_J_domains"]
        spread = (max(Js) - min(Js)) / r["G_J"]
        print(f"a/W={x:.3f} ndofs={r['ndofs']:7d} P={r['P']:.9e} C={r['C']:.9e} "
              f"G_C={r['G_compliance_2pt']:.7e} G_J={r['G_J']:.7e} "
              f"(C-J)/J={r['G_compliance_2pt'] / r['G_J'] - 1:+.1e} J-domain spread {spread:.1e} "
              f"KII/KI={r['KII_int_domains'][1] / r['KI_int_domains'][1]:+.0e} "
              f"[{r['t_total']:.1f}s]", flush=True)

    results = {}
    for mat in MATERIALS:
        recs = sweep[mat["key"]]
        Ep = e_prime(E, mat["nu"], mat["plane"])
        a = np.array([r["a"] for r in recs])
        P = np.array([r["P"] for r in recs])
        C = np.array([r["C"] for r in recs])
        GJ = np.array([r["G_J"] for r in recs])
        GC_ = np.array([r["G_compliance_2pt"] for r in recs])
        KI_J = np.sqrt(GJ * Ep)
        KI_int = np.array([r["KI_int_domains"][MAIN_DOMAIN] for r in recs])
        F = KI_J * W * THICK / (P * np.sqrt(np.pi * a))
        res = dict(
            plane=mat["plane"], nu=mat["nu"], E_prime=Ep,
            a_over_W=(a / W).tolist(), a=a.tolist(),
            compliance=C.tolist(), P_per_unit_delta=P.tolist(),
            P_from_energy=[r["P_from_energy"] for r in recs],
            Px_per_unit_delta=[r["Px"] for r in recs],
            G_compliance=GC_.tolist(), G_J=GJ.tolist(),
            G_J_domains=[r["G_J_domains"] for r in recs],
            rel_diff_G_compliance_vs_J=(GC_ / GJ - 1).tolist(),
            K_I=KI_J.tolist(), K_I_interaction=KI_int.tolist(),
            K_II_interaction=[r["KII_int_domains"][MAIN_DOMAIN] for r in recs],
            F_clamped=F.tolist(), F_tada=f_tada(a / W).tolist(),
            F_gross_srawley=f_gross_srawley(a / W).tolist(),
            ratio_F_clamped_over_F_tada=(F / f_tada(a / W)).tolist(),
            ndofs=[r["ndofs"] for r in recs],
        )
        # independent global check: cubic spline of ln C over the a/W grid
        # (separately generated meshes) -> dC/da
        cs = CubicSpline(a, np.log(C))
        G_spline = 0.5 * P ** 2 / THICK * C * cs(a, 1)
        res["G_spline_of_C_grid"] = G_spline.tolist()
        # independent global check: 2 (U(a_i) - U(a_j)) = -integral of G da
        # at unit Delta: P(a0) - P(a) = 2 int_a0^a G da (Simpson on ln G)
        csG = CubicSpline(a, np.log(GJ))
        fine = np.linspace(a[0], a[-1], 4001)
        integ = np.concatenate([[0.0], np.cumsum(0.5 * (np.exp(csG(fine[1:])) + np.exp(csG(fine[:-1])))
                                                 * np.diff(fine))])
        res["check_P_drop_vs_integral_of_G_J"] = dict(
            P_a0_minus_P_a=(P[0] - P).tolist(),
            two_integral_G_J=(2 * np.interp(a, fine, integ)).tolist())
        if mat["key"] == "plane_stress_nu_1/3":
            Pc = P * np.sqrt(GC / GJ)
            dc = C * Pc
            res["G_c"] = GC
            res["P_c"] = Pc.tolist()
            res["delta_c"] = dc.tolist()
            res["elastic_energy"] = (0.5 * Pc * dc).tolist()
            res["K_c"] = float(np.sqrt(GC * Ep))
        results[mat["key"]] = res

    # ---------------------------------------------------------------- report A
    for mat in MATERIALS:
        res = results[mat["key"]]
        print(f"\n-- {mat['key']}: E'={res['E_prime']:.6e}")
        print(" a/W    C [m/N]          P [N/m]          G_compl [J/m2]   G_J [J/m2]       "
              "C-vs-J    K_I [Pa m^0.5]   KI_int/KI_J-1  F_clamped  F_Tada   F_GS     F/F_Tada")
        for i, x in enumerate(res["a_over_W"]):
            print(f" {x:.3f}  {res['compliance'][i]:.9e}  {res['P_per_unit_delta'][i]:.9e}  "
                  f"{res['G_compliance'][i]:.9e}  {res['G_J'][i]:.9e}  "
                  f"{res['rel_diff_G_compliance_vs_J'][i]:+.1e}  {res['K_I'][i]:.9e}  "
                  f"{res['K_I_interaction'][i] / res['K_I'][i] - 1:+.1e}  "
                  f"   {res['F_clamped'][i]:.6f}  {res['F_tada'][i]:.4f}  "
                  f"{res['F_gross_srawley'][i]:.4f}  {res['ratio_F_clamped_over_F_tada'][i]:.4f}")
        d = np.array(res["rel_diff_G_compliance_vs_J"])
        dsp = np.array(res["G_spline_of_C_grid"]) / np.array(res["G_J"]) - 1
        print(f" max |G_compliance/G_J - 1| = {np.max(np.abs(d)):.2e}; "
              f"spline-of-C-grid derivative vs G_J: max |rel diff| = {np.max(np.abs(dsp)):.2e} "
              f"(interior points 0.25..0.85: {np.max(np.abs(dsp[2:-2])):.2e})")
        chk = res["check_P_drop_vs_integral_of_G_J"]
        print(f" P(0.2W) - P(0.9W) = {chk['P_a0_minus_P_a'][-1]:.9e}, 2 int G_J da = "
              f"{chk['two_integral_G_J'][-1]:.9e} (rel {chk['two_integral_G_J'][-1] / chk['P_a0_minus_P_a'][-1] - 1:+.1e})")
    r3, r1 = results["plane_strain_nu_1/4"], results["plane_stress_nu_1/3"]
    dF = np.max(np.abs(np.array(r3["F_clamped"]) / np.array(r1["F_clamped"]) - 1))
    print(f"\nplane strain nu=1/4 is plane stress nu*=nu/(1-nu)=1/3 with E*=E/(1-nu^2): "
          f"max |F(iii)/F(i) - 1| = {dF:.1e}, P(iii)/P(i) = {np.mean(np.array(r3['P_per_unit_delta']) / np.array(r1['P_per_unit_delta'])):.12f} "
          f"(16/15 = {16 / 15:.12f})")

    # LEFM path
    res = results["plane_stress_nu_1/3"]
    aW = np.array(res["a_over_W"])
    Pc, dc, U = map(np.array, (res["P_c"], res["delta_c"], res["elastic_energy"]))
    print(f"\n-- LEFM path, plane stress nu=1/3, G_c={GC} J/m^2, K_c=sqrt(G_c E)={res['K_c']:.6e} Pa m^0.5")
    print(" a/W    P_c [N/m]        delta_c [m]      U=P_c delta_c/2 [J/m]  d(delta_c)/da sign")
    dd = np.gradient(dc, aW * W)
    for i in range(len(aW)):
        print(f" {aW[i]:.3f}  {Pc[i]:.9e}  {dc[i]:.9e}  {U[i]:.9e}         {'-' if dd[i] < 0 else '+'}")
    # where does Delta_c decrease with a (G at unit Delta increases)?  spline of ln G_J
    csG = CubicSpline(aW, np.log(res["G_J"]))
    fine = np.linspace(aW[0], aW[-1], 70001)
    dec = csG(fine, 1) > 0
    edges = np.nonzero(np.diff(dec.astype(int)))[0]
    bounds = np.concatenate([[0], edges + 1, [len(fine)]])
    intervals = [[float(fine[b0]), float(fine[b1 - 1])] for b0, b1 in zip(bounds[:-1], bounds[1:]) if dec[b0]]
    turning = [float(0.5 * (fine[e] + fine[e + 1])) for e in edges]
    res["snap_back"] = dict(
        description="a/W intervals where Delta_c decreases with a (G at fixed Delta increases with a): "
                    "the LEFM equilibrium path snaps back there, so crack growth is unstable under "
                    "grip-displacement control; elsewhere Delta_c increases and growth is stable",
        a_over_W_intervals_delta_c_decreasing=intervals,
        a_over_W_turning_points=turning,
        delta_c_at_turning_points=[float(np.sqrt(GC / np.exp(csG(x)))) for x in turning],
    )
    print(f" Delta_c decreases with a (snap-back, unstable under displacement control) for a/W in "
          + ", ".join(f"[{i0:.4f}, {i1:.4f}]" for i0, i1 in intervals)
          + "; turning points a/W = " + ", ".join(f"{x:.4f} (delta_c = {d:.6e} m)" for x, d in
                                                  zip(turning, res["snap_back"]["delta_c_at_turning_points"])))
    # energy balance along the whole path (snap-back parts included, d(delta) < 0 there):
    # int P d(Delta) = G_c t (a - a0) + U(a) - U(a0)
    csP = CubicSpline(aW, Pc)
    csD = CubicSpline(aW, dc)
    ff = np.linspace(aW[0], aW[-1], 20001)
    work = np.trapezoid(csP(ff) * csD(ff, 1), ff)
    rhs = GC * THICK * (aW[-1] - aW[0]) * W + U[-1] - U[0]
    res["energy_balance_check"] = dict(
        a_over_W_from=float(aW[0]), a_over_W_to=float(aW[-1]),
        work_int_P_ddelta=float(work), Gc_t_da_plus_dU=float(rhs),
        note="cubic splines of P_c(a), delta_c(a) over the a/W grid")
    print(f" energy balance a/W {aW[0]:.3f} -> {aW[-1]:.3f}: int P_c d(delta_c) = {work:.6e} J/m, "
          f"G_c t (a - a0) + U(a) - U(a0) = {rhs:.6e} J/m (rel {work / rhs - 1:+.1e})")

    # ------------------------------------------------------- convergence A + B
    mat0 = MATERIALS[0]
    conv = {}
    print(f"\n== convergence at a/W = 0.5 (plane stress nu=1/3; A: top (0,1), B: top (1,0)); "
          f"compliance derivative: 2-point (delta), 4-point (delta), 2-point (10 delta)")
    rows = []
    for lev in args.conv_levels:
        rec = analyse_a(0.05, lev, [mat0], stencil=(-10, -2, -1, 1, 2, 10), dc=True, shear=True)[0]
        rows.append(rec)
        sh = rec["shear"]
        print(f"level {lev} alpha={alpha_of(lev):.4f} ndofs={rec['ndofs']:8d} min angle {rec['min_angle_deg']:.1f} "
              f"h_min={rec['h_min']:.1e} h_max={rec['h_max']:.1e}\n"
              f"   A: P={rec['P']:.10e} G_J=[{', '.join(f'{g:.9e}' for g in rec['G_J_domains'])}]\n"
              f"      G_compl 2pt={rec['G_compliance_2pt']:.9e} 4pt={rec['G_compliance_4pt']:.9e} "
              f"2pt(10delta)={rec['G_compliance_2pt_10delta']:.9e}  KI_int={rec['KI_int_domains'][1]:.9e} "
              f"KI_dc={rec['KI_dc']:.6e}\n"
              f"   B: Px={sh['Px']:.10e} Py={sh['Py']:.6e} KII=[{', '.join(f'{g:.9e}' for g in sh['KII_domains'])}] "
              f"KI={sh['KI_domains'][1]:+.2e} KII_dc={sh['KII_dc']:.6e} J={sh['J_domains'][1]:.9e}"
              f" opening [{sh['crack_face_opening_min']:+.1e}, {sh['crack_face_opening_max']:+.1e}] "
              f"(max sliding {sh['crack_face_sliding_max']:.3e})  [{rec['t_total']:.1f}s]", flush=True)
    conv["a_over_W_0.5"] = [dict((k, v) for k, v in r.items() if k not in ("material",)) for r in rows]
    f = rows[-1]
    g = rows[-2]
    print(f" change between the two finest levels: P {f['P'] / g['P'] - 1:+.1e}, "
          f"G_J {f['G_J'] / g['G_J'] - 1:+.1e}, G_compliance {f['G_compliance_2pt'] / g['G_compliance_2pt'] - 1:+.1e}, "
          f"B K_II {f['shear']['KII_domains'][1] / g['shear']['KII_domains'][1] - 1:+.1e}")
    lev_sweep = [r for r in rows if r["level"] == args.level]
    if lev_sweep:
        s = lev_sweep[0]
        print(f" sweep level {args.level} vs finest: P {s['P'] / f['P'] - 1:+.1e}, G_J {s['G_J'] / f['G_J'] - 1:+.1e}, "
              f"G_compliance {s['G_compliance_2pt'] / f['G_J'] - 1:+.1e}, "
              f"B K_II {s['shear']['KII_domains'][1] / f['shear']['KII_domains'][1] - 1:+.1e}")
    for x in (0.2, 0.9):
        rows_e = []
        for lev in args.conv_levels_ends:
            rec = analyse_a(x * W, lev, [mat0])[0]
            rows_e.append(rec)
            print(f"a/W={x} level {lev} ndofs={rec['ndofs']:8d} P={rec['P']:.10e} "
                  f"G_J=[{', '.join(f'{g:.9e}' for g in rec['G_J_domains'])}] "
                  f"G_compl={rec['G_compliance_2pt']:.9e}  [{rec['t_total']:.1f}s]", flush=True)
        conv[f"a_over_W_{x}"] = [dict((k, v) for k, v in r.items() if k not in ("material",)) for r in rows_e]
        f, g = rows_e[-1], rows_e[-2]
        print(f" a/W={x}: change between the two finest levels: P {f['P'] / g['P'] - 1:+.1e}, "
              f"G_J {f['G_J'] / g['G_J'] - 1:+.1e}, G_compliance {f['G_compliance_2pt'] / g['G_compliance_2pt'] - 1:+.1e}")

    # --------------------------------------------------------------------- B
    fin = rows[-1]
    sh = fin["shear"]
    KI, KII = sh["KI_domains"][MAIN_DOMAIN], sh["KII_domains"][MAIN_DOMAIN]
    th = mts_angle(KI, KII)
    Ep = e_prime(E, mat0["nu"], mat0["plane"])
    B = dict(
        description="SENT a/W = 0.5, top grip u = (Delta, 0), bottom u = 0, plane stress nu = 1/3, "
                    "per unit Delta; finest convergence level",
        a_over_W=0.5, level=fin["level"], ndofs=fin["ndofs"],
        Px_per_unit_delta=sh["Px"], Py_per_unit_delta=sh["Py"],
        K_I=KI, K_II=KII, K_I_domains=sh["KI_domains"], K_II_domains=sh["KII_domains"],
        J_domains=sh["J_domains"], J_from_K=(KI ** 2 + KII ** 2) / Ep,
        K_I_displacement_correlation=sh["KI_dc"], K_II_displacement_correlation=sh["KII_dc"],
        K_II_over_K_I=None,
        K_II_over_K_I_note="K_I = 0 by symmetry (computed K_I/K_II is round-off), so K_II/K_I is not defined",
        K_I_over_K_II=KI / KII,
        K_I_is_zero_by_symmetry=True,
        symmetry_note="y -> -y reflection maps problem B onto minus itself plus a rigid translation, so "
                      "sigma_yy is odd in y: K_I = 0 and the normal crack-face gap is zero exactly "
                      "(faces touch without pressure; no interpenetration); pure mode II",
        crack_face_opening_min=sh["crack_face_opening_min"],
        crack_face_opening_max=sh["crack_face_opening_max"],
        crack_face_sliding_max=sh["crack_face_sliding_max"],
        mts_kink_angle_deg=float(np.degrees(th)),
        mts_convention="theta_c = 2 arctan[(K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)], measured from the "
                       "crack's own direction (+x here), counter-clockwise positive; kink direction "
                       "vector (cos theta_c, sin theta_c) in x-y",
        kink_direction=[float(np.cos(th)), float(np.sin(th))],
        mts_pure_mode_II_deg=float(np.degrees(mts_angle(0.0, 1.0))),
        initiation_Gc_200=dict(
            note="LEFM crack initiation for G_c = 200 J/m^2, K_c = sqrt(G_c E'): (a) energy criterion "
                 "J = G_c; (b) MTS criterion K_eq = cos(theta_c/2)[K_I cos^2(theta_c/2) - 1.5 K_II sin theta_c] = K_c",
            delta_c_J=float(np.sqrt(GC / sh["J_domains"][MAIN_DOMAIN])),
            P_x_c_J=float(sh["Px"] * np.sqrt(GC / sh["J_domains"][MAIN_DOMAIN])),
            K_eq_mts_per_unit_delta=float(hoop_stress(th, KI, KII)),
            delta_c_mts=float(np.sqrt(GC * Ep) / hoop_stress(th, KI, KII)),
            P_x_c_mts=float(sh["Px"] * np.sqrt(GC * Ep) / hoop_stress(th, KI, KII))),
    )
    print(f"\n== B (level {fin['level']}): K_I = {KI:+.3e}, K_II = {KII:.9e} Pa m^0.5 per m of grip shear, "
          f"K_I/K_II = {KI / KII:+.1e}; DC: K_II = {sh['KII_dc']:.6e}, K_I = {sh['KI_dc']:+.1e}; "
          f"J = {sh['J_domains'][1]:.9e} vs K^2/E' = {(KI ** 2 + KII ** 2) / Ep:.9e}")
    print(f"   crack-face normal gap (vertex nodes) in [{sh['crack_face_opening_min']:+.2e}, "
          f"{sh['crack_face_opening_max']:+.2e}] m vs max sliding {sh['crack_face_sliding_max']:.4e} m per m of grip shear")
    ini = B["initiation_Gc_200"]
    print(f"   initiation for G_c = {GC}: J = G_c at delta = {ini['delta_c_J']:.6e} m (P_x = {ini['P_x_c_J']:.6e} N/m); "
          f"MTS K_eq = K_c at delta = {ini['delta_c_mts']:.6e} m (P_x = {ini['P_x_c_mts']:.6e} N/m)")
    print(f"   MTS kink angle theta_c = {np.degrees(th):.4f} deg (from +x, CCW positive), direction ({np.cos(th):.5f}, {np.sin(th):.5f})")

    out = dict(
        description="LEFM reference for the clamped-grip SENT plate (dhpd validation/fracture); scikit-fem P2",
        inputs=dict(W=W, L=L, thickness=THICK, E=E, G_c=GC, materials=MATERIALS,
                    grips="clamped: bottom edge u=(0,0); top edge u=(Delta_x, Delta_y) on every node",
                    load_A="top u = (0, 1 m)", load_B="top u = (1 m, 0)",
                    units="SI; forces per m of thickness; all values per unit grip displacement Delta = 1 m",
                    mesh_level_sweep=args.level, alpha_sweep=alpha_of(args.level),
                    mesh="RGB-refined structured grid, h = min(alpha W/2, alpha d) around tip and grip "
                         "corners, alpha = 0.7*2^(-level/2), tip floor 1e-5 W, corner floor 1e-4 W; P2",
                    delta_a_compliance=DELTA_A,
                    J_domains_times_min_a_W_minus_a=DOMAINS, main_domain=MAIN_DOMAIN,
                    G_used_for_K_F_Pc="G_J (main domain)"),
        software=dict(python=platform.python_version(), skfem=skfem.__version__,
                      numpy=np.__version__, scipy=scipy.__version__),
        materials=results,
        mode_mixity_B=B,
        convergence=conv,
        runtime_s=time.time() - T0,
    )
    with open(args.out, "w") as fh:
        json.dump(out, fh, indent=1)
    print(f"\nwrote {args.out} (total runtime {time.time() - T0:.1f} s)")


if __name__ == "__main__":
    main()
