#!/usr/bin/env python3
"""Discrete shape tensor of the shear model across a free-edged strip (rows of a square
grid, infinite in x, overlap partial volumes as in src/discretization/partial_volume.rs)
and the predicted axial force flux P_xx = sum_j f_ij xi_x V_j per row under a homogeneous
uniaxial stress state eps = diag(1, -nu):
   weighted dilatation: P_xx/E = (1+alpha)(1 + alpha nu/(1-nu)),  alpha = (Kxx-Kyy)/m
   gradient dilatation: P_xx/E = (1+alpha)
Also the continuum alpha(s) for a disc truncated at depth s. Prints only."""
import math
import numpy as np

def disc_overlap(big, small, dist):
    if dist >= big + small: return 0.0
    if dist <= abs(big - small): return math.pi * min(big, small) ** 2
    a = small**2 * math.acos(max(-1, min(1, (dist**2 + small**2 - big**2) / (2 * dist * small))))
    b = big**2 * math.acos(max(-1, min(1, (dist**2 + big**2 - small**2) / (2 * dist * big))))
    c = 0.5 * math.sqrt(max(0.0, (-dist + small + big) * (dist + small - big) * (dist - small + big) * (dist + small + big)))
    return a + b - c

def factor(dist, delta, dx, rule):
    r = dx / math.sqrt(math.pi) if rule == "overlap" else 0.5 * dx
    if rule == "none": return float(dist <= delta)
    if rule == "ramp":
        if dist <= delta - r: return 1.0
        if dist <= delta: return (delta + r - dist) / (2 * r)
        return 0.0
    return disc_overlap(delta, r, dist) / (math.pi * r * r)

def rows(n, mfac, rule="overlap"):
    """alpha per row for a strip n rows high (spacing 1)."""
    delta = mfac
    reach = delta + 1 / math.sqrt(math.pi) + 1e-9
    R = int(math.ceil(reach))
    out = []
    for k in range(n):
        m = kxx = kyy = 0.0
        for p in range(-R, R + 1):
            for q in range(-R, R + 1):
                if p == 0 and q == 0: continue
                if not (0 <= k + q < n): continue
                d = math.hypot(p, q)
                f = factor(d, delta, 1.0, rule)
                if f <= 0: continue
                w = f / d**2           # V = 1
                m += w * d * d; kxx += w * p * p; kyy += w * q * q
        out.append((kxx - kyy) / m)
    return np.array(out)

def section(n, mfac, nu, rule="overlap"):
    a = rows(n, mfac, rule)
    wtd = ((1 + a) * (1 + a * nu / (1 - nu))).mean()
    grd = (1 + a).mean()
    return wtd, grd, a

if __name__ == "__main__":
    for n, mf in [(10, 3.015), (20, 3.015), (30, 3.015), (40, 3.015), (10, 2.015), (10, 4.015), (20, 2.015), (20, 4.015), (40, 4.015), (80, 3.015)]:
        for nu in (0.0, 1/3):
            w, g, a = section(n, mf, nu)
            print(f"rows={n:3d} m={mf} nu={nu:.3f}: section factor weighted {w:.4f}, gradient {g:.4f};"
                  f" alpha rows 0..3 = {np.round(a[:4], 4).tolist()}")
    # continuum alpha(s), disc radius 1 truncated at depth s
    print("continuum alpha(s):")
    for s in np.linspace(0, 1, 11):
        # integrate over the truncated disc in polar coords
        N = 2000; th = (np.arange(N) + 0.5) * 2 * np.pi / N; rr = (np.arange(N) + 0.5) / N
        T, Rr = np.meshgrid(th, rr); y = Rr * np.sin(T)
        keep = y >= -s
        A = (Rr * keep).sum(); C = (Rr * np.cos(2 * T) * keep).sum()
        print(f"  s/delta={s:.1f} alpha={C / A:.4f}")
