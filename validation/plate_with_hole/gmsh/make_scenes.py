#!/usr/bin/env python3
"""Writes the dhpd scenes of the plate with a hole on the committed Gmsh meshes
(uniaxial tension P = 1 MPa on the `left` and `right` boundary groups, as in
../README.md). The loads balance, so the plate is held statically
determinately: both components of the cell nearest (-0.5, 0) and the y
component of the cell nearest (0.5, 0), each selected by a box of half a
millimetre around its centroid (the centroids are read from the mesh here).

    python3 validation/plate_with_hole/gmsh/make_scenes.py
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = ["plate_hole_tri_h0.02", "plate_hole_tri_h0.01", "plate_hole_quad_h0.02"]


def centroids(path):
    """Area centroids (as dhpd computes them) of the triangles and quadrangles
    of an ASCII MSH 4.1 file."""
    lines = open(path).read().split("\n")
    nodes, cells, k = {}, [], 0
    while k < len(lines):
        if lines[k] == "$Nodes":
            blocks = int(lines[k + 1].split()[0])
            k += 2
            for _ in range(blocks):
                n = int(lines[k].split()[3])
                tags = [int(t) for t in lines[k + 1:k + 1 + n]]
                xyz = [tuple(map(float, l.split()[:2])) for l in lines[k + 1 + n:k + 1 + 2 * n]]
                nodes.update(zip(tags, xyz))
                k += 1 + 2 * n
        elif lines[k] == "$Elements":
            blocks = int(lines[k + 1].split()[0])
            k += 2
            for _ in range(blocks):
                etype, n = int(lines[k].split()[2]), int(lines[k].split()[3])
                for l in lines[k + 1:k + 1 + n]:
                    if etype in (2, 3):
                        cells.append(polygon_centroid([nodes[int(t)] for t in l.split()[1:]]))
                k += 1 + n
        else:
            k += 1
    return cells


def polygon_centroid(p):
    a = cx = cy = 0.0
    for (x0, y0), (x1, y1) in zip(p, p[1:] + p[:1]):
        w = x0 * y1 - x1 * y0
        a, cx, cy = a + w, cx + (x0 + x1) * w, cy + (y0 + y1) * w
    return (cx / (3 * a), cy / (3 * a))


def box_around(c, half=5e-4):
    return f"{{ min = [{c[0] - half!r}, {c[1] - half!r}], max = [{c[0] + half!r}, {c[1] + half!r}] }}"


def scene(mesh, model):
    cells = centroids(os.path.join(HERE, mesh + ".msh"))
    near = lambda x, y: min(cells, key=lambda c: (c[0] - x) ** 2 + (c[1] - y) ** 2)
    extra = "stress = true\n" if model == "shear" else ""
    return f"""# Plate with a hole (001 Sec. 6.3) on the unstructured Gmsh mesh {mesh}.msh:
# one point per cell (centroid, cell area), delta = 3.015 sqrt(cell area), E = 30 GPa,
# nu = 1/3, plane stress, P = 1 MPa on the left and right boundary groups (each
# facet's length times P on the cell it bounds), statically determinate supports.
# Compared with the scikit-fem reference by `cargo run --release --example mesh_plate`
# (validation/plate_with_hole/README.md, "On an imported Gmsh mesh").
name = "{mesh.replace(".", "p")}_{model}"

[model]
dimension = "plane_stress"
kind = "{model}"

[discretization]
horizon_factor = 3.015

[materials.concrete]
youngs_modulus = 30e9
poisson_ratio = 0.3333333333333333

[[meshes]]
path = "{mesh}.msh"
material = "concrete"

[[boundary]]
name = "pin"
box = {box_around(near(-0.5, 0.0))}
displacement = {{ x = 0.0, y = 0.0 }}

[[boundary]]
name = "roller"
box = {box_around(near(0.5, 0.0))}
displacement = {{ y = 0.0 }}

[[loads]]
name = "left"
kind = "traction"
group = "left"
value = [-1e6, 0.0]

[[loads]]
name = "right"
kind = "traction"
group = "right"
value = [1e6, 0.0]

[output]
vtu = false
{extra}"""


if __name__ == "__main__":
    for mesh in MESHES:
        for model in ("bond_based", "shear"):
            path = os.path.join(HERE, f"{mesh}_{model}.toml")
            open(path, "w").write(scene(mesh, model))
            print(path)
