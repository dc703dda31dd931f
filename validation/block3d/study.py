#!/usr/bin/env python3
"""3D mode I/II/III block of 001 Sec. 6.4 with dhpd's explicit driver.

    python3 validation/block3d/study.py scenes     # (re)write scenes/*.toml
    python3 validation/block3d/study.py run NAME.. # run scenes into $BLOCK3D_OUT/NAME (default /tmp/block3d)
    python3 validation/block3d/study.py            # analyse the runs: results/*.csv, *.png

The raw outputs (VTU snapshots, ~13 MB each at 5 mm) are not committed; the
analysis reads them from $BLOCK3D_OUT (default /tmp/block3d).
"""
import os, sys, re, json, base64, struct, subprocess, glob, time
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(HERE, "scenes")
RESULTS = os.path.join(HERE, "results")
OUT = os.environ.get("BLOCK3D_OUT", "/tmp/block3d")
DHPD = os.environ.get("DHPD", "/work/bin/dhpd")

L, H, B = 0.5, 0.2, 0.1          # block x, y, z (m)
A0 = 0.3                          # initial crack length (m), plane y = H/2
DT = 8.09e-7                      # the paper's time step
PAPER = {1: dict(init=385e-6, speed=343.6, arrest=590e-6, restart=630e-6),
         2: dict(init=120e-6, speed=824.4),
         3: dict(init=360e-6, speed=265.9)}
E, NU, RHO = 30e9, 1 / 3, 2400.0
MU = E / (2 * (1 + NU))
C_S = (MU / RHO) ** 0.5
C_R = C_S * (0.862 + 1.14 * NU) / (1 + NU)   # Viktorov's approximation
GRIP_DIR = {1: "y", 2: "x", 3: "z"}


def scene_name(mode, h, crit):
    return f"mode{mode}_{int(round(h * 1000))}mm_{crit}"


def scene_text(mode, h, crit):
    d = GRIP_DIR[mode]
    name = scene_name(mode, h, crit)
    what = {1: "opening (grips moved apart in +-y)", 2: "in-plane shear (grips moved in +-x)",
            3: "out-of-plane shear (grips moved in +-z)"}[mode]
    crit_txt = ('shear_criterion = "deviatoric"   # 001 Eq. 37-40, the paper\'s rule\n'
                'calibration = "continuum"        # the paper\'s critical value (as validation/dynamics 5b)\n'
                if crit == "deviatoric" else
                '# dhpd defaults: shear_criterion = "energy"; calibration "dissipation" (in 3D no factor\n'
                '# is measured, so the continuum value is kept: the run says so in summary.json)\n')
    n = round(L / h) * round(H / h) * round(B / h)
    lines = [f"# Mode {mode} ({what}) of the 3D block of 001 Sec. 6.4, spacing {h*1000:g} mm ({n:,} points),",
             f"# criterion: {crit}. Block 0.5 x 0.2 x 0.1 m, crack plane y = 0.1 for x < 0.3 m through the",
             "# whole thickness; one point layer of the top and bottom faces at x < 0.1 m moved at +-1 m/s",
             "# (our reading of the paper's Fig. 14, which is not in the text). E = 30 GPa, nu = 1/3,",
             "# rho = 2400, G0 = 200 J/m^2, dt = 8.09e-7 s (the paper's), 1 ms.",
             f'name = "{name}"',
             "[model]", 'dimension = "3d"', 'kind = "shear"',
             "[materials.concrete]", "youngs_modulus = 3.0e10", "poisson_ratio = 0.3333333333333333",
             "density = 2400.0", "fracture_energy = 200.0",
             "[[regions]]", 'material = "concrete"', f"spacing = {h:g}",
             "box = { min = [0.0, 0.0, 0.0], max = [0.5, 0.2, 0.1] }",
             "[[cracks]]                       # the initial crack: no bond crosses it",
             "origin = [0.0, 0.1, 0.0]", "edge1 = [0.3, 0.0, 0.0]", "edge2 = [0.0, 0.0, 0.1]",
             "[[boundary]]                     # one point layer (the paper's) under the cracked part",
             'name = "bottom"', f"box = {{ min = [0.0, 0.0, 0.0], max = [0.1, {h:g}, 0.1] }}",
             f"velocity = {{ {d} = -1.0 }}",
             "[[boundary]]", 'name = "top"', f"box = {{ min = [0.0, {H - h:g}, 0.0], max = [0.1, 0.2, 0.1] }}",
             f"velocity = {{ {d} = 1.0 }}",
             "[fracture]", crit_txt.rstrip("\n"),
             "# the grips would tear (10 mm trial, README): the bonds within 30 mm of the loaded",
             "# layers (as the 2D scene validation/dynamics/scenes/mode_one_dynamic_shear.toml) never break",
             "no_fail = [ { box = { min = [0.0, 0.0, 0.0], max = [0.1, 0.03, 0.1] } },",
             "            { box = { min = [0.0, 0.17, 0.0], max = [0.1, 0.2, 0.1] } } ]",
             "[dynamics]", "end_time = 1e-3", f"time_step = {DT:g}", "record_every = 2",
             "[output]", "every = 20                       # ~62 snapshots", "points_csv = false"]
    # probes: the first point row above the crack plane, from the tip on, at three depths
    for zc, zn in ((h / 2, "z0"), (B / 2 - h / 2, "zmid"), (B - h / 2, "z1")):
        for k in range(round((L - A0) / h)):
            x = A0 + h / 2 + k * h
            lines += ["[[output.probes]]", f'name = "p{k:03d}_{zn}"', f"at = [{x:.6g}, {H/2 + h/2:.6g}, {zc:.6g}]"]
    return "\n".join(lines) + "\n"


def write_scenes():
    os.makedirs(SCENES, exist_ok=True)
    for mode in (1, 2, 3):
        for h in (0.005, 0.01):
            for crit in ("deviatoric", "default"):
                with open(os.path.join(SCENES, scene_name(mode, h, crit) + ".toml"), "w") as f:
                    f.write(scene_text(mode, h, crit))


def run(names):
    os.makedirs(OUT, exist_ok=True)
    for n in names:
        scene = os.path.join(SCENES, n + ".toml")
        out = os.path.join(OUT, n)
        t0 = time.time()
        with open(os.path.join(OUT, n + ".log"), "w") as log:
            subprocess.run(["nice", "-n", "10", DHPD, "run", scene, "--out", out], stdout=log,
                           stderr=subprocess.STDOUT, check=True)
        with open(os.path.join(OUT, n + ".wall"), "w") as f:
            f.write(f"{time.time() - t0:.1f}\n")


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "scenes":
        write_scenes()
    elif len(sys.argv) > 1 and sys.argv[1] == "run":
        run(sys.argv[2:])
