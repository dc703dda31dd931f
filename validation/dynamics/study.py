"""Explicit-dynamics benchmarks of dhpd (issue 9): reflection at a horizon jump,
wave speed, dynamic relaxation against the implicit solve, throughput.

Usage: python3 validation/dynamics/study.py
       [reflection|waves|relaxation|throughput|corner|shear_fracture|kalthoff|branching|all]
Env DHPD: the dhpd binary (default target/release/dhpd). Writes the scenes it
runs into scenes/, numbers into results/, figures next to this file.
"""

import csv
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DHPD = os.environ.get("DHPD", os.path.join(ROOT, "target", "release", "dhpd"))
SCENES = os.path.join(HERE, "scenes")
RESULTS = os.path.join(HERE, "results")
os.makedirs(SCENES, exist_ok=True)
os.makedirs(RESULTS, exist_ok=True)
WORK = tempfile.mkdtemp(prefix="dhpd-dyn-")


def run(name, text, threads=None, keep=True):
    """Writes scenes/NAME.toml (when keep) and runs it; returns the output dir."""
    path = os.path.join(SCENES if keep else WORK, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(WORK, name)
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    subprocess.run([DHPD, "run", path, "--out", out], check=True, env=env,
                   stdout=subprocess.DEVNULL)
    return out


def points(out):
    with open(os.path.join(out, "points.csv")) as f:
        return list(csv.DictReader(f))


def summary(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


# ---------------------------------------------------------------- reflection
FINE = 1.0 / 240.0  # close to the paper's 4.19e-3 m, and a whole number per metre


def jump_scene(horizons, ratio, width, end_time, every=None):
    """1D bar, E = rho = 1 (c = 1): fine part [0, Lf], coarse part [Lf, 2 Lf]
    with ratio x the spacing; a pulse at Lf/2 splits in two halves; the
    right-going one crosses the jump at t = Lf/2."""
    lf = 16.0 * width
    lf = math.ceil(lf / (ratio * FINE)) * ratio * FINE
    text = f"""# Reflection at a horizon jump (000 Sec. 4, formulation Sec. 9): 1D bar,
# E = rho = 1, fine spacing {FINE:.6g} m on [0, {lf:.6g}], {ratio} x coarser beyond,
# delta = 3.015 x spacing, Gaussian pulse of width {width} m at the middle of the fine part.
[model]
dimension = "1d"
horizons = "{horizons}"
[materials.m]
youngs_modulus = 1.0
density = 1.0
[[regions]]
material = "m"
spacing = {FINE!r}
box = {{ min = [0.0], max = [{lf!r}] }}
[[regions]]
material = "m"
spacing = {ratio * FINE!r}
box = {{ min = [{lf!r}], max = [{2 * lf!r}] }}
[[initial_conditions]]
gaussian = {{ center = [{lf / 2!r}], width = {width}, amplitude = [0.002] }}
[dynamics]
end_time = {end_time!r}
record_every = 100000
"""
    return text, lf


def reflection():
    rows = []
    for ratio in (2, 10):
        for width in (0.1, 0.2, 0.3, 0.5):
            for horizons in ("dual", "traditional", "constant"):
                _, lf = jump_scene(horizons, ratio, width, 1.0)
                t_end = 0.75 * lf
                text, _ = jump_scene(horizons, ratio, width, t_end)
                name = f"jump_{horizons}_r{ratio}_w{width}"
                out = run(name, text, keep=(width == 0.3))
                pts = points(out)
                window = [abs(float(p["u_x"])) for p in pts
                          if 0.5 * lf < float(p["x"]) < 0.95 * lf]
                transmitted = max(abs(float(p["u_x"])) for p in pts if float(p["x"]) > lf)
                s = summary(out)
                rows.append(dict(ratio=ratio, width=width, horizons=horizons,
                                 reflection_percent=100 * max(window) / 0.001,
                                 transmitted_percent=100 * transmitted / 0.001,
                                 balance_error=s["max_balance_error"],
                                 points=s["points"], steps=s["steps"]))
                print(rows[-1])
    with open(os.path.join(RESULTS, "reflection.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    # Snapshots of the ratio-10, width-0.3 case.
    snaps = {}
    for horizons in ("dual", "traditional"):
        _, lf = jump_scene(horizons, 10, 0.3, 1.0)
        for frac in (0.0, 0.35, 0.5, 0.6, 0.75):
            t = max(frac * lf, 1e-9)
            text, _ = jump_scene(horizons, 10, 0.3, t)
            out = run(f"snap_{horizons}_{frac}", text, keep=False)
            pts = points(out)
            snaps[(horizons, frac)] = ([float(p["x"]) for p in pts],
                                       [float(p["u_x"]) for p in pts])
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    for ax, horizons in zip(axes, ("dual", "traditional")):
        for k, frac in enumerate((0.0, 0.35, 0.5, 0.6, 0.75)):
            x, u = snaps[(horizons, frac)]
            ax.plot(x, [v + 0.0 * k for v in u], lw=1, label=f"t = {frac * lf:.2f} s")
        ax.axvline(lf, color="k", ls=":", lw=1)
        ax.set_title(f"{'DH-PD' if horizons == 'dual' else 'traditional variable horizon'}: "
                     "spacing ×10 at the dotted line")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("u [m]")
        ax.legend(fontsize=7)
        ax.set_ylim(-2.5e-4, 2.1e-3)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "reflection_waves.png"), dpi=110)
    fig, ax = plt.subplots(figsize=(6, 4))
    for ratio, marker in ((2, "o"), (10, "s")):
        for horizons, color in (("dual", "C0"), ("traditional", "C3"), ("constant", "C2")):
            sel = [r for r in rows if r["ratio"] == ratio and r["horizons"] == horizons]
            ax.semilogy([r["width"] for r in sel], [r["reflection_percent"] for r in sel],
                        marker=marker, color=color, ls="-" if ratio == 10 else "--",
                        label=f"{horizons}, ratio {ratio}")
    ax.axhline(3.17, color="k", ls=":", lw=1, label="000: < 3.17 %")
    ax.set_xlabel("pulse width [m] (coarse horizon: 0.0105 m × ratio)")
    ax.set_ylabel("reflected amplitude [% of incident]")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "reflection.png"), dpi=110)


# ---------------------------------------------------------------- wave speed
def peak_time(out, column, before):
    """Time of the first pulse's peak at a probe (samples up to `before` s)."""
    with open(os.path.join(out, "probes.csv")) as f:
        rows = list(csv.DictReader(f))
    t = [float(r["time"]) for r in rows]
    y = [abs(float(r[column])) for r in rows]
    k = max((i for i in range(1, len(y) - 1) if t[i] < before), key=lambda i: y[i])
    denom = y[k - 1] - 2 * y[k] + y[k + 1]
    return t[k] + 0.5 * (t[k + 1] - t[k]) * (y[k - 1] - y[k + 1]) / denom, (t, y)


def waves():
    rows = []
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    # 1D bar: E = 4, rho = 1 -> c = 2.
    for width in (0.05, 0.1, 0.2):
        text = f"""# Wave speed in a 1D bar: E = 4, rho = 1, c = sqrt(E/rho) = 2 m/s; Gaussian
# pulse of width {width} m at x = 0.5; probes at 1.0, 1.5, 2.0.
[model]
dimension = "1d"
[materials.m]
youngs_modulus = 4.0
density = 1.0
[[regions]]
material = "m"
spacing = 0.005
box = {{ min = [0.0], max = [3.0] }}
[[initial_conditions]]
gaussian = {{ center = [0.5], width = {width}, amplitude = [1e-6] }}
[dynamics]
end_time = 0.9
[output]
probes = [ {{ name = "a", at = [1.0025] }}, {{ name = "b", at = [1.5025] }}, {{ name = "c", at = [2.0025] }} ]
"""
        out = run(f"wave_bar_w{width}", text, keep=(width == 0.1))
        times = []
        for probe, x in (("a", 1.0025), ("b", 1.5025), ("c", 2.0025)):
            tp, (t, y) = peak_time(out, f"{probe}_ux", (x - 0.5) / 2.0 + 0.2)
            times.append((x, tp))
            if width == 0.1:
                axes[0].plot(t, y, label=f"probe at x = {x:.4f} m")
        # Speed from the slope of arrival time against distance (start-up free).
        (x0, t0), (_, _), (x2, t2) = times
        c = (x2 - x0) / (t2 - t0)
        rows.append(dict(case="1d_bar", width=width, delta=0.015, reference=2.0, measured=c,
                         error_percent=100 * (c / 2.0 - 1)))
        print(rows[-1])
    axes[0].set_title("1D bar, pulse width 0.1 m: |u| at three probes")
    axes[0].set_xlabel("t [s]")
    axes[0].legend(fontsize=8)
    # 2D plane-stress plate, plane pulse along x: c_P = sqrt(E / (rho (1 - nu^2))), nu = 1/3.
    cp = math.sqrt(1.0 / (1.0 - 1.0 / 9.0))
    for width in (0.03, 0.06):
        text = f"""# P-wave speed in a 2D plane-stress plate (bond-based, nu = 1/3): E = rho = 1,
# c_P = sqrt(E/(rho (1 - nu^2))) = {cp:.6f} m/s; plane Gaussian pulse (u_x) of width
# {width} m at x = 0.15; probes on the centre line (free edges 0.3 m away: their
# waves reach it after 0.49 s, after the run).
[model]
dimension = "plane_stress"
[materials.m]
youngs_modulus = 1.0
density = 1.0
[[regions]]
material = "m"
spacing = 0.0025
box = {{ min = [0.0, 0.0], max = [0.6, 0.6] }}
[[initial_conditions]]
gaussian = {{ center = [0.15], width = {width}, amplitude = [1e-6, 0.0] }}
[dynamics]
end_time = 0.33
[output]
vtu = false
points_csv = false
probes = [ {{ name = "a", at = [0.25125, 0.30125] }}, {{ name = "b", at = [0.35125, 0.30125] }}, {{ name = "c", at = [0.45125, 0.30125] }} ]
"""
        out = run(f"wave_plate_w{width}", text, keep=(width == 0.06))
        times = []
        for probe, x in (("a", 0.25125), ("b", 0.35125), ("c", 0.45125)):
            tp, (t, y) = peak_time(out, f"{probe}_ux", 1.0)
            times.append((x, tp))
            if width == 0.06:
                axes[1].plot(t, y, label=f"probe at x = {x:.3f} m")
        (x0, t0), _, (x2, t2) = times
        c = (x2 - x0) / (t2 - t0)
        rows.append(dict(case="2d_plane_stress_plate", width=width, delta=0.0075375,
                         reference=cp, measured=c, error_percent=100 * (c / cp - 1)))
        print(rows[-1])
    axes[1].set_title("plane-stress plate, plane pulse 0.06 m: |u_x|")
    axes[1].set_xlabel("t [s]")
    axes[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "wave_speed.png"), dpi=110)
    with open(os.path.join(RESULTS, "wave_speed.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


# ---------------------------------------------------------------- relaxation
def relaxation():
    rows = []
    for model, nu in (("bond_based", ""), ("shear", "poisson_ratio = 0.3\n")):
        for spacing in (0.02, 0.01):
            body = f"""[model]
dimension = "plane_stress"
kind = "{model}"
[materials.m]
youngs_modulus = 3.0e10
{nu}[[regions]]
material = "m"
spacing = {spacing}
box = {{ min = [0.0, 0.0], max = [1.0, 0.5] }}
[[holes]]
center = [0.5, 0.25]
radius = 0.1
[[boundary]]
name = "left"
box = {{ min = [0.0, 0.0], max = [{3 * spacing}, 0.5] }}
displacement = {{ x = 0.0, y = 0.0 }}
[[loads]]
name = "pull"
kind = "traction"
face = "+x"
value = [1.0e6, 0.0]
[output]
points_csv = true
vtu = false
"""
            tag = f"{model}_h{spacing}"
            static = run(f"hole_static_{tag}", "# Plate with a hole, implicit solve.\n" + body,
                         keep=(spacing == 0.01))
            results = {}
            for kernel in ("linearised", "nonlinear"):
                text = (f"# Plate with a hole by adaptive dynamic relaxation ({kernel} kernel).\n"
                        + body + f"[dynamics]\nmethod = \"relaxation\"\nkernel = \"{kernel}\"\n"
                        "steps = 2000000\ntolerance = 1e-10\nrecord_every = 1000\n")
                results[kernel] = run(f"hole_relaxation_{kernel}_{tag}", text,
                                      keep=(spacing == 0.01))
            ps = points(static)
            umax = max(max(abs(float(p["u_x"])), abs(float(p["u_y"]))) for p in ps)
            with open(os.path.join(static, "summary.json")) as f:
                st = json.load(f)
            t_static = st["total_seconds"] if "total_seconds" in st else float("nan")
            for kernel, out in results.items():
                pr = points(out)
                diff = max(max(abs(float(a["u_x"]) - float(b["u_x"])),
                               abs(float(a["u_y"]) - float(b["u_y"]))) for a, b in zip(ps, pr))
                s = summary(out)
                rows.append(dict(model=model, spacing=spacing, points=s["points"], kernel=kernel,
                                 steps=s["steps"], outcome=s["outcome"]["kind"],
                                 max_diff_relative=diff / umax,
                                 relaxation_seconds=s["total_seconds"],
                                 implicit_seconds=t_static,
                                 ratio=s["total_seconds"] / t_static))
                print(rows[-1])
    with open(os.path.join(RESULTS, "relaxation.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


# ---------------------------------------------------------------- throughput
def throughput(repeats=9):
    """Time per step on the Peridigm comparison box with both bond sets: dhpd's
    default (overlap partial volumes, bonds to delta + dx/2) and
    volume_correction = "none" (bonds to delta, Peridigm's bond set). The two are
    run alternately (paired), one and two threads; medians."""
    path = os.path.join(SCENES, "throughput_box_3d.toml")
    text = open(path).read()
    none = text.replace('name = "throughput_box_3d"', 'name = "throughput_box_3d_none"').replace(
        "horizon_factor = 3.015\n", 'horizon_factor = 3.015\nvolume_correction = "none"\n')
    none_path = os.path.join(SCENES, "throughput_box_3d_none.toml")
    with open(none_path, "w") as f:
        f.write(none)
    rows = []
    for threads in (1, 2):
        samples = {"default": [], "none": []}
        for _ in range(repeats):
            for bonds, scene in (("default", path), ("none", none_path)):
                env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
                out = os.path.join(WORK, f"tp{threads}_{bonds}")
                subprocess.run([DHPD, "run", scene, "--out", out], check=True, env=env,
                               stdout=subprocess.DEVNULL)
                s = summary(out)
                samples[bonds].append((s["bond_updates_per_second"], s["timings"]["integration"],
                                       s["timings"]["forces"], s["bonds"], s["steps"]))
        for bonds, x in samples.items():
            steps = x[0][4]
            rows.append(dict(threads=threads, bond_set=bonds, directed_bonds=x[0][3], steps=steps,
                             median_step_ms=1e3 * statistics.median(v[1] for v in x) / steps,
                             fastest_step_ms=1e3 * min(v[1] for v in x) / steps,
                             median_bond_updates_per_second=statistics.median(v[0] for v in x),
                             force_share=statistics.median(v[2] / v[1] for v in x),
                             runs=repeats))
            print(rows[-1])
    with open(os.path.join(RESULTS, "throughput.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    # One core, each vector path of the force loop (DHPD_SIMD narrows the choice;
    # a path the CPU lacks falls back to the widest it has, named in `kernel`).
    paths = []
    for simd in ("baseline", "avx2", "avx512"):
        samples = []
        for _ in range(repeats):
            env = dict(os.environ, RAYON_NUM_THREADS="1", DHPD_SIMD=simd)
            out = os.path.join(WORK, f"tp_{simd}")
            subprocess.run([DHPD, "run", path, "--out", out], check=True, env=env,
                           stdout=subprocess.DEVNULL)
            s = summary(out)
            samples.append((s["bond_updates_per_second"], s["kernel"]))
        paths.append(dict(requested=simd, kernel=samples[0][1], runs=repeats,
                          median_bond_updates_per_second=statistics.median(x[0] for x in samples)))
        print(paths[-1])
    with open(os.path.join(RESULTS, "throughput_paths.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(paths[0]))
        w.writeheader()
        w.writerows(paths)


# ---------------------------------------------------------------- 2D wave plate, refined corner
def corner_scene(layout, horizons="dual", end_time=0.04):
    """001 Sec. 6.1: plate 0.1 x 0.04 m, E = rho = 1, nu = 0 (shear model, plane
    stress), spacing 1e-3 m with the corner [0.06, 0.1] x [0.02, 0.04] at 5e-4 m
    (layout "corner"), or uniform 1e-3 / 5e-4 ("coarse" / "fine"); Gaussian
    initial displacement at (0.04, 0.02)."""
    coarse, fine = 1e-3, 5e-4
    if layout == "corner":
        regions = [((0.0, 0.0), (0.06, 0.04), coarse), ((0.06, 0.0), (0.1, 0.02), coarse),
                   ((0.06, 0.02), (0.1, 0.04), fine)]
    else:
        h = coarse if layout == "coarse" else fine
        regions = [((0.0, 0.0), (0.1, 0.04), h)]
    text = f"""# 2D wave plate with a refined corner (001 Sec. 6.1): shear model, plane stress,
# E = rho = 1, nu = 0, layout "{layout}", horizons "{horizons}".
[model]
dimension = "plane_stress"
kind = "shear"
horizons = "{horizons}"
[materials.m]
youngs_modulus = 1.0
poisson_ratio = 0.0
density = 1.0
"""
    for lo, hi, h in regions:
        text += f"""[[regions]]
material = "m"
spacing = {h!r}
box = {{ min = [{lo[0]!r}, {lo[1]!r}], max = [{hi[0]!r}, {hi[1]!r}] }}
"""
    text += f"""[[initial_conditions]]
gaussian = {{ center = [0.04, 0.02], width = 0.004, amplitude = [1e-6, 1e-6] }}
[dynamics]
end_time = {end_time!r}
time_step = 1.0e-4
record_every = 100000
[output]
vtu = true
"""
    return text


def corner():
    """Reflection at the spacing jump: the refined run minus the uniform coarse
    run, on the coarse points outside the corner, after the wave has reached
    the corner and come back (t = 0.04 s, c = 1 m/s)."""
    rows = []
    for t_end in (0.03, 0.04):
        outs = {}
        for layout, horizons in (("corner", "dual"), ("corner", "constant"), ("coarse", "dual")):
            outs[(layout, horizons)] = run(f"wave_plate_{layout}_{horizons}_t{t_end}",
                                           corner_scene(layout, horizons, t_end),
                                           keep=(t_end == 0.04))
        ref = {(round(float(p["x"]), 9), round(float(p["y"]), 9)): p
                 for p in points(outs[("coarse", "dual")])}
        for key in (("corner", "dual"), ("corner", "constant")):
            worst, amp = 0.0, 0.0
            for p in points(outs[key]):
                x, y = float(p["x"]), float(p["y"])
                q = ref.get((round(x, 9), round(y, 9)))
                if q is None:
                    continue  # a fine point
                u = math.hypot(float(p["u_x"]), float(p["u_y"]))
                du = math.hypot(float(p["u_x"]) - float(q["u_x"]), float(p["u_y"]) - float(q["u_y"]))
                worst = max(worst, du)
                amp = max(amp, math.hypot(float(q["u_x"]), float(q["u_y"])))
            s = summary(outs[key])
            rows.append(dict(time=t_end, layout=key[0], horizons=key[1], points=s["points"],
                             steps=s["steps"],
                             max_difference_to_uniform=worst, max_wave_amplitude=amp,
                             relative_percent=100 * worst / amp,
                             balance_error=s["max_balance_error"], seconds=s["total_seconds"]))
            print(rows[-1])
    with open(os.path.join(RESULTS, "wave_plate_corner.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(15, 2.9))
    for ax, key in zip(axes, (("coarse", "dual"), ("corner", "dual"), ("corner", "constant"))):
        pts = points(outs[key])
        x = [float(p["x"]) for p in pts]
        y = [float(p["y"]) for p in pts]
        m = [math.hypot(float(p["u_x"]), float(p["u_y"])) for p in pts]
        sc = ax.scatter(x, y, c=m, s=1.5, cmap="viridis", vmin=0, vmax=max(m))
        ax.set_aspect("equal")
        ax.set_title(f"{key[0]} spacing, {key[1]} horizons: |u| at t = 0.04 s", fontsize=9)
        ax.plot([0.06, 0.06, 0.1], [0.04, 0.02, 0.02], "w:", lw=1)
    fig.colorbar(sc, ax=axes, shrink=0.8)
    fig.savefig(os.path.join(HERE, "wave_plate_corner.png"), dpi=110)


# ---------------------------------------------------------------- shear model, dynamic mode I
def shear_fracture():
    """A coarse mode I case after 001 Sec. 6.4, in 2D: plate 0.5 x 0.2 m, edge
    crack 0.3 m along the mid-height from the left, E = 30 GPa, nu = 1/3,
    rho = 2400, G0 = 200 J/m^2, the top and bottom edges of the cracked part
    (x < 0.1 m) pulled apart at 1 m/s: the crack mouth opens."""
    rows = []
    for model in ("shear", "bond_based"):
        nu = "poisson_ratio = 0.3333333333333333\n" if model == "shear" else ""
        criterion = 'shear_criterion = "deviatoric"\n' if model == "shear" else ""
        text = f"""# Dynamic mode I fracture (after 001 Sec. 6.4, 2D plane stress, coarse):
# {model} model, plate 0.5 x 0.2 m, edge crack 0.3 m, E = 30 GPa, nu = 1/3,
# rho = 2400, G0 = 200 J/m^2, three layers of the top and bottom edges at x < 0.1 m
# moved at +-1 m/s (the crack mouth opens).
[model]
dimension = "plane_stress"
kind = "{model}"
[materials.concrete]
youngs_modulus = 3.0e10
{nu}density = 2400.0
fracture_energy = 200.0
[[regions]]
material = "concrete"
spacing = 5e-3
box = {{ min = [0.0, 0.0], max = [0.5, 0.2] }}
[[cracks]]
from = [0.0, 0.1]
to = [0.3, 0.1]
[[boundary]]
name = "bottom"
box = {{ min = [0.0, 0.0], max = [0.1, 0.015] }}
velocity = {{ y = -1.0 }}
[[boundary]]
name = "top"
box = {{ min = [0.0, 0.185], max = [0.1, 0.2] }}
velocity = {{ y = 1.0 }}
[fracture]
{criterion}calibration = "continuum"  # the numbers of this report (issue 21: to be re-measured with the default)
no_fail = [ {{ box = {{ min = [0.0, 0.0], max = [0.1, 0.03] }} }}, {{ box = {{ min = [0.0, 0.17], max = [0.1, 0.2] }} }} ]
[dynamics]
end_time = 1e-3
record_every = 20
[output]
every = 40
"""
        out = run(f"mode_one_dynamic_{model}", text)
        pts = points(out)
        cracked = [(float(p["x"]), float(p["y"])) for p in pts
                   if float(p["damage"]) >= 0.35 and float(p["x"]) > 0.305]
        tip = max((c[0] for c in cracked), default=0.3)
        off = max((abs(c[1] - 0.1) for c in cracked), default=0.0)
        s = summary(out)
        rows.append(dict(model=model, points=s["points"], steps=s["steps"],
                         bonds_broken=s["bonds_broken"], crack_tip_x=tip,
                         largest_offset_from_crack_line=off,
                         balance_error=s["max_balance_error"], seconds=s["total_seconds"]))
        print(rows[-1])
        if model == "shear":
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            fig, ax = plt.subplots(figsize=(7, 3))
            sc = ax.scatter([float(p["x"]) for p in pts], [float(p["y"]) for p in pts],
                            c=[float(p["damage"]) for p in pts], s=3, cmap="inferno_r",
                            vmin=0, vmax=1)
            ax.set_aspect("equal")
            ax.set_title("shear model, dynamic mode I: damage at t = 1 ms", fontsize=9)
            fig.colorbar(sc, ax=ax, shrink=0.8)
            fig.tight_layout()
            fig.savefig(os.path.join(HERE, "mode_one_shear.png"), dpi=110)
    with open(os.path.join(RESULTS, "mode_one_dynamic.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


# ---------------------------------------------------------------- dynamic fracture
def read_vtu(path):
    """Points (x, y) and the damage of a dhpd VTU file (ASCII or binary)."""
    import base64
    import re
    import struct
    text = open(path).read()
    arrays = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)"[^>]*format="(\w+)">\n(.*?)</DataArray>',
                         text, re.S):
        kind, name, fmt, body = m.groups()
        if fmt == "ascii":
            values = [float(v) for v in body.split()]
        else:
            raw = base64.b64decode(body.strip())
            count = struct.unpack("<I", raw[:4])[0]
            code = {"Float64": "d", "Int32": "i", "Int64": "q", "UInt8": "B"}[kind]
            size = struct.calcsize(code)
            values = list(struct.unpack("<%d%s" % (count // size, code), raw[4:4 + count]))
        arrays[name] = values
    pts = arrays["points"]
    xy = [(pts[3 * k], pts[3 * k + 1]) for k in range(len(pts) // 3)]
    return xy, arrays["damage"]


def series(out):
    """(time, file) of the snapshots of a run."""
    import re
    text = open(os.path.join(out, "series.pvd")).read()
    return [(float(t), os.path.join(out, f))
            for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', text)]


def principal_angle(points):
    """Angle (degrees from +x, in [0, 180)) of the principal axis of a point set."""
    n = len(points)
    mx = sum(p[0] for p in points) / n
    my = sum(p[1] for p in points) / n
    sxx = sum((p[0] - mx) ** 2 for p in points)
    syy = sum((p[1] - my) ** 2 for p in points)
    sxy = sum((p[0] - mx) * (p[1] - my) for p in points)
    return math.degrees(0.5 * math.atan2(2 * sxy, sxx - syy)) % 180.0


def kalthoff_scene(name, regions, g0=6.9e4, end_time=90e-6, calibration="dissipation",
                   tip_spacing=1e-3):
    text = f"""# Kalthoff-Winkler (000 Sec. 6): plate 0.2 x 0.1 m, notches 50 mm long from the
# left edge at y = 25 and 75 mm, the left edge between them hit at 22 m/s (three
# point layers), E = 190 GPa, rho = 7800, nu = 1/4 (bond-based, plane strain),
# G0 = {g0:g} J/m^2 (000 Sec. 6: 6.9e4), delta = 3.015 dx; {name};
# fracture.calibration = "{calibration}".
[model]
dimension = "plane_strain"
[materials.steel]
youngs_modulus = 1.9e11
density = 7800.0
fracture_energy = {g0!r}
"""
    for lo, hi, h in regions:
        text += f"""[[regions]]
material = "steel"
spacing = {h!r}
box = {{ min = [{lo[0]!r}, {lo[1]!r}], max = [{hi[0]!r}, {hi[1]!r}] }}
"""
    h0 = regions[0][2]
    text += f"""[[cracks]]
from = [0.0, 0.025]
to = [0.05, 0.025]
[[cracks]]
from = [0.0, 0.075]
to = [0.05, 0.075]
[[boundary]]
name = "impactor"
box = {{ min = [0.0, 0.025], max = [{3 * h0!r}, 0.075] }}
velocity = {{ x = 22.0 }}
[fracture]
"""
    if calibration != "dissipation":
        text += f'calibration = "{calibration}"\n'
    text += f"""no_fail = [ {{ box = {{ min = [0.0, 0.025], max = [{3 * h0!r}, 0.075] }} }} ]
[dynamics]
end_time = {end_time!r}
record_every = 1
[output]
every = 10
"""
    # Probes on the points around the upper notch tip (0.05, 0.075): the first step
    # at which one of them has damage is the first broken tip bond.
    h = tip_spacing
    for i, dx in enumerate((-0.5, 0.5, 1.5)):
        for j, dy in enumerate((-0.5, 0.5)):
            text += f"""[[output.probes]]
name = "tip_{i}{j}"
at = [{0.05 + dx * h!r}, {0.075 + dy * h!r}]
"""
    return text


def first_break(out):
    """Time of the first broken bond anywhere (history.csv, every step), and of
    the first broken bond of a point next to the upper notch tip (probes.csv)."""
    anywhere = tip = float("nan")
    with open(os.path.join(out, "history.csv")) as f:
        for row in csv.DictReader(f):
            if int(row["broken_bonds"]) > 0:
                anywhere = float(row["time"])
                break
    with open(os.path.join(out, "probes.csv")) as f:
        for row in csv.DictReader(f):
            if any(float(v) > 0 for k, v in row.items() if k.endswith("_damage")):
                tip = float(row["time"])
                break
    return anywhere, tip


def crack_history(out, tip, side, damage=0.35):
    """Crack-tip distance from the notch tip against time, from the snapshots:
    the farthest point with at least this damage ahead of the notch tip
    (x beyond it) on one side (+1 upper, −1 lower)."""
    rows = []
    for t, f in series(out):
        xy, phi = read_vtu(f)
        cracked = [p for p, d in zip(xy, phi) if d >= damage and p[0] > tip[0]
                   and side * (p[1] - 0.05) > 0]
        reach = max((math.hypot(p[0] - tip[0], p[1] - tip[1]) for p in cracked), default=0.0)
        rows.append((t, reach))
    return rows


def speed(history, lo=0.005):
    """Mean crack speed while it grows: from the first snapshot with a crack
    longer than `lo` to the first one at its final length (NaN: it never
    grew beyond `lo`)."""
    final = max((r for _, r in history), default=0.0)
    grown = [(t, r) for t, r in history if r > lo]
    if len(grown) < 2:
        return float("nan")
    end = next(k for k, (_, r) in enumerate(grown) if r >= final)
    (t0, r0), (t1, r1) = grown[0], grown[max(end, 1)]
    return (r1 - r0) / (t1 - t0) if t1 > t0 else float("nan")


def kalthoff():
    mu = 1.9e11 / 2.5
    cs = math.sqrt(mu / 7800.0)
    cr = 0.9194 * cs
    cases = [
        ("uniform 1 mm", "kalthoff_uniform_1mm", [((0.0, 0.0), (0.2, 0.1), 1e-3)]),
        ("uniform 0.5 mm", "kalthoff_uniform_0.5mm", [((0.0, 0.0), (0.2, 0.1), 5e-4)]),
        ("0.5 mm band x in [0.04, 0.14] m, 1 mm elsewhere (DH-PD)", "kalthoff_band",
         [((0.0, 0.0), (0.04, 0.1), 1e-3), ((0.04, 0.0), (0.14, 0.1), 5e-4),
          ((0.14, 0.0), (0.2, 0.1), 1e-3)]),
    ]
    runs = [(6.9e4, "dissipation"), (6.9e4, "continuum"), (6.9e3, "dissipation"),
            (6.9e3, "continuum")]
    rows = []
    histories = {}
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(runs), len(cases), figsize=(5 * len(cases), 2.8 * len(runs)))
    for (g0, calibration), ax_row in zip(runs, axes):
        for ax, (label, name, regions) in zip(ax_row, cases):
            scene = name + ("" if g0 == 6.9e4 else f"_g{g0:g}")
            scene += "" if calibration == "dissipation" else "_continuum"
            out = run(scene, kalthoff_scene(label, regions, g0, calibration=calibration,
                                            tip_spacing=min(h for _, _, h in regions)))
            s = summary(out)
            pts = points(out)
            anywhere, at_tip = first_break(out)
            for side, tip in ((1, (0.05, 0.075)), (-1, (0.05, 0.025))):
                cracked = [(float(p["x"]), float(p["y"])) for p in pts
                           if float(p["damage"]) >= 0.35 and float(p["x"]) > tip[0] + 2e-3
                           and side * (float(p["y"]) - 0.05) > 0
                           and 0.002 < float(p["y"]) < 0.098 and float(p["x"]) < 0.198]
                hist = crack_history(out, tip, side)
                final = hist[-1][1] if hist else 0.0
                # The angle of a crack that ran (longer than 5 mm), from the notch
                # direction (+x), as an acute angle.
                angle = principal_angle(cracked) if final > 0.005 and len(cracked) > 3 \
                    else float("nan")
                angle = min(angle, 180.0 - angle)
                v = speed(hist)
                histories[(g0, calibration, label, side)] = hist
                rows.append(dict(g0=g0, calibration=calibration, case=label,
                                 crack="upper" if side > 0 else "lower",
                                 points=s["points"], steps=s["steps"],
                                 bonds_broken=s["bonds_broken"],
                                 first_broken_bond_us=anywhere * 1e6,
                                 first_tip_bond_us=at_tip * 1e6,
                                 damage_035_us=next((t for t, r in hist if r > 0),
                                                    float("nan")) * 1e6,
                                 final_length_mm=final * 1e3, angle_deg=angle,
                                 crack_speed=v, speed_over_rayleigh=v / cr,
                                 seconds=s["total_seconds"]))
                print(rows[-1])
            ax.scatter([float(p["x"]) for p in pts], [float(p["y"]) for p in pts],
                       c=[float(p["damage"]) for p in pts], s=0.3, cmap="inferno_r",
                       vmin=0, vmax=1)
            ax.set_aspect("equal")
            ax.set_title(f"G0 = {g0:g}, {calibration}, {label}: damage at 90 µs", fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "kalthoff.png"), dpi=120)
    fig, ax = plt.subplots(figsize=(6, 4))
    for (g0, calibration, label, side), hist in histories.items():
        if side > 0:
            ax.plot([t * 1e6 for t, _ in hist], [r * 1e3 for _, r in hist],
                    label=f"G0 = {g0:g}, {calibration}, {label[:14]}")
    ax.set_xlabel("time [µs]")
    ax.set_ylabel("crack reach beyond the notch tip [mm] (damage ≥ 0.35)")
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "kalthoff_tip.png"), dpi=120)
    with open(os.path.join(RESULTS, "kalthoff.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    # Where propagation starts: the 1 mm plate (dissipation calibration) at
    # fractions of the paper's G0.
    label, name, regions = cases[0]
    threshold = []
    for fraction in (2, 3, 4):
        g0 = 6.9e4 / fraction
        out = run(f"{name}_g0_over_{fraction}", kalthoff_scene(label, regions, g0))
        hist = crack_history(out, (0.05, 0.075), 1)
        threshold.append(dict(g0=g0, first_tip_bond_us=first_break(out)[1] * 1e6,
                              final_length_mm=hist[-1][1] * 1e3,
                              crack_speed=speed(hist)))
        print(threshold[-1])
    with open(os.path.join(RESULTS, "kalthoff_threshold.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(threshold[0]))
        w.writeheader()
        w.writerows(threshold)


def branching():
    """Ha & Bobaru (2010): glass plate 0.1 x 0.04 m, notch 50 mm from the left
    edge at mid-height, E = 72 GPa, rho = 2440, G0 = 3.8 J/m^2, delta = 1 mm
    (spacing 1/3 mm, m = 3), 2 MPa applied suddenly on the top and bottom edges,
    43 us, bond-based plane stress."""
    h = 1.0 / 3000.0
    text = f"""# Dynamic crack branching (Ha & Bobaru 2010): glass 0.1 x 0.04 m, notch 50 mm at
# mid-height, E = 72 GPa, rho = 2440, G0 = 3.8 J/m^2, delta = 1 mm (spacing 1/3 mm,
# m = 3), 2 MPa on the top and bottom edges from t = 0, bond-based plane stress.
[model]
dimension = "plane_stress"
[discretization]
horizon_factor = 3.0
[materials.glass]
youngs_modulus = 7.2e10
density = 2440.0
fracture_energy = 3.8
[[regions]]
material = "glass"
spacing = {h!r}
box = {{ min = [0.0, 0.0], max = [0.1, 0.04] }}
[[cracks]]
from = [0.0, 0.02]
to = [0.05, 0.02]
[[loads]]
name = "top"
kind = "traction"
face = "+y"
value = [0.0, 2.0e6]
[[loads]]
name = "bottom"
kind = "traction"
face = "-y"
value = [0.0, -2.0e6]
[fracture]
calibration = "continuum"  # the numbers of this report (issue 21: to be re-measured with the default)
[dynamics]
end_time = 43e-6
record_every = 50
[output]
every = 25
"""
    out = run("branching_glass", text)
    s = summary(out)
    cr = 0.9194 * math.sqrt(7.2e10 / (2 * (1 + 1 / 3)) / 2440.0)
    hist = []
    branch = None
    for t, f in series(out):
        xy, phi = read_vtu(f)
        cracked = [p for p, d in zip(xy, phi) if d >= 0.35 and p[0] > 0.0505]
        tip = max((p[0] for p in cracked), default=0.05)
        hist.append((t, tip))
        if branch is None and cracked:
            # A branch: at some x the damaged points split into two groups in y
            # more than 2 horizons apart.
            columns = {}
            for p in cracked:
                columns.setdefault(round(p[0] / h), []).append(p[1])
            for k in sorted(columns):
                ys = sorted(columns[k])
                if any(b - a > 2e-3 for a, b in zip(ys, ys[1:])):
                    branch = (t, k * h)
                    break
    speeds = [((t0 + t1) / 2, (x1 - x0) / (t1 - t0))
              for (t0, x0), (t1, x1) in zip(hist, hist[1:]) if t1 > t0]
    top = max((v for _, v in speeds), default=float("nan"))
    rows = [dict(points=s["points"], steps=s["steps"], time_step=s["time_step"],
                 branch_time=branch[0] if branch else float("nan"),
                 branch_x=branch[1] if branch else float("nan"),
                 max_tip_speed=top, rayleigh=cr, max_speed_over_rayleigh=top / cr,
                 final_tip_x=hist[-1][1], seconds=s["total_seconds"])]
    print(rows[0])
    with open(os.path.join(RESULTS, "branching.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(RESULTS, "branching_tip.csv"), "w", newline="") as f:
        f.write("time,tip_x\n")
        for t, x in hist:
            f.write(f"{t!r},{x!r}\n")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    pts = points(out)
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 3.2))
    a.scatter([float(p["x"]) for p in pts], [float(p["y"]) for p in pts],
              c=[float(p["damage"]) for p in pts], s=0.2, cmap="inferno_r", vmin=0, vmax=1)
    a.set_aspect("equal")
    a.set_title("glass plate, 2 MPa: damage at 43 µs", fontsize=9)
    b.plot([t * 1e6 for t, _ in speeds], [v for _, v in speeds], "o-", ms=3)
    b.axhline(cr, color="k", ls=":", label="Rayleigh speed")
    b.set_xlabel("t [µs]")
    b.set_ylabel("crack-tip speed [m/s] (x of the farthest damaged point)")
    b.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "branching.png"), dpi=120)


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "all"
    for name, fn in (("reflection", reflection), ("waves", waves),
                     ("relaxation", relaxation), ("throughput", throughput),
                     ("corner", corner), ("shear_fracture", shear_fracture),
                     ("kalthoff", kalthoff), ("branching", branching)):
        if what in (name, "all"):
            fn()
