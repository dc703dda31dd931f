#!/usr/bin/env python3
"""Scene generator and runner for the shear-surface study.

A case is a dict of parameters (see defaults()). run() writes the scene to work/scenes/,
runs dhpd into work/out/ (skipped when the output is newer than the scene and the binary),
and returns the reactions, the innermost constrained point centres a, b (the FEM domain)
and, for the column test, the force through the cuts x = 0.25 and x = 0.75.

dhpd: $DHPD, default target/release/dhpd of the repository."""
import json, math, os, subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
WORK = os.path.join(HERE, "work")
RESULTS = os.path.join(HERE, "results")
DHPD = os.environ.get("DHPD", os.path.join(REPO, "target", "release", "dhpd"))
EPS = 1e-4          # column test: imposed axial strain


def defaults(**kw):
    """kind, Poisson ratio, refinement r (spacing 0.01/r left, 0.005/r right), E2, height,
    horizon factor m, dilatation, volume correction, supports (std = strip_2d.toml's layers,
    roller, repo = the layers of src/validation, columns = column test), stress output,
    uniform = one spacing (times 1/r) on both halves instead of 0.01/0.005."""
    p = dict(kind="shear", nu=1/3, r=1, e2=2.0, H=0.1, m=3.015, dil="weighted", vc="overlap",
             sup="std", stress=False, uniform=None)
    p.update(kw)
    return p


def name_of(p):
    def f(v):
        return f"{v:.4g}".replace(".", "p") if isinstance(v, float) else str(v)
    nm = "_".join(f"{k}{f(p[k])}" for k in ["kind", "nu", "r", "e2", "H", "m", "dil", "vc", "sup"])
    if p["stress"]:
        nm += "_S"
    if p["uniform"]:
        nm += "_u" + str(p["uniform"]).replace(".", "p")
    return nm


def spacings(p):
    u = p["uniform"]
    return (0.01 / p["r"], 0.005 / p["r"]) if u is None else (u / p["r"], u / p["r"])


def support_layers(p, dxl, dxr):
    # "repo": the layers of src/validation (x <= 0.025 + dxl/4, x >= 0.9725 - dxr/4), whose
    # innermost centres stay at 0.025 / 0.9725 for odd refinements
    return (0.025 + 0.25 * dxl, 0.9725 - 0.25 * dxr) if p["sup"] == "repo" else (0.03, 0.97)


def columns(dxl, dxr):
    """Centre x and spacing of every point column, left half then right half."""
    xs, x = [], dxl / 2
    while x < 0.5:
        xs.append((x, dxl)); x += dxl
    x = 0.5 + dxr / 2
    while x < 1.0:
        xs.append((x, dxr)); x += dxr
    return xs


def scene(p):
    dxl, dxr = spacings(p)
    nu, H, sup = p["nu"], p["H"], p["sup"]
    s = [f'name = "{name_of(p)}"', "[model]", 'dimension = "plane_stress"', f'kind = "{p["kind"]}"']
    if p["kind"] == "shear" and p["dil"] != "weighted":
        s.append(f'dilatation = "{p["dil"]}"')
    if p["kind"] == "bond_based" and abs(nu - 1/3) > 1e-12:
        s.append("allow_any_poisson = true")
    s += ["[discretization]", f'horizon_factor = {p["m"]}', f'volume_correction = "{p["vc"]}"']
    s += ["[materials.soft]", "youngs_modulus = 1.0", f"poisson_ratio = {nu!r}",
          "[materials.stiff]", f"youngs_modulus = {p['e2']!r}", f"poisson_ratio = {nu!r}"]
    s += ["[[regions]]", 'material = "soft"', f"spacing = {dxl!r}", f"box = {{ min = [0.0, 0.0], max = [0.5, {H!r}] }}",
          "[[regions]]", 'material = "stiff"', f"spacing = {dxr!r}", f"box = {{ min = [0.5, 0.0], max = [1.0, {H!r}] }}"]
    if sup in ("std", "roller", "repo"):
        lx = "x = 0.0" if sup == "roller" else "x = 0.0, y = 0.0"
        xl, xr = support_layers(p, dxl, dxr)
        s += ["[[boundary]]", 'name = "left"', f"box = {{ min = [0.0, 0.0], max = [{xl!r}, {H!r}] }}", f"displacement = {{ {lx} }}"]
        if sup == "roller":   # pin u_y of the left layer's row(s) at mid-height
            s += ["[[boundary]]", 'name = "pin"', f"box = {{ min = [0.0, {H/2 - 0.6*dxl!r}], max = [0.03, {H/2 + 0.6*dxl!r}] }}", "displacement = { y = 0.0 }"]
        s += ["[[boundary]]", 'name = "right"', f"box = {{ min = [{xr!r}, 0.0], max = [1.0, {H!r}] }}", "displacement = { x = 1e-4 }"]
    elif sup == "columns":
        # every point column gets u_x = EPS * x (u_y free): a homogeneous axial strain with free
        # lateral contraction and no end effects; the force through a cut is minus the sum of
        # the reactions of the columns left of it
        for k, (xc, dx) in enumerate(columns(dxl, dxr)):
            s += ["[[boundary]]", f'name = "c{k:05d}_{xc:.6f}"'.replace(".", "p"),
                  f"box = {{ min = [{xc - 0.4*dx!r}, 0.0], max = [{xc + 0.4*dx!r}, {H!r}] }}",
                  f"displacement = {{ x = {EPS * xc!r} }}"]
        # pin u_y of the point nearest (0.5 - dxl/2, H/2) (rigid mode)
        yc = dxl * (math.floor(H / 2 / dxl) + 0.5)
        s += ["[[boundary]]", 'name = "pin"',
              f"box = {{ min = [{0.5 - dxl*0.9!r}, {yc - 0.4*dxl!r}], max = [{0.5 - dxl*0.1!r}, {yc + 0.4*dxl!r}] }}",
              "displacement = { y = 0.0 }"]
    s += ["[output]", "vtu = false", f"stress = {'true' if p['stress'] and p['kind'] == 'shear' else 'false'}"]
    s += ["[[output.profiles]]", 'name = "centerline"', f"from = [0.0, {H/2!r}]", f"to = [1.0, {H/2!r}]"]
    return "\n".join(s) + "\n"


def run(p):
    nm, txt = name_of(p), scene(p)
    dxl, dxr = spacings(p)
    os.makedirs(os.path.join(WORK, "scenes"), exist_ok=True)
    path = os.path.join(WORK, "scenes", nm + ".toml")
    if not os.path.exists(path) or open(path).read() != txt:
        with open(path, "w") as f:
            f.write(txt)
    out = os.path.join(WORK, "out", nm)
    sm = os.path.join(out, "summary.json")
    if not os.path.exists(DHPD):
        raise SystemExit(f"no dhpd at {DHPD}: run `cargo build --release` in the repository or set DHPD")
    if not os.path.exists(sm) or os.path.getmtime(sm) < max(os.path.getmtime(path), os.path.getmtime(DHPD)):
        subprocess.run([DHPD, "run", path, "--out", out], check=True, capture_output=True)
    sm = json.load(open(sm))
    rx = {r["name"]: r["force"][0] for r in sm["reactions"]}
    # innermost constrained centres: the FEM domain [a, b]
    xl, xr = support_layers(p, dxl, dxr)
    a = max(dxl * (k + 0.5) for k in range(1000) if dxl * (k + 0.5) <= xl + 1e-12)
    b = min(0.5 + dxr * (k + 0.5) for k in range(10000) if 0.5 + dxr * (k + 0.5) >= xr - 1e-12)
    cuts = {}
    if p["sup"] == "columns":
        cols = sorted((float(k.split("_")[1].replace("p", ".")), v) for k, v in rx.items() if k.startswith("c"))
        for c in (0.25, 0.75):
            cuts[c] = -sum(v for x, v in cols if x < c)
    return dict(p=p, name=nm, cuts=cuts, out=out, rx=rx, a=a, b=b, dxl=dxl, dxr=dxr, summary=sm)


if __name__ == "__main__":   # the reproduction case: strip_2d.toml with kind = "shear"
    res = run(defaults())
    print(res["rx"], res["a"], res["b"])
