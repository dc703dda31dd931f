#!/usr/bin/env python3
"""Gmsh meshes for dhpd's mesh import (issue 10).

Writes MSH 4.1 files next to this script, ASCII (`NAME.msh`) and binary
(`NAME_bin.msh`), and prints element counts and areas/volumes:

* plate with a hole (validation/plate_with_hole): plate [-0.5, 0.5]^2 m minus
  the central disc of radius 0.125 m, nearly uniform cells of size h:
    - `plate_hole_tri_h{0.02,0.01,0.005}`  linear triangles (type 2)
    - `plate_hole_quad_h{0.02,0.01}`       quad-dominant (type 3, a few type 2)
  Three surfaces sharing edges: the left strip [-0.5, -0.5+3h], the middle
  part with the hole, the right strip [0.5-3h, 0.5].
  Physical groups: 2D "plate" (all three surfaces), "left_layer",
  "right_layer" (the strips, so a layer of cells can be selected); 1D "left"
  (x = -0.5), "right" (x = +0.5), "top" (y = +0.5), "bottom" (y = -0.5),
  "hole" (the circle).
* `cube_tet_h0.25`: unit cube [0,1]^3, linear tetrahedra (type 4), h = 0.25,
  3D "body", 2D "xmin" (x = 0), "xmax" (x = 1).
* `bimaterial_strip`: [0,1] x [0,0.1] split at x = 0.5, triangles, h = 0.025,
  2D "soft" (x < 0.5), "stiff" (x > 0.5), 1D "left" (x = 0), "right" (x = 1).

Usage: python3 mesh_plate_with_hole.py [--sizes 0.02 0.01 0.005] [--no-quad]
Pinned: gmsh==4.13.1 (PyPI wheel), CPython 3.11.
"""
import argparse
import math
import os
import sys

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))
R = 0.125
EPS = 1e-5


def fmt_h(h):
    return ("%g" % h)


def setup_size(h):
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)


def write_both(name):
    """Write NAME.msh (ASCII) and NAME_bin.msh (binary), MSH 4.1."""
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.SaveAll", 0)  # only elements of physical groups (the default)
    out = []
    for binary, suffix in ((0, ""), (1, "_bin")):
        gmsh.option.setNumber("Mesh.Binary", binary)
        path = os.path.join(HERE, name + suffix + ".msh")
        gmsh.write(path)
        out.append((os.path.basename(path), os.path.getsize(path)))
    gmsh.option.setNumber("Mesh.Binary", 0)
    return out


def curves_in_box(x0, y0, x1, y1, z0=-EPS, z1=EPS, dim=1):
    return [t for (_, t) in gmsh.model.getEntitiesInBoundingBox(
        x0 - EPS, y0 - EPS, z0, x1 + EPS, y1 + EPS, z1, dim)]


def element_stats(dim):
    """Counts per element type, total measure of all elements of `dim`, and a
    size summary (min, mean, max, coefficient of variation of the cell measure)."""
    counts = {}
    sizes = []
    for (d, tag) in gmsh.model.getEntities(dim):
        types, _, _ = gmsh.model.mesh.getElements(d, tag)
        for t in types:
            name = gmsh.model.mesh.getElementProperties(t)[0]
            n = len(gmsh.model.mesh.getElementsByType(t, tag)[0])
            counts[name] = counts.get(name, 0) + n
    # exact measures of straight-sided elements from the node coordinates
    node_tags, coords, _ = gmsh.model.mesh.getNodes()
    xyz = {int(t): coords[3 * i:3 * i + 3] for i, t in enumerate(node_tags)}
    for (d, tag) in gmsh.model.getEntities(dim):
        types, _, conn = gmsh.model.mesh.getElements(d, tag)
        for t, c in zip(types, conn):
            nn = gmsh.model.mesh.getElementProperties(t)[3]
            for k in range(0, len(c), nn):
                p = [xyz[int(n)] for n in c[k:k + nn]]
                sizes.append(measure(p, dim))
    n = len(sizes)
    mean = math.fsum(sizes) / n
    cv = math.sqrt(math.fsum((v - mean) ** 2 for v in sizes) / n) / mean
    return counts, math.fsum(sizes), (min(sizes), mean, max(sizes), cv)


def measure(p, dim):
    """Area (dim 2: polygon, shoelace) or volume (dim 3: tetrahedron)."""
    if dim == 2:
        a = 0.0
        for i in range(len(p)):
            x0, y0 = p[i][0], p[i][1]
            x1, y1 = p[(i + 1) % len(p)][0], p[(i + 1) % len(p)][1]
            a += x0 * y1 - x1 * y0
        return abs(a) / 2
    if len(p) == 4:
        a = [p[1][i] - p[0][i] for i in range(3)]
        b = [p[2][i] - p[0][i] for i in range(3)]
        c = [p[3][i] - p[0][i] for i in range(3)]
        det = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
               + a[2] * (b[0] * c[1] - b[1] * c[0]))
        return abs(det) / 6
    raise ValueError("unsupported element with %d nodes" % len(p))


def hole_polygon_area():
    """Area of the polygon through the mesh nodes on the hole curve(s)."""
    pts = []
    for t in curves_in_box(-R, -R, R, R):
        _, coords, _ = gmsh.model.mesh.getNodes(1, t, includeBoundary=True)
        pts += [(coords[3 * i], coords[3 * i + 1]) for i in range(len(coords) // 3)]
    pts = sorted(set(pts), key=lambda q: math.atan2(q[1], q[0]))
    a = 0.0
    for i in range(len(pts)):
        x0, y0 = pts[i]
        x1, y1 = pts[(i + 1) % len(pts)]
        a += x0 * y1 - x1 * y0
    return a / 2, len(pts)


def size_line(size, dim):
    lo, mean, hi, cv = size
    return ("cell %s min/mean/max %.3e/%.3e/%.3e, max/min %.2f, cv %.3f, "
            "equivalent spacing (mean)^(1/%d) = %.4g m"
            % ("area" if dim == 2 else "volume", lo, mean, hi, hi / lo, cv, dim, mean ** (1 / dim)))


def plate_with_hole(h, quad):
    gmsh.model.add("plate_hole")
    occ = gmsh.model.occ
    w = 3 * h
    left = occ.addRectangle(-0.5, -0.5, 0, w, 1)
    mid = occ.addRectangle(-0.5 + w, -0.5, 0, 1 - 2 * w, 1)
    right = occ.addRectangle(0.5 - w, -0.5, 0, w, 1)
    disk = occ.addDisk(0, 0, 0, R, R)
    occ.cut([(2, mid)], [(2, disk)])
    occ.fragment(occ.getEntities(2), [])  # shared edges between the three surfaces
    occ.synchronize()
    surf = [t for (_, t) in gmsh.model.getEntities(2)]
    sl = [t for t in surf if _in_box(2, t, -0.5, -0.5, -0.5 + w, 0.5)]
    sr = [t for t in surf if _in_box(2, t, 0.5 - w, -0.5, 0.5, 0.5)]
    assert len(sl) == 1 and len(sr) == 1 and len(surf) == 3, surf
    groups = [
        (2, surf, "plate"),
        (2, sl, "left_layer"),
        (2, sr, "right_layer"),
        (1, curves_in_box(-0.5, -0.5, -0.5, 0.5), "left"),
        (1, curves_in_box(0.5, -0.5, 0.5, 0.5), "right"),
        (1, curves_in_box(-0.5, 0.5, 0.5, 0.5), "top"),
        (1, curves_in_box(-0.5, -0.5, 0.5, -0.5), "bottom"),
        (1, curves_in_box(-R, -R, R, R), "hole"),
    ]
    for dim, tags, name in groups:
        assert tags, name
        gmsh.model.addPhysicalGroup(dim, tags, name=name)
    setup_size(h)
    if quad:
        gmsh.option.setNumber("Mesh.Algorithm", 8)  # Frontal-Delaunay for quads
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)  # blossom
    else:
        gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay
        gmsh.option.setNumber("Mesh.RecombineAll", 0)
    gmsh.model.mesh.generate(2)
    counts, area, size = element_stats(2)
    poly, nhole = hole_polygon_area()
    exact = 1 - math.pi * R * R
    return counts, area, exact, 1 - poly, nhole, size


def _in_box(dim, tag, x0, y0, x1, y1):
    b = gmsh.model.getBoundingBox(dim, tag)
    return b[0] > x0 - EPS and b[1] > y0 - EPS and b[3] < x1 + EPS and b[4] < y1 + EPS


def cube():
    gmsh.model.add("cube")
    gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    gmsh.model.occ.synchronize()
    vol = [t for (_, t) in gmsh.model.getEntities(3)]
    xmin = curves_in_box(0, 0, 0, 1, z0=-EPS, z1=1 + EPS, dim=2)
    xmax = curves_in_box(1, 0, 1, 1, z0=-EPS, z1=1 + EPS, dim=2)
    xmin = [t for t in xmin if gmsh.model.getBoundingBox(2, t)[3] < EPS]
    xmax = [t for t in xmax if gmsh.model.getBoundingBox(2, t)[0] > 1 - EPS]
    assert len(xmin) == 1 and len(xmax) == 1
    gmsh.model.addPhysicalGroup(3, vol, name="body")
    gmsh.model.addPhysicalGroup(2, xmin, name="xmin")
    gmsh.model.addPhysicalGroup(2, xmax, name="xmax")
    setup_size(0.25)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay
    gmsh.option.setNumber("Mesh.RecombineAll", 0)
    gmsh.model.mesh.generate(3)
    return element_stats(3)


def strip():
    gmsh.model.add("strip")
    occ = gmsh.model.occ
    a = occ.addRectangle(0, 0, 0, 0.5, 0.1)
    b = occ.addRectangle(0.5, 0, 0, 0.5, 0.1)
    occ.fragment([(2, a)], [(2, b)])
    occ.synchronize()
    surf = [t for (_, t) in gmsh.model.getEntities(2)]
    soft = [t for t in surf if _in_box(2, t, 0, 0, 0.5, 0.1)]
    stiff = [t for t in surf if _in_box(2, t, 0.5, 0, 1, 0.1)]
    assert len(soft) == 1 and len(stiff) == 1
    gmsh.model.addPhysicalGroup(2, soft, name="soft")
    gmsh.model.addPhysicalGroup(2, stiff, name="stiff")
    gmsh.model.addPhysicalGroup(1, curves_in_box(0, 0, 0, 0.1), name="left")
    gmsh.model.addPhysicalGroup(1, curves_in_box(1, 0, 1, 0.1), name="right")
    setup_size(0.025)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    gmsh.option.setNumber("Mesh.RecombineAll", 0)
    gmsh.model.mesh.generate(2)
    return element_stats(2)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=float, nargs="+", default=[0.02, 0.01, 0.005])
    ap.add_argument("--quad-sizes", type=float, nargs="*", default=[0.02, 0.01])
    args = ap.parse_args()
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    print("gmsh", gmsh.__version__, "python", sys.version.split()[0])
    for quad, sizes in ((False, args.sizes), (True, args.quad_sizes)):
        for h in sizes:
            counts, area, exact, polyexact, nhole, size = plate_with_hole(h, quad)
            name = "plate_hole_%s_h%s" % ("quad" if quad else "tri", fmt_h(h))
            files = write_both(name)
            print("%s: h=%g elements %s; hole polygon %d sides" % (name, h, counts, nhole))
            print("  area %.15f; 1-pi r^2 = %.15f (diff %.3e, polygonal hole); "
                  "1 - polygon area = %.15f (diff %.1e)"
                  % (area, exact, area - exact, polyexact, area - polyexact))
            print("  " + size_line(size, 2))
            for f, s in files:
                print("  %s %d bytes" % (f, s))
            gmsh.model.remove()
    counts, vol, size = cube()
    files = write_both("cube_tet_h0.25")
    print("cube_tet_h0.25: elements %s; volume %.15f (diff %.1e)" % (counts, vol, vol - 1))
    print("  " + size_line(size, 3))
    for f, s in files:
        print("  %s %d bytes" % (f, s))
    gmsh.model.remove()
    counts, area, size = strip()
    files = write_both("bimaterial_strip")
    print("bimaterial_strip: elements %s; area %.15f (diff %.1e)" % (counts, area, area - 0.1))
    print("  " + size_line(size, 2))
    for f, s in files:
        print("  %s %d bytes" % (f, s))
    gmsh.model.remove()
    gmsh.finalize()


if __name__ == "__main__":
    main()
