#!/usr/bin/env python3
"""Linear-elastic FEM / LEFM reference for the mode-I 3D block (quasi-static).

Setup (the 3D block of validation/block3d):
  block x in [0, 0.5], y in [0, 0.2], z in [0, B], B = 0.1 m; E = 30 GPa,
  nu = 1/3, linear elastic, small strain; through crack on the plane y = 0.1
  for 0 <= x < a = 0.3 m (straight front x = a along z), traction-free faces,
  no contact; grips: u_y = -v on the bottom face y = 0 and u_y = +v on the top
  face y = 0.2, both for 0 <= x <= 0.1 (only u_y prescribed, u_x and u_z
  free); rigid motions removed by u_x = 0 at the bottom grip near x = 0.045
  (and u_z = 0 at one point in 3D).  P = y reaction of the top grip for the
  whole thickness B, total opening 2v; G0 = 200 J/m^2.
  Everything is linear: results are computed for v = 1 m and scaled.

Method (scikit-fem, P2 elements; the meshers, crack splitting and domain
integrals are reused from validation/fracture/fem/lefm_fem.py):
  * 2D full model (plane stress and plane strain): structured base grid of
    [0, 0.5] x [0, 0.2] (spacing 0.025; grid lines on x = 0.1, x = a,
    y = 0.1), red-green-blue refinement to h = min(alpha H/2, alpha d), d =
    distance to the crack tip (floor 1e-5 H) or to the grip ends (0.1, 0),
    (0.1, 0.2) and grip corners (0, 0), (0, 0.2) (floor 1e-4 H), H = 0.1 m;
    mesh level l has alpha = 0.7 * 2^(-l/2).  The crack is opened by
    duplicating the nodes on y = 0.1, 0 <= x < a (tip node shared).  BCs
    exactly as above (u_x = 0 at the bottom vertex nearest x = 0.045).
    P' = top-grip y reaction per unit thickness for v = 1, checked against the
    strain energy (U = P' v) and against the bottom-grip reaction.
  * G (per unit thickness, v = 1) by three methods:
      (1) compliance: C = 2v/P', G = (P'^2/2) dC/da (= P^2/(2B) dC/da for the
          whole thickness), dC/da by central differences over a with step
          delta = 1e-4 H; the meshes at a +- delta are the mesh of a with the
          nodes near the tip shifted by +-delta * phi(r) (phi = 1 for r < 0.025,
          smooth step to 0 at r = 0.05), so the discretisation error cancels;
      (2) domain J-integral on three annuli (r1, r2) = (0.20, 0.40),
          (0.35, 0.65), (0.50, 0.90) x H around the tip (the middle one is
          G_J; the outer radius 0.09 m stays inside the body);
      (3) interaction integral K_I (Williams auxiliary field), G_K = K_I^2/E'.
  * 2D half model (check of the symmetry bookkeeping, levels 0 and 3):
    y in [0.1, 0.2] with u_y = 0 on the ligament y = 0.1, x > a and u_x = 0
    at the top vertex nearest x = 0.045; G = 2 J_half, K_I = 2 K_I,half.
  * mesh convergence: levels 0-3 of the full model; the finest level gives
    the reference numbers.
  * LEFM critical point: G(v) = g v^2 with g = G_J at v = 1, so
    v_c = sqrt(G0/g), 2v_c, P_c = B P' v_c; stiffness k = P/(2v) = B P'/2;
    G per unit P^2 = g / (B P')^2.
  * LEFM propagation path (P and 2v with G = G0 for a = 0.3 ... 0.45 m; half
    model, level 2).
  * 3D (nu = 1/3): quarter model y in [0.1, 0.2], z in [0, B/2] with u_y = 0
    on the ligament, u_z = 0 on the mid-plane z = B/2 and u_x = 0 at the one
    top-grip node nearest (0.045, 0.2, B/2) (a point instead of the line of
    the full problem: the line adds only a self-equilibrated constraint).
    Mesh: the 2D half-model section mesh (alpha 1.0, tip floor 1e-3 H;
    coarse check: alpha 1.4, tip floor 1e-2 H) extruded through z layers
    graded (x2) toward the free face z = 0, prisms split into 3 tetrahedra,
    P2 tetrahedra (extrusion, assembly and LU-preconditioned CG of
    fem_sent3d.py).  P = 2 P_quarter (v = 1); G_avg = -(2v/B) dP_quarter/da
    (compliance, same morph as in 2D) and G_avg = 4 I_quarter / B (3D domain
    integral, q = q_2D(r) uniform in z).  Checks: a 3D plane-strain run
    (u_z = 0 also on z = 0) against the 2D plane-strain half model on the
    same section mesh (bookkeeping and z discretisation), and that 2D
    section model against the finest 2D model (in-plane discretisation
    error); the 3D free-face P' and G divided by (1 + that error) are the
    corrected 3D estimate.
  * Beam (double cantilever) estimates G = 3 E h^3 (2v)^2 / (16 a_eff^4),
    h = 0.1, E plane stress, a_eff = a measured from x = 0, from the grip
    centre x = 0.05 or from the grip end x = 0.1, each without and with the
    root-rotation correction 0.64 h; P from the same cantilever,
    P' = E h^3 v / (4 a_eff^3).

Run:  python3 fem_block.py     (writes reference_block.json next to this file;
      about 6 min on one core; the 3D part peaks at ~10 GB of memory)
"""
import json
import os
import platform
import sys
import time

import numpy as np
import scipy

import skfem
from skfem import Basis, ElementTetP2, MeshTet, MeshTri1

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "fracture", "fem"))
from lefm_fem import (Model, e_prime, lame, mesh_quality,  # noqa: E402
                      point_size_field, refine_to_size, smooth_step_q,
                      split_crack, structured_tri, tip_integrals, uniform_lines)
from fem_sent3d import Model3D, Solver, extrude, z_fractions  # noqa: E402

LX, LY, B = 0.5, 0.2, 0.1      # block [m]
Y_CRACK = 0.1                  # crack plane
H = 0.1                        # arm height (= LY / 2)
A_CRACK = 0.3                  # crack length [m]
X_GRIP = 0.1                   # grips cover 0 <= x <= X_GRIP
X_FIX = 0.045                  # u_x = 0 near here
E = 30e9
NU = 1.0 / 3.0
G0 = 200.0
H0 = 0.025                     # base grid spacing
TIP_FLOOR = 1e-5 * H
CORNER_FLOOR = 1e-4 * H
DELTA_A = 1e-4 * H             # crack-length step of the compliance derivative
DOMAINS = [(0.20, 0.40), (0.35, 0.65), (0.50, 0.90)]   # x ell (ell = H here)
MAIN_DOMAIN = 1
LEVELS = [0, 1, 2, 3]
PLANES = ("stress", "strain")
PATH_A = [0.3, 0.325, 0.35, 0.375, 0.4, 0.425, 0.45]
PATH_LEVEL = 2
# 3D meshes: in-plane alpha and tip floor, first z layer and largest layer (fractions of B/2)
LEVELS_3D = {"coarse": dict(alpha=1.4, tip_floor=1e-2 * H, dz0=4e-2, dzmax=0.4),
             "main": dict(alpha=1.0, tip_floor=1e-3 * H, dz0=2e-2, dzmax=0.25)}
TOL = 1e-9


def alpha_of(level):
    return 0.7 * 2.0 ** (-level / 2.0)


def ell_of(a):
    """Length scale of the J domains / morph region: stays inside the body."""
    return min(H, LX - a)


# --------------------------------------------------------------------- 2D mesh
def block_mesh(a, alpha, half, tip_floor=TIP_FLOOR):
    """P1 triangle mesh (MeshTri1) of the full block (crack opened) or of the upper half."""
    xs = np.concatenate([uniform_lines(0, X_GRIP, H0)[:-1],
                         uniform_lines(X_GRIP, a, H0)[:-1],
                         uniform_lines(a, LX, H0)])
    y0 = Y_CRACK if half else 0.0
    ys = uniform_lines(y0, LY, H0)
    # "/" above the crack plane, "\" below: the grid is mirror symmetric
    p, t = structured_tri(xs, ys, lambda xc, yc: yc > Y_CRACK)
    pts = [(a, Y_CRACK), (X_GRIP, LY), (0.0, LY)]
    if not half:
        pts += [(X_GRIP, 0.0), (0.0, 0.0)]
    sf = point_size_field(pts, alpha, [tip_floor] + [CORNER_FLOOR] * (len(pts) - 1),
                          alpha * H / 2)
    m = refine_to_size(MeshTri1(p, t), sf)
    if half:
        return m
    p2, t2, _ = split_crack(m.p, m.t, [((0.0, Y_CRACK), (a, Y_CRACK))], [(a, Y_CRACK)])
    return MeshTri1(p2, t2)


def morph_points(p, a, da):
    """x += da * phi(r), r = in-plane distance to the tip (a, Y_CRACK)."""
    ell = ell_of(a)
    p = p.copy()
    r = np.hypot(p[0] - a, p[1] - Y_CRACK)
    p[0] += da * smooth_step_q(r, 0.25 * ell, 0.5 * ell)
    return p


def nearest_vertex(mesh, x, y):
    return int(np.argmin(np.hypot(mesh.p[0] - x, mesh.p[1] - y)))


# --------------------------------------------------------------------- 2D solve
def solve_2d(model, a, plane, half):
    """v = 1; returns u, P' (top grip, per unit thickness), checks, lam, mu."""
    lam, mu = lame(E, NU, plane)
    K = model.K(lam, mu)
    m = model.mesh
    nd = model.basis.nodal_dofs
    _, top_y = model.edge_dofs(lambda x: (np.abs(x[1] - LY) < TOL) & (x[0] < X_GRIP))
    if half:
        _, low_y = model.edge_dofs(lambda x: (np.abs(x[1] - Y_CRACK) < TOL) & (x[0] > a))
        low_val = 0.0
        fix_x = nd[0, nearest_vertex(m, X_FIX, LY)]
    else:
        _, low_y = model.edge_dofs(lambda x: (np.abs(x[1]) < TOL) & (x[0] < X_GRIP))
        low_val = -1.0
        fix_x = nd[0, nearest_vertex(m, X_FIX, 0.0)]
    fixed = np.concatenate([top_y, low_y, [fix_x]])
    vals = np.concatenate([np.ones(len(top_y)), np.full(len(low_y), low_val), [0.0]])
    u = model.solve_dirichlet(K, fixed, vals)
    r = K @ u
    P = float(r[top_y].sum())
    U = 0.5 * float(u @ r)
    return dict(u=u, P=P, P_from_energy=(2 * U if half else U),
                P_bottom=(None if half else -float(r[low_y].sum())),
                Rx_fix=float(r[fix_x]), lam=lam, mu=mu)


def analyse_2d(a, alpha, half, planes=PLANES):
    """G at crack length a by compliance, domain J and interaction integral."""
    t0 = time.time()
    mesh = block_mesh(a, alpha, half)
    models = {k: Model(MeshTri1(morph_points(mesh.p, a, k * DELTA_A), mesh.t)) if k else Model(mesh)
              for k in (-1, 0, 1)}
    ell = ell_of(a)
    fac = 2.0 if half else 1.0            # half model: J and K_I of the half domain
    out = {}
    for plane in planes:
        # the ligament of the morphed half-model meshes starts at the shifted tip
        S = {k: solve_2d(mdl, a + k * DELTA_A, plane, half) for k, mdl in models.items()}
        s0 = S[0]
        C = {k: 2.0 / s["P"] for k, s in S.items()}
        P = s0["P"]
        tips = [tip_integrals(models[0], s0["u"], (a, Y_CRACK), (1.0, 0.0), s0["lam"], s0["mu"],
                              plane, NU, E, f1 * ell, f2 * ell) for f1, f2 in DOMAINS]
        Ep = e_prime(E, NU, plane)
        GJ = [fac * d["J"] for d in tips]
        KI = [fac * d["KI"] for d in tips]
        rec = dict(a=a, alpha=alpha, half_model=half, ndofs=models[0].ndofs,
                   n_elems=int(mesh.t.shape[1]),
                   P_per_unit_v_per_unit_thickness=P,
                   P_from_energy_rel_diff=s0["P_from_energy"] / P - 1,
                   G_compliance=0.5 * P ** 2 * (C[1] - C[-1]) / (2 * DELTA_A),
                   G_J_domains=GJ, G_J=GJ[MAIN_DOMAIN],
                   KI_domains=KI, G_K_domains=[k ** 2 / Ep for k in KI],
                   KII_domains=[fac * d["KII"] for d in tips])
        rec["G_K"] = rec["G_K_domains"][MAIN_DOMAIN]
        if not half:
            rec["P_bottom_rel_diff"] = s0["P_bottom"] / P - 1
            rec["Rx_fix_over_P"] = s0["Rx_fix"] / P
        out[plane] = rec
    qual = mesh_quality(mesh)
    for rec in out.values():
        rec["min_angle_deg"], rec["h_min"], rec["h_max"] = qual
        rec["t_s"] = time.time() - t0
    return out


def critical(P1, g):
    """P' at v = 1 and G at v = 1 (per unit thickness) -> LEFM quantities (whole B)."""
    vc = float(np.sqrt(G0 / g))
    return dict(k_N_per_m=B * P1 / 2, G_per_unit_v2=g, G_per_unit_2v_squared=g / 4,
                G_per_unit_P2=g / (B * P1) ** 2, v_c=vc, opening_2v_c=2 * vc,
                P_c=B * P1 * vc, P_c_per_unit_thickness=P1 * vc)


# --------------------------------------------------------------------- 3D
def dirichlet_3d(model, a, plane_strain):
    m, b = model.mesh, model.basis
    top = b.get_dofs(facets=m.facets_satisfying(lambda x: (np.abs(x[1] - LY) < TOL) & (x[0] < X_GRIP)))
    lig = b.get_dofs(facets=m.facets_satisfying(lambda x: (np.abs(x[1] - Y_CRACK) < TOL) & (x[0] > a)))
    mid = b.get_dofs(facets=m.facets_satisfying(lambda x: np.abs(x[2] - B / 2) < TOL))
    fixed = {int(d): 1.0 for d in top.all("u^2")}
    fixed.update({int(d): 0.0 for d in lig.all("u^2")})
    fixed.update({int(d): 0.0 for d in mid.all("u^3")})
    if plane_strain:
        face = b.get_dofs(facets=m.facets_satisfying(lambda x: np.abs(x[2]) < TOL))
        fixed.update({int(d): 0.0 for d in face.all("u^3")})
    pin = int(np.argmin(np.hypot(np.hypot(m.p[0] - X_FIX, m.p[1] - LY), m.p[2] - B / 2)))
    fixed[int(b.nodal_dofs[0, pin])] = 0.0
    D = np.array(sorted(fixed), dtype=np.int64)
    return D, np.array([fixed[d] for d in D]), np.asarray(top.all("u^2"))


def domain_integral_3d(model, u, a, r1, r2, intorder=3):
    """I = int [sigma_ij u_i,1 - w delta_1j] q,j dV over the quarter, q = q(r)."""
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    m = model.mesh
    p, t = m.p, m.t
    dv = np.hypot(p[0] - a, p[1] - Y_CRACK)[t]
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
    X = sb.doflocs
    gq = sb.interpolate(smooth_step_q(np.hypot(X[0] - a, X[1] - Y_CRACK), r1, r2)).grad
    return float(np.sum(vb.dx * np.einsum("jen,jen->en", S, gq)))


def analyse_3d(name, cases, log):
    """3D quarter model on mesh LEVELS_3D[name]; cases: subset of ("plane_strain_check", "free_faces")."""
    a = A_CRACK
    lv = LEVELS_3D[name]
    t0 = time.time()
    m2 = block_mesh(a, lv["alpha"], half=True, tip_floor=lv["tip_floor"])
    zs = z_fractions(lv["dz0"], lv["dzmax"]) * B / 2
    mesh = extrude(m2, zs)
    models = {k: Model3D(MeshTet(morph_points(mesh.p, a, k * DELTA_A), mesh.t)) if k else Model3D(mesh)
              for k in (-1, 0, 1)}
    # 2D plane-strain half model on the same section mesh (reference of the check)
    m2d = Model(m2)
    s2d = solve_2d(m2d, a, "strain", half=True)
    ell = ell_of(a)
    GJ2d = 2 * tip_integrals(m2d, s2d["u"], (a, Y_CRACK), (1.0, 0.0), s2d["lam"], s2d["mu"], "strain",
                             NU, E, DOMAINS[MAIN_DOMAIN][0] * ell, DOMAINS[MAIN_DOMAIN][1] * ell)["J"]
    t_asm = time.time() - t0
    out = dict(section_vertices=int(m2.p.shape[1]), z_nodes=zs.tolist(), n_tets=int(mesh.t.shape[1]),
               ndofs=int(models[0].basis.N), level=lv,
               section_2d_plane_strain=dict(P_per_unit_v_per_unit_thickness=s2d["P"], G_J=GJ2d))
    log(f"  3D mesh {name}: section vertices {m2.p.shape[1]}, z layers {len(zs) - 1} (first {zs[1]:.2e} m), "
        f"tets {mesh.t.shape[1]}, ndofs {models[0].basis.N}; assembly {t_asm:.0f} s", flush=True)
    for case in cases:
        pe = case == "plane_strain_check"
        t1 = time.time()
        D, vals, topy = dirichlet_3d(models[0], a, pe)
        solver = Solver(models[0].K(NU), D)
        Pq = {}
        for k, mdl in models.items():
            K = mdl.K(NU)
            u, it, res = solver.solve(K, D, vals)
            r = K @ u
            Pq[k] = float(r[topy].sum())
            if k == 0:
                u0, Uq = u, 0.5 * float(u @ r)
        P1 = 2 * Pq[0] / B                    # whole-thickness P per unit v, per unit thickness
        Gc = -2 * (Pq[1] - Pq[-1]) / (2 * DELTA_A) / B
        GJ = [4 * domain_integral_3d(models[0], u0, a, f1 * ell, f2 * ell) / B for f1, f2 in DOMAINS]
        rec = dict(P_per_unit_v_per_unit_thickness=P1, P_from_energy_rel_diff=4 * Uq / (B * P1) - 1,
                   G_compliance=Gc, G_J_domains=GJ, G_J=GJ[MAIN_DOMAIN],
                   rel_diff_compliance_vs_J=Gc / GJ[MAIN_DOMAIN] - 1,
                   t_factorisation_s=solver.t_fact, t_s=time.time() - t1)
        rec.update(critical(P1, GJ[MAIN_DOMAIN]))
        if pe:
            rec["vs_2D_plane_strain_same_section"] = dict(P=P1 / s2d["P"] - 1, G_J=GJ[MAIN_DOMAIN] / GJ2d - 1,
                                                          G_compliance=Gc / GJ2d - 1)
        out[case] = rec
        log(f"  3D {case}: P'={P1:.6e} N/m/m (energy check {rec['P_from_energy_rel_diff']:+.1e}) "
            f"G_compl={Gc:.6e} G_J={GJ[MAIN_DOMAIN]:.6e} (C-J)/J={rec['rel_diff_compliance_vs_J']:+.1e} "
            f"J-domain spread {(max(GJ) - min(GJ)) / GJ[MAIN_DOMAIN]:.1e}  P_c={rec['P_c'] / 1e3:.3f} kN "
            f"2v_c={rec['opening_2v_c'] * 1e3:.5f} mm  [{rec['t_s']:.0f} s]", flush=True)
        if pe:
            c = rec["vs_2D_plane_strain_same_section"]
            log(f"    vs 2D plane strain (same section mesh): P {c['P']:+.1e}, G_J {c['G_J']:+.1e}, "
                f"G_compl {c['G_compliance']:+.1e}", flush=True)
    return out


# --------------------------------------------------------------------- beam
def beam_estimates(log):
    """Cantilever DCB: P' = E h^3 v/(4 L^3), G = 3 E h^3 (2v)^2/(16 L^4) per unit thickness."""
    out = {}
    for name, x0 in (("from_x0", 0.0), ("from_grip_centre", X_GRIP / 2), ("from_grip_end", X_GRIP)):
        for corr in (0.0, 0.64):
            L = A_CRACK - x0 + corr * H
            g = 3 * E * H ** 3 * 2.0 ** 2 / (16 * L ** 4)      # v = 1
            P1 = E * H ** 3 / (4 * L ** 3)
            key = f"{name}{'_plus_0.64h' if corr else ''}"
            out[key] = dict(a_eff=L, **critical(P1, g))
            log(f"  beam {key:32s} a_eff={L:.3f} m: k={out[key]['k_N_per_m']:.4e} N/m "
                f"G/(2v)^2={g / 4:.4e} J/m^4  P_c={out[key]['P_c'] / 1e3:.3f} kN "
                f"2v_c={out[key]['opening_2v_c'] * 1e3:.5f} mm")
    return out


# --------------------------------------------------------------------- main
def fmt(rec):
    sp = (max(rec["G_J_domains"]) - min(rec["G_J_domains"])) / rec["G_J"]
    return (f"P'={rec['P_per_unit_v_per_unit_thickness']:.9e} (energy {rec['P_from_energy_rel_diff']:+.0e}) "
            f"G_C={rec['G_compliance']:.7e} G_J={rec['G_J']:.7e} G_K={rec['G_K']:.7e} "
            f"(C-J)/J={rec['G_compliance'] / rec['G_J'] - 1:+.1e} (K-J)/J={rec['G_K'] / rec['G_J'] - 1:+.1e} "
            f"J-spread {sp:.0e}")


def main():
    T0 = time.time()
    lines = []

    def log(*args, **kw):
        s = " ".join(str(x) for x in args)
        lines.append(s)
        print(s, flush=True)

    log(f"Mode-I block: {LX} x {LY} x {B} m, crack y={Y_CRACK} 0<=x<{A_CRACK}, grips 0<=x<={X_GRIP} "
        f"(u_y = -+v), E={E:.3g} nu={NU:.4f} G0={G0}")
    log(f"python {platform.python_version()}, skfem {skfem.__version__}, numpy {np.__version__}, "
        f"scipy {scipy.__version__}")

    log("\n== 2D full model (crack opened), P2, mesh levels; v = 1, per unit thickness")
    full = {}
    for lev in LEVELS:
        res = analyse_2d(A_CRACK, alpha_of(lev), half=False)
        full[lev] = res
        r0 = res["stress"]
        log(f" level {lev} alpha={alpha_of(lev):.3f} ndofs={r0['ndofs']} elems={r0['n_elems']} "
            f"min angle {r0['min_angle_deg']:.1f} h_min {r0['h_min']:.1e} [{r0['t_s']:.1f} s]; "
            f"bottom/top reaction -1 = {r0['P_bottom_rel_diff']:+.0e}, Rx_fix/P = {r0['Rx_fix_over_P']:+.0e}")
        for plane in PLANES:
            log(f"   plane {plane:6s}: {fmt(res[plane])}")

    log("\n== 2D half model (symmetry u_y = 0 on the ligament), levels 0 and finest")
    half = {}
    for lev in (LEVELS[0], LEVELS[-1]):
        res = analyse_2d(A_CRACK, alpha_of(lev), half=True)
        half[lev] = res
        for plane in PLANES:
            f = full[lev][plane]
            h = res[plane]
            log(f" level {lev} plane {plane:6s}: {fmt(h)}")
            log(f"     half/full - 1: P {h['P_per_unit_v_per_unit_thickness'] / f['P_per_unit_v_per_unit_thickness'] - 1:+.1e}"
                f", G_J {h['G_J'] / f['G_J'] - 1:+.1e}, G_C {h['G_compliance'] / f['G_compliance'] - 1:+.1e}")

    log("\n== mesh convergence (full model): relative change to the finest level")
    fin = LEVELS[-1]
    conv = {}
    for plane in PLANES:
        conv[plane] = {}
        for lev in LEVELS[:-1]:
            c, f = full[lev][plane], full[fin][plane]
            d = {q: c[q] / f[q] - 1 for q in ("P_per_unit_v_per_unit_thickness", "G_compliance", "G_J", "G_K")}
            conv[plane][lev] = d
            log(f"  {plane:6s} level {lev}: P {d['P_per_unit_v_per_unit_thickness']:+.1e}  "
                f"G_C {d['G_compliance']:+.1e}  G_J {d['G_J']:+.1e}  G_K {d['G_K']:+.1e}")

    log("\n== LEFM critical point (finest full model, G = G_J; whole thickness B = 0.1 m)")
    results = {}
    for plane in PLANES:
        f = full[fin][plane]
        crit = critical(f["P_per_unit_v_per_unit_thickness"], f["G_J"])
        crit_c = critical(f["P_per_unit_v_per_unit_thickness"], f["G_compliance"])
        crit_k = critical(f["P_per_unit_v_per_unit_thickness"], f["G_K"])
        results[f"plane_{plane}"] = dict(
            level=fin, **crit,
            P_c_from_G_compliance=crit_c["P_c"], P_c_from_G_K=crit_k["P_c"],
            G_methods_per_unit_v2_per_unit_thickness=dict(compliance=f["G_compliance"], J=f["G_J"], K=f["G_K"]),
            E_prime=e_prime(E, NU, plane))
        log(f"  plane {plane:6s}: k = P/(2v) = {crit['k_N_per_m']:.6e} N/m, G/(2v)^2 = "
            f"{crit['G_per_unit_2v_squared']:.6e} J/m^4, G/P^2 = {crit['G_per_unit_P2']:.6e} J/m^2/N^2")
        log(f"                 P_c = {crit['P_c'] / 1e3:.4f} kN ({crit['P_c_per_unit_thickness'] / 1e3:.3f} kN/m), "
            f"2v_c = {crit['opening_2v_c'] * 1e3:.6f} mm  (P_c from G_C {crit_c['P_c'] / 1e3:.4f}, "
            f"from G_K {crit_k['P_c'] / 1e3:.4f} kN)")

    log(f"\n== LEFM propagation path (half model, level {PATH_LEVEL}, G = G_J = G0)")
    log("   a [m]   P/(2v) [N/m]    G/(2v)^2 [J/m^4]  (C-J)/J   P_c [kN]   2v_c [mm]  (plane stress | plane strain)")
    path = {plane: [] for plane in PLANES}
    for a in PATH_A:
        res = analyse_2d(a, alpha_of(PATH_LEVEL), half=True)
        row = []
        for plane in PLANES:
            r = res[plane]
            c = critical(r["P_per_unit_v_per_unit_thickness"], r["G_J"])
            path[plane].append(dict(a=a, k_N_per_m=c["k_N_per_m"], G_per_unit_2v_squared=c["G_per_unit_2v_squared"],
                                    G_compliance_rel_diff=r["G_compliance"] / r["G_J"] - 1,
                                    P_c=c["P_c"], opening_2v_c=c["opening_2v_c"]))
            row.append(f"{c['k_N_per_m']:.5e}  {c['G_per_unit_2v_squared']:.5e}  "
                       f"{r['G_compliance'] / r['G_J'] - 1:+.0e}  {c['P_c'] / 1e3:8.3f}  {c['opening_2v_c'] * 1e3:.5f}")
        log(f"   {a:.3f}  " + "  |  ".join(row))

    log("\n== beam-theory (cantilever DCB, E plane stress) estimates")
    beam = beam_estimates(log)

    log("\n== 3D quarter model (P2 tetrahedra, nu = 1/3)")
    res3d = {"main": analyse_3d("main", ("plane_strain_check", "free_faces"), log),
             "coarse": analyse_3d("coarse", ("free_faces",), log)}
    m3, c3 = res3d["main"]["free_faces"], res3d["coarse"]["free_faces"]
    res3d["coarse_vs_main"] = {q: c3[q] / m3[q] - 1 for q in ("P_per_unit_v_per_unit_thickness",
                                                             "G_compliance", "G_J", "P_c", "opening_2v_c")}
    log("  3D coarse/main - 1: " + ", ".join(f"{q} {v:+.1e}" for q, v in res3d["coarse_vs_main"].items()))
    # in-plane discretisation error of the main 3D section: its 2D plane-strain half model vs the
    # finest 2D full model; the 3D free-face values divided by (1 + error) are the corrected estimate
    sec, fps = res3d["main"]["section_2d_plane_strain"], full[LEVELS[-1]]["strain"]
    eP = sec["P_per_unit_v_per_unit_thickness"] / fps["P_per_unit_v_per_unit_thickness"] - 1
    eG = sec["G_J"] / fps["G_J"] - 1
    res3d["section_error_vs_finest_2D"] = dict(P=eP, G_J=eG)
    res3d["free_faces_corrected"] = critical(m3["P_per_unit_v_per_unit_thickness"] / (1 + eP), m3["G_J"] / (1 + eG))
    c = res3d["free_faces_corrected"]
    log(f"  3D section error (2D plane strain, section mesh vs finest): P {eP:+.1e}, G_J {eG:+.1e}; corrected 3D: "
        f"k={c['k_N_per_m']:.5e} N/m P_c={c['P_c'] / 1e3:.3f} kN 2v_c={c['opening_2v_c'] * 1e3:.5f} mm")

    ps, pe = results["plane_stress"], results["plane_strain"]
    r3 = res3d["free_faces_corrected"]
    log("\n== summary (whole thickness B = 0.1 m, G0 = 200 J/m^2)")
    log(f"  plane stress : k = {ps['k_N_per_m']:.5e} N/m, P_c = {ps['P_c'] / 1e3:.3f} kN, 2v_c = {ps['opening_2v_c'] * 1e3:.5f} mm")
    log(f"  plane strain : k = {pe['k_N_per_m']:.5e} N/m, P_c = {pe['P_c'] / 1e3:.3f} kN, 2v_c = {pe['opening_2v_c'] * 1e3:.5f} mm")
    log(f"  3D (corr.)   : k = {r3['k_N_per_m']:.5e} N/m, P_c = {r3['P_c'] / 1e3:.3f} kN, 2v_c = {r3['opening_2v_c'] * 1e3:.5f} mm")
    for key, b in beam.items():
        log(f"  beam {key:32s}: P_c/P_c(plane stress) = {b['P_c'] / ps['P_c']:.3f}, "
            f"2v_c/2v_c(plane stress) = {b['opening_2v_c'] / ps['opening_2v_c']:.3f}, "
            f"G/G_FEM = {b['G_per_unit_v2'] / ps['G_per_unit_v2']:.3f}")
    runtime = time.time() - T0
    log(f"\ntotal runtime {runtime:.1f} s")

    def clean(d):
        return {str(k): (clean(v) if isinstance(v, dict) else v) for k, v in d.items()}

    out = dict(
        description="Linear-elastic FEM/LEFM reference for the mode-I 3D block of validation/block3d "
                    "(scikit-fem P2; 2D plane stress / plane strain, coarse 3D quarter model)",
        inputs=dict(block=[LX, LY, B], crack_plane_y=Y_CRACK, a=A_CRACK, grips=f"u_y = -v (y=0) / +v (y={LY}) "
                    f"for 0<=x<={X_GRIP}, u_x, u_z free; u_x = 0 near x = {X_FIX} on the bottom grip",
                    E=E, nu=NU, G0=G0, units="SI: N, m, J/m^2; k = P/(2v) in N/m; P for the whole thickness B",
                    mesh_levels={str(l): alpha_of(l) for l in LEVELS}, tip_floor=TIP_FLOOR,
                    corner_floor=CORNER_FLOOR, delta_a_compliance=DELTA_A,
                    J_domains=[[f1 * H, f2 * H] for f1, f2 in DOMAINS], main_domain=MAIN_DOMAIN,
                    G_used_for_critical_point="G_J (main domain), finest level of the full model"),
        software=dict(python=platform.python_version(), skfem=skfem.__version__,
                      numpy=np.__version__, scipy=scipy.__version__),
        results=results,
        full_model_levels=clean(full),
        half_model_check=clean(half),
        convergence_rel_to_finest=clean(conv),
        propagation_path_half_model=dict(level=PATH_LEVEL, **path),
        model_3d=res3d,
        beam_estimates=beam,
        runtime_s=runtime,
    )
    with open(os.path.join(HERE, "reference_block.json"), "w") as fh:
        json.dump(out, fh, indent=1)
    with open(os.path.join(HERE, "run_log_block.txt"), "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print(f"wrote {os.path.join(HERE, 'reference_block.json')} and run_log_block.txt")


if __name__ == "__main__":
    main()
