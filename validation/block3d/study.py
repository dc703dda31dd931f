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
             "[dynamics]", ("end_time = 4e-4                  # the crack reaches x = 0.5 m at 275 us (a 1 ms run stopped at 362 us)"
                            if (mode == 2 and h == 0.005) else "end_time = 1e-3"), f"time_step = {DT:g}", "record_every = 2",
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



# ---------------------------------------------------------------- analysis
VTK_T = {"Float64": "<f8", "Int64": "<i8", "UInt8": "u1", "Int32": "<i4"}
D_TH = 0.2   # a clean planar cut leaves 0.39 on the rows beside it (m = 3): the front is at half of it


def read_vtu(path, names=("points", "damage")):
    s = open(path, "rb").read().decode()
    out = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)"([^>]*)>\s*([^<]*)</DataArray>', s):
        t, n, attr, body = m.groups()
        if n not in names:
            continue
        raw = base64.b64decode(body.strip())
        nb = struct.unpack("<I", raw[:4])[0]
        a = np.frombuffer(raw[4:4 + nb], dtype=VTK_T[t])
        nc = re.search(r'NumberOfComponents="(\d+)"', attr)
        out[n] = a.reshape(-1, int(nc.group(1))) if nc else a
    return out


def snapshots(d):
    pvd = open(os.path.join(d, "series.pvd")).read()
    return [(float(t), os.path.join(d, f)) for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', pvd)]


def run_dir(name):
    d = os.path.join(OUT, name)
    if os.path.isdir(d):
        return d
    part = glob.glob(os.path.join(OUT, f".{name}.partial-*"))
    return part[0] if part else None


def front_series(name, h):
    """Per snapshot: crack front per z layer = largest x of a point in the two rows beside the
    crack plane with damage >= D_TH (0.3 m, the initial tip, when none); the damaged points'
    extent off the plane."""
    d = run_dir(name)
    rows = []
    keep = {}
    for t, f in snapshots(d) if os.path.exists(os.path.join(d, "series.pvd")) else \
            [(int(re.search(r"(\d+)\.vtu", f).group(1)) * DT, f) for f in sorted(glob.glob(os.path.join(d, "step_*.vtu")))]:
        v = read_vtu(f)
        p, D = v["points"], v["damage"]
        band = np.abs(p[:, 1] - H / 2) < h
        zs = np.unique(np.round(p[:, 2], 9))
        fr = []
        for z in zs:
            sel = band & (np.abs(p[:, 2] - z) < 1e-9) & (D >= D_TH)
            fr.append(max(A0, p[sel, 0].max()) if sel.any() else A0)
        fr = np.array(fr)
        ahead = (p[:, 0] > A0) & (D > 0)
        dam = D >= D_TH
        off = dam & ~band
        rows.append(dict(t=t, front_mean=fr.mean(), front_min=fr.min(), front_max=fr.max(),
                         n_damaged_ahead=int(ahead.sum()), n_dam=int(dam.sum()), n_dam_off_plane=int(off.sum()),
                         off_plane_ymin=float(p[off, 1].min()) if off.any() else np.nan,
                         off_plane_ymax=float(p[off, 1].max()) if off.any() else np.nan,
                         max_damage=float(D.max())))
        keep[t] = (p, D)
    return rows, keep


def probe_arrivals(name, h):
    """First time each probe (first row above the plane, 3 depths) has damage > 0 and >= D_TH."""
    f = os.path.join(run_dir(name), "probes.csv")
    if not os.path.exists(f):
        return None
    import csv
    with open(f) as fh:
        r = list(csv.reader(fh))
    head, data = r[0], np.array(r[1:], dtype=float)
    t = data[:, head.index("time")]
    out = {}
    for j, c in enumerate(head):
        m = re.match(r"(p\d{3}_z\w+?)_damage$", c) or re.match(r"(p\d{3}_z\w+?)\.damage$", c)
        if not m:
            continue
        k = int(m.group(1)[1:4]); zn = m.group(1).split("_", 1)[1]
        x = A0 + h / 2 + k * h
        any_ = np.nonzero(data[:, j] > 0)[0]; th = np.nonzero(data[:, j] >= D_TH)[0]
        out[(zn, x)] = (t[any_[0]] if len(any_) else np.nan, t[th[0]] if len(th) else np.nan)
    return out


def smooth_speed(t, x, w=2):
    """Speed from the front smoothed by a centred moving average over 2w+1 snapshots."""
    xs = np.array([x[max(0, i - w):i + w + 1].mean() for i in range(len(x))])
    return np.gradient(xs, t), xs


ARR = {}


def measure(name, h):
    """Every number of the report for one run; writes results/<name>_front.csv."""
    rows, keep = front_series(name, h)
    t = np.array([r["t"] for r in rows]); xm = np.array([r["front_mean"] for r in rows])
    os.makedirs(RESULTS, exist_ok=True)
    with open(os.path.join(RESULTS, name + "_front.csv"), "w") as f:
        ks = list(rows[0])
        f.write(",".join(ks) + ",speed_smoothed\n")
        v, xs = smooth_speed(t, xm)
        for r, vv in zip(rows, v):
            f.write(",".join(f"{r[k]:.6g}" for k in ks) + f",{vv:.6g}\n")
    d = run_dir(name)
    res = dict(run=name, mode=int(name[4]), spacing_mm=h * 1000, complete=os.path.basename(d) == name)
    # initiation (a): first damage at a point ahead of the tip, probes (every 2 steps) and snapshots
    arr = probe_arrivals(name, h)
    ARR[name] = arr
    if arr:
        tip = [v[0] for (zn, x), v in arr.items() if abs(x - (A0 + h / 2)) < 1e-9]
        res["init_first_bond_probe_us"] = np.nanmin(tip) * 1e6 if np.isfinite(tip).any() else np.nan
        first_any = [v[0] for v in arr.values()]
        res["first_damage_ahead_probe_us"] = np.nanmin(first_any) * 1e6 if np.isfinite(first_any).any() else np.nan
    i = np.nonzero([r["n_damaged_ahead"] > 0 for r in rows])[0]
    res["init_first_bond_snapshot_us"] = t[i[0]] * 1e6 if len(i) else np.nan
    # initiation (b): the mean front one spacing ahead of the tip
    i = np.nonzero(xm >= A0 + h)[0]
    res["init_front_one_spacing_us"] = t[i[0]] * 1e6 if len(i) else np.nan
    # end of propagation: the front within one spacing of the far end, else the last snapshot
    j = np.nonzero(xm >= L - h)[0]
    res["front_reaches_end_us"] = t[j[0]] * 1e6 if len(j) else np.nan
    res["front_final_mean_m"] = xm[-1]; res["front_final_min_m"] = rows[-1]["front_min"]
    res["front_final_max_m"] = rows[-1]["front_max"]
    res["t_last_us"] = t[-1] * 1e6
    if len(i):
        i0 = i[0]; i1 = j[0] if len(j) else len(t) - 1
        res["mean_speed_m_s"] = (xm[i1] - xm[i0]) / (t[i1] - t[i0]) if i1 > i0 else np.nan
        v, xs = smooth_speed(t, xm)
        res["peak_speed_m_s"] = v[i0:i1 + 1].max()
        # arrests: after initiation and before the end, spans of >= 3 snapshot intervals (~49 us)
        # in which the mean front moves by at most one spacing (mean speed <= ~100 m/s)
        stops = []
        k = i0
        while k < i1:
            k2 = k
            while k2 + 1 <= i1 and xm[k2 + 1] - xm[k] <= h + 1e-9:
                k2 += 1
            if k2 - k >= 3 and k2 < i1:
                stops.append((t[k] * 1e6, t[k2] * 1e6))
            k = max(k2, k + 1)
        res["arrests_us"] = ";".join(f"{a:.0f}-{b:.0f}" for a, b in stops)
        if stops:
            moving = (xm[i1] - xm[i0]) / ((t[i1] - t[i0]) - sum((b - a) * 1e-6 for a, b in stops))
            res["mean_speed_moving_m_s"] = moving
    if arr:
        # mid-depth probes: arrival (damage >= D_TH) against x; the longest waits between neighbours
        xa = sorted((x, v[1]) for (zn, x), v in arr.items() if zn == "zmid" and np.isfinite(v[1]))
        if len(xa) > 2:
            xs_, ts_ = np.array(xa).T
            order = np.argsort(ts_)
            gaps = np.diff(ts_)
            big = np.argsort(gaps)[::-1][:3]
            res["probe_longest_waits_us"] = ";".join(f"x={xs_[b]:.4f}->{xs_[b+1]:.4f}:{ts_[b]*1e6:.0f}-{ts_[b+1]*1e6:.0f}"
                                                      for b in sorted(big) if gaps[b] > 0)
            res["probe_mid_first_us"] = ts_.min() * 1e6; res["probe_mid_last_us"] = ts_.max() * 1e6
            res["probe_mid_last_x"] = xs_[np.argmax(ts_)]
            if len(xs_) > 1 and ts_[-1] > ts_[0]:
                res["probe_mid_mean_speed_m_s"] = (xs_[-1] - xs_[0]) / (ts_[-1] - ts_[0])
    res["max_off_plane_damaged_pts"] = max(r["n_dam_off_plane"] for r in rows)
    res["off_plane_y_range_m"] = f"{np.nanmin([r['off_plane_ymin'] for r in rows]):.4g}-{np.nanmax([r['off_plane_ymax'] for r in rows]):.4g}" \
        if any(r["n_dam_off_plane"] for r in rows) else ""
    sj = os.path.join(d, "summary.json")
    if os.path.exists(sj):
        S = json.load(open(sj))
        res.update(points=S["points"], bonds=S["bonds"], steps=S["steps"], bonds_broken=S["bonds_broken"],
                   time_per_step_s=S["timings"]["integration"] / S["steps"], wall_s=S["total_seconds"],
                   setup_s=S["timings"]["setup"], max_balance_error=S["max_balance_error"],
                   external_work_J=S["final_record"]["external_work"], kinetic_J=S["final_record"]["kinetic"],
                   internal_work_J=S["final_record"]["strain"], threads=S["threads"])
    return res, rows, keep


def plot_run(name, h, res, rows, keep):
    import matplotlib; matplotlib.use("Agg"); import matplotlib.pyplot as plt
    ts = sorted(keep)
    # four times: initiation, two during growth, the last
    t0 = res.get("init_front_one_spacing_us", np.nan)
    cand = [ts[len(ts) // 4], ts[len(ts) // 2], ts[3 * len(ts) // 4], ts[-1]]
    if np.isfinite(t0):
        i0 = min(range(len(ts)), key=lambda i: abs(ts[i] * 1e6 - t0))
        step = max(1, (len(ts) - 1 - i0) // 3)
        cand = [ts[min(i0 + k * step, len(ts) - 1)] for k in range(3)] + [ts[-1]]
    fig, ax = plt.subplots(4, 2, figsize=(13, 9.5), gridspec_kw=dict(width_ratios=[1, 1]))
    ax = ax.T
    for c, tt in enumerate(cand):
        p, D = keep[tt]
        band = np.abs(p[:, 1] - H / 2) < h
        # crack plane (x-z): the larger damage of the two rows beside the plane
        nx, nz = round(L / h), round(B / h)
        img = np.zeros((nz, nx))
        ix = np.clip((p[band, 0] / h).astype(int), 0, nx - 1); iz = np.clip((p[band, 2] / h).astype(int), 0, nz - 1)
        np.maximum.at(img, (iz, ix), D[band])
        a = ax[0, c]; im = a.imshow(img, origin="lower", extent=[0, L, 0, B], vmin=0, vmax=0.6, cmap="inferno", aspect="equal")
        a.axvline(A0, color="c", lw=0.8, ls="--"); a.set_title(f"t = {tt*1e6:.0f} µs: crack plane (rows beside y = 0.1)", fontsize=9)
        a.set_xlabel("x [m]"); a.set_ylabel("z [m]")
        # side view (x-y): the largest damage over z
        ny = round(H / h)
        img2 = np.zeros((ny, nx))
        ix = np.clip((p[:, 0] / h).astype(int), 0, nx - 1); iy = np.clip((p[:, 1] / h).astype(int), 0, ny - 1)
        np.maximum.at(img2, (iy, ix), D)
        a = ax[1, c]; a.imshow(img2, origin="lower", extent=[0, L, 0, H], vmin=0, vmax=0.6, cmap="inferno", aspect="equal")
        a.plot([0, A0], [H / 2, H / 2], "c--", lw=0.8); a.set_title(f"t = {tt*1e6:.0f} µs: side view, max damage over z", fontsize=9)
        a.set_xlabel("x [m]"); a.set_ylabel("y [m]")
    fig.subplots_adjust(hspace=0.45, right=0.88)
    fig.colorbar(im, cax=fig.add_axes([0.91, 0.25, 0.015, 0.5]), label="damage")
    fig.suptitle(f"{name}: damage (initial crack x < 0.3 m at y = 0.1, dashed)")
    fig.savefig(os.path.join(HERE, f"{name}_damage.png"), dpi=80)
    plt.close(fig)


def plot_fronts(results, allrows, tag):
    import matplotlib; matplotlib.use("Agg"); import matplotlib.pyplot as plt
    names = [r["run"] for r in results]
    fig, ax = plt.subplots(2, 3, figsize=(15, 7.5), sharex=True)
    for mode in (1, 2, 3):
        P = PAPER[mode]
        for r in results:
            if r["mode"] != mode:
                continue
            rows = allrows[r["run"]]
            t = np.array([q["t"] for q in rows]) * 1e6; xm = np.array([q["front_mean"] for q in rows])
            a = ax[0, mode - 1]
            l, = a.plot(t, xm, "-o", ms=2.5, label=r["run"])
            a.fill_between(t, [q["front_min"] for q in rows], [q["front_max"] for q in rows], color=l.get_color(), alpha=0.2)
            arr = ARR.get(r["run"])
            if arr:
                for zn, mk in (("z0", "v"), ("zmid", "x"), ("z1", "^")):
                    xa = np.array([(x, v[1]) for (z, x), v in arr.items() if z == zn and np.isfinite(v[1])])
                    if len(xa):
                        a.plot(xa[:, 1] * 1e6, xa[:, 0], mk, ms=3, color=l.get_color(), alpha=0.6,
                               label=f"probe arrivals, {zn}" if r is results[0] else None)
            v, _ = smooth_speed(t * 1e-6, xm)
            ax[1, mode - 1].plot(t, v, "-", color=l.get_color(), label=r["run"])
        for a in ax[:, mode - 1]:
            a.axvline(P["init"] * 1e6, color="k", ls="--", lw=1, label=f"paper initiation {P['init']*1e6:.0f} µs")
            if mode == 1:
                a.axvspan(P["arrest"] * 1e6, P["restart"] * 1e6, color="grey", alpha=0.25, label="paper: arrest 590-630 µs")
        ax[1, mode - 1].axhline(P["speed"], color="k", ls=":", label=f"paper mean speed {P['speed']} m/s")
        ax[1, mode - 1].axhline(C_R, color="r", ls=":", lw=0.8, label=f"c_R = {C_R:.0f} m/s")
        ax[0, mode - 1].set_title(f"mode {'I' * mode if mode < 3 else 'III'}: crack front (mean over z; band min-max)")
        ax[0, mode - 1].set_ylabel("front x [m]"); ax[0, mode - 1].set_ylim(0.29, 0.51)
        ax[1, mode - 1].set_ylabel("speed [m/s] (smoothed mean front)"); ax[1, mode - 1].set_xlabel("t [µs]")
        ax[1, mode - 1].set_ylim(bottom=0)
        ax[0, mode - 1].legend(fontsize=7); ax[1, mode - 1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, f"fronts_{tag}.png"), dpi=80)
    plt.close(fig)


def analyse(names=None):
    if names is None:
        names = sorted({os.path.basename(p).lstrip(".").split(".partial")[0]
                        for p in glob.glob(os.path.join(OUT, "*mode*")) if os.path.isdir(p)})
    results, allrows = [], {}
    for n in names:
        h = int(re.search(r"_(\d+)mm_", n).group(1)) / 1000
        res, rows, keep = measure(n, h)
        plot_run(n, h, res, rows, keep)
        results.append(res); allrows[n] = rows
        print(json.dumps(res, default=float))
    keys = []
    for r in results:
        keys += [k for k in r if k not in keys]
    with open(os.path.join(RESULTS, "summary.csv"), "w") as f:
        f.write(",".join(keys) + "\n")
        for r in results:
            f.write(",".join(f"{r[k]:.6g}" if isinstance(r.get(k), (float, np.floating)) else str(r.get(k, "")) for k in keys) + "\n")
    # a markdown table of the main numbers (pasted into README.md)
    def g(r, k, fmt="{:.0f}"):
        v = r.get(k)
        return "–" if v is None or (isinstance(v, float) and not np.isfinite(v)) or v == "" else \
            (fmt.format(v) if not isinstance(v, str) else v)
    with open(os.path.join(RESULTS, "table.md"), "w") as f:
        f.write("| run | first bond ahead [µs] (probe / snapshot) | front +1 spacing [µs] | paper initiation [µs] | "
                "front at x = 0.5 [µs] | mean speed [m/s] | paper [m/s] | peak speed [m/s] | arrests [µs] | bonds broken | "
                "steps | time/step [s] | wall [s] | max balance error |\n|" + "---|" * 14 + "\n")
        for r in results:
            P = PAPER[r["mode"]]
            f.write(f"| {r['run']} | {g(r, 'init_first_bond_probe_us', '{:.1f}')} / {g(r, 'init_first_bond_snapshot_us')} | "
                    f"{g(r, 'init_front_one_spacing_us')} | {P['init']*1e6:.0f} | {g(r, 'front_reaches_end_us')} | "
                    f"{g(r, 'mean_speed_m_s')} | {P['speed']} | {g(r, 'peak_speed_m_s')} | {g(r, 'arrests_us')} | "
                    f"{g(r, 'bonds_broken', '{:,}')} | {g(r, 'steps')} | {g(r, 'time_per_step_s', '{:.2f}')} | "
                    f"{g(r, 'wall_s')} | {g(r, 'max_balance_error', '{:.1e}')} |\n")
    for tag in sorted({n.split("_", 1)[1] for n in names}):
        sel = [r for r in results if r["run"].endswith(tag)]
        plot_fronts(sel, allrows, tag)


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "scenes":
        write_scenes()
    elif len(sys.argv) > 1 and sys.argv[1] == "run":
        run(sys.argv[2:])
    else:
        analyse(sys.argv[1:] or None)
