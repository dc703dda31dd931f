//! Tests of the MSH 4.1 reader: the Gmsh meshes of validation/plate_with_hole/gmsh,
//! hand-written files with known cells, and malformed input (an Err, never a panic).
use dhpd::geometry::gmsh::{read_msh, Mesh};
use std::panic::{catch_unwind, AssertUnwindSafe};

const R: f64 = 0.125;

fn dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("validation/plate_with_hole/gmsh")
}

fn load(name: &str, dim: usize) -> Mesh {
    let bytes = std::fs::read(dir().join(name)).unwrap();
    read_msh(&bytes, dim).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// ASCII and binary give the same mesh: identical topology, groups and tags;
/// coordinates differ only because Gmsh writes ASCII with "%.16g" (not
/// round-trip exact), by at most 1.2e-16 relative.
fn same(a: &Mesh, b: &Mesh) {
    assert_eq!(a.node_tag, b.node_tag);
    assert_eq!(a.cells.element_tag, b.cells.element_tag);
    assert_eq!(a.cells.nodes, b.cells.nodes);
    assert_eq!(a.cells.groups, b.cells.groups);
    assert_eq!(a.groups, b.groups);
    let scale = a.nodes.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    for (p, q) in a.nodes.iter().zip(&b.nodes) {
        for k in 0..3 {
            assert!(
                (p[k] - q[k]).abs() <= 1.2e-16 * scale.max(p[k].abs()),
                "{p:?} {q:?}"
            );
        }
    }
    for (p, q) in a.cells.measure.iter().zip(&b.cells.measure) {
        assert!(((p - q) / p).abs() < 1e-13);
    }
}

fn names(m: &Mesh) -> Vec<(usize, String)> {
    m.groups.iter().map(|g| (g.dim, g.name.clone())).collect()
}

fn hole_polygon_area(m: &Mesh) -> f64 {
    let hole = m.group("hole").unwrap();
    let mut p: Vec<[f64; 3]> = hole.nodes.iter().map(|&i| m.nodes[i]).collect();
    p.sort_by(|a, b| a[1].atan2(a[0]).total_cmp(&b[1].atan2(b[0])));
    (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}

#[test]
fn plate_with_hole_meshes() {
    // (file stem, h, triangles, quadrangles, nodes, hole nodes)
    let cases = [
        ("plate_hole_tri_h0.02", 0.02, 5692, 0, 2966, 40),
        ("plate_hole_quad_h0.02", 0.02, 12, 2402, 2530, 40),
    ];
    for (stem, h, tri, quad, nodes, hole) in cases {
        let a = load(&format!("{stem}.msh"), 2);
        let b = load(&format!("{stem}_bin.msh"), 2);
        same(&a, &b);
        let n3 = a.cells.nodes.iter().filter(|n| n.len() == 3).count();
        let n4 = a.cells.nodes.iter().filter(|n| n.len() == 4).count();
        assert_eq!((n3, n4, a.nodes.len()), (tri, quad, nodes), "{stem}");
        let mut got = names(&a);
        got.sort();
        let mut want: Vec<(usize, String)> = [
            (1, "bottom"),
            (1, "hole"),
            (1, "left"),
            (1, "right"),
            (1, "top"),
            (2, "left_layer"),
            (2, "plate"),
            (2, "right_layer"),
        ]
        .iter()
        .map(|(d, s)| (*d, s.to_string()))
        .collect();
        want.sort();
        assert_eq!(got, want);
        // total area: 1 - pi r^2 up to the polygonal hole, and exactly 1 - (polygon area) to round-off
        let total: f64 = a.cells.measure.iter().sum();
        let poly = hole_polygon_area(&a);
        assert!(
            (total - (1.0 - poly)).abs() < 1e-12,
            "{stem}: {total} vs {}",
            1.0 - poly
        );
        let gap = total - (1.0 - std::f64::consts::PI * R * R);
        assert!(
            gap > 0.0 && gap < 0.6 * h * h,
            "{stem}: polygonal hole gap {gap}"
        );
        assert_eq!(a.group("hole").unwrap().nodes.len(), hole);
        for &i in &a.group("hole").unwrap().nodes {
            let p = a.nodes[i];
            assert!(((p[0] * p[0] + p[1] * p[1]).sqrt() - R).abs() < 1e-12);
        }
        // edges and layers
        let plate = a.group("plate").unwrap();
        assert_eq!(plate.cells.len(), a.cells.measure.len());
        for (side, x) in [("left", -0.5), ("right", 0.5)] {
            let g = a.group(side).unwrap();
            assert_eq!(
                g.nodes.len(),
                (1.0 / h).round() as usize + 1,
                "{stem} {side}"
            );
            assert!(g.nodes.iter().all(|&i| a.nodes[i][0] == x));
            let layer = a.group(&format!("{side}_layer")).unwrap();
            assert!(!layer.cells.is_empty());
            for &c in &layer.cells {
                assert!((a.cells.centroid[c][0] - x).abs() < 3.0 * h);
                assert!(a.cells.groups[c].len() == 2); // plate and the layer
            }
            let area: f64 = layer.cells.iter().map(|&c| a.cells.measure[c]).sum();
            assert!(
                (area - 3.0 * h).abs() < 1e-12,
                "{stem} {side}_layer area {area}"
            );
        }
        for x in &a.cells.centroid {
            assert!(x[0].abs() < 0.5 && x[1].abs() < 0.5 && x[0].hypot(x[1]) > R && x[2] == 0.0);
        }
    }
}

#[test]
fn cube_and_bimaterial_strip() {
    let a = load("cube_tet_h0.25.msh", 3);
    let b = load("cube_tet_h0.25_bin.msh", 3);
    same(&a, &b);
    assert_eq!((a.cells.measure.len(), a.nodes.len()), (391, 144));
    assert!((a.cells.measure.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    let c: [f64; 3] = (0..3)
        .map(|k| {
            a.cells
                .centroid
                .iter()
                .zip(&a.cells.measure)
                .map(|(x, v)| x[k] * v)
                .sum::<f64>()
        })
        .collect::<Vec<_>>()
        .try_into()
        .unwrap();
    assert!(c.iter().all(|v| (v - 0.5).abs() < 1e-14), "{c:?}");
    for (name, x) in [("xmin", 0.0), ("xmax", 1.0)] {
        let g = a.group(name).unwrap();
        assert_eq!((g.dim, g.nodes.len()), (2, 31));
        assert!(g.nodes.iter().all(|&i| a.nodes[i][0] == x));
    }
    assert_eq!(a.group("body").unwrap().cells.len(), 391);

    let a = load("bimaterial_strip.msh", 2);
    let b = load("bimaterial_strip_bin.msh", 2);
    same(&a, &b);
    let (soft, stiff) = (a.group("soft").unwrap(), a.group("stiff").unwrap());
    assert_eq!((soft.cells.len(), stiff.cells.len()), (210, 208));
    assert!(a.cells.groups.iter().all(|g| g.len() == 1)); // each cell in exactly one material
    for (g, range) in [(soft, 0.0..0.5), (stiff, 0.5..1.0)] {
        assert!(g
            .cells
            .iter()
            .all(|&c| range.contains(&a.cells.centroid[c][0])));
        let area: f64 = g.cells.iter().map(|&c| a.cells.measure[c]).sum();
        assert!((area - 0.05).abs() < 1e-15, "{area}");
    }
    assert_eq!(a.group("left").unwrap().nodes.len(), 5);
    // reading the 3D cube as 2D, or the strip as 3D, is refused
    assert!(read_msh(&std::fs::read(dir().join("cube_tet_h0.25.msh")).unwrap(), 2).is_err());
    assert!(read_msh(
        &std::fs::read(dir().join("bimaterial_strip.msh")).unwrap(),
        3
    )
    .is_err());
}

/// Two triangles and a quadrangle (unit square split, plus a 2 x 1 rectangle),
/// non-contiguous node tags, an unnamed group, a point group, a skipped section.
const TINY: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
1 7 \"left edge\"
2 1 \"tri\"
2 2 \"quad\"
$EndPhysicalNames
$Comments
anything, even $Nodes
$EndComments
$Entities
1 1 2 0
5 0 0 0 1 9
1 0 0 0 0 1 0 1 7 2 5 -5
1 0 0 0 1 1 0 1 1 0
2 1 0 0 3 1 0 2 2 3 0
$EndEntities
$Nodes
4 7 10 70
0 5 0 1
10
0 0 0
1 1 0 3
20
30
40
1 0 0
1 1 0
0 1 0
2 2 0 2
50
60
3 0 0
3 1 0
1 1 0 1
70
0 0.5 0
$EndNodes
$Elements
4 5 1 20
0 5 15 1
20 10
1 1 1 1
11 10 70
2 1 2 2
1 10 20 40
2 20 30 40
2 2 3 1
3 20 50 60 30
$EndElements
$NodeData
1
\"u\"
$EndNodeData
";

fn tiny() -> Mesh {
    read_msh(TINY.as_bytes(), 2).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn tiny_ascii_known_cells() {
    let m = tiny();
    assert_eq!(m.node_tag, vec![10, 20, 30, 40, 50, 60, 70]);
    assert_eq!(m.cells.element_tag, vec![1, 2, 3]);
    assert_eq!(m.cells.measure, vec![0.5, 0.5, 2.0]);
    let third = 1.0 / 3.0;
    let want = [
        [third, third, 0.0],
        [2.0 * third, 2.0 * third, 0.0],
        [2.0, 0.5, 0.0],
    ];
    for (c, w) in m.cells.centroid.iter().zip(want) {
        for k in 0..3 {
            assert!((c[k] - w[k]).abs() < 1e-15, "{c:?} {w:?}");
        }
    }
    assert_eq!(
        m.cells.nodes,
        vec![vec![0, 1, 3], vec![1, 2, 3], vec![1, 4, 5, 2]]
    );
    let g = |n: &str| m.group(n).unwrap().clone();
    assert_eq!(
        (g("tri").cells, g("tri").nodes),
        (vec![0, 1], vec![0, 1, 2, 3])
    );
    assert_eq!(
        (g("quad").cells, g("quad").nodes),
        (vec![2], vec![1, 2, 4, 5])
    );
    assert_eq!(
        (
            g("left edge").dim,
            g("left edge").tag,
            g("left edge").nodes.clone()
        ),
        (1, 7, vec![0, 6])
    );
    // point entity 5 carries the unnamed physical group (0, 9)
    let p = m.groups.iter().find(|g| g.dim == 0).unwrap();
    assert_eq!((p.tag, p.name.as_str(), p.nodes.clone()), (9, "", vec![0]));
    // surface 2 is in two groups: "quad" (2, 2) and the unnamed (2, 3)
    let unnamed = m
        .groups
        .iter()
        .position(|g| (g.dim, g.tag) == (2, 3))
        .unwrap();
    assert_eq!(m.groups[unnamed].name, "");
    assert_eq!(
        m.cells.groups[2],
        vec![
            m.groups.iter().position(|g| g.name == "quad").unwrap(),
            unnamed
        ]
    );
    assert_eq!(m.groups.len(), 5);
}

#[test]
fn tiny_binary_big_endian_and_orientation() {
    // parametric nodes (u on a curve) are read and their parameters skipped
    let p = read_msh(
        TINY.replace("1 1 0 1\n70\n0 0.5 0\n", "1 1 1 1\n70\n0 0.5 0 0.25\n")
            .as_bytes(),
        2,
    )
    .unwrap();
    assert_eq!(p, tiny());
    // A clockwise triangle is accepted (|area|); the same file written in
    // binary (little- and big-endian) reads the same.
    let m = read_msh(TINY.replace("1 10 20 40", "1 10 40 20").as_bytes(), 2).unwrap();
    assert_eq!(m.cells.measure[0], 0.5);
    let tiny = tiny();
    for big in [false, true] {
        let b = to_binary(&tiny, big);
        let mb = read_msh(&b, 2).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(mb, tiny);
    }
}

/// Writes `m` as a binary MSH 4.1 file (one entity per cell type, as Gmsh does),
/// little- or big-endian.
fn to_binary(m: &Mesh, big: bool) -> Vec<u8> {
    let mut o = b"$MeshFormat\n4.1 1 8\n".to_vec();
    let i32b = |v: i32| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let u64b = |v: u64| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let f64b = |v: f64| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    o.extend(i32b(1));
    o.extend(b"\n$EndMeshFormat\n$PhysicalNames\n3\n1 7 \"left edge\"\n2 1 \"tri\"\n2 2 \"quad\"\n$EndPhysicalNames\n$Entities\n");
    for n in [1u64, 1, 2, 0] {
        o.extend(u64b(n));
    }
    // point 5 (group 9), curve 1 (group 7), surfaces 1 (group 1) and 2 (group 2)
    o.extend(i32b(5));
    for _ in 0..3 {
        o.extend(f64b(0.0));
    }
    o.extend(u64b(1));
    o.extend(i32b(9));
    let ent = |o: &mut Vec<u8>, tag: i32, phys: &[i32]| {
        o.extend(i32b(tag));
        for _ in 0..6 {
            o.extend(f64b(0.0));
        }
        o.extend(u64b(phys.len() as u64));
        for &p in phys {
            o.extend(i32b(p));
        }
        o.extend(u64b(0));
    };
    ent(&mut o, 1, &[7]);
    ent(&mut o, 1, &[1]);
    ent(&mut o, 2, &[2, 3]);
    o.extend(b"\n$EndEntities\n$Nodes\n");
    for n in [1u64, 7, 10, 70] {
        o.extend(u64b(n));
    }
    o.extend(i32b(2));
    o.extend(i32b(1));
    o.extend(i32b(0));
    o.extend(u64b(7));
    for &t in &m.node_tag {
        o.extend(u64b(t));
    }
    for x in &m.nodes {
        for v in x {
            o.extend(f64b(*v));
        }
    }
    o.extend(b"\n$EndNodes\n$Elements\n");
    for n in [4u64, 5, 1, 20] {
        o.extend(u64b(n));
    }
    let block = |o: &mut Vec<u8>, d: i32, e: i32, t: i32, els: &[(u64, Vec<u64>)]| {
        o.extend(i32b(d));
        o.extend(i32b(e));
        o.extend(i32b(t));
        o.extend(u64b(els.len() as u64));
        for (tag, nodes) in els {
            o.extend(u64b(*tag));
            for &n in nodes {
                o.extend(u64b(n));
            }
        }
    };
    block(&mut o, 0, 5, 15, &[(20, vec![10])]);
    block(&mut o, 1, 1, 1, &[(11, vec![10, 70])]);
    block(
        &mut o,
        2,
        1,
        2,
        &[(1, vec![10, 20, 40]), (2, vec![20, 30, 40])],
    );
    block(&mut o, 2, 2, 3, &[(3, vec![20, 50, 60, 30])]);
    o.extend(b"\n$EndElements\n");
    o
}

/// A hexahedron (sheared, planar faces) and a tetrahedron with known volumes.
#[test]
fn tiny_3d_known_cells() {
    let s = 0.3; // shear of the top face in x
    let mut nodes = String::new();
    let corners = [
        [0., 0., 0.],
        [2., 0., 0.],
        [2., 1., 0.],
        [0., 1., 0.],
        [s, 0., 1.],
        [2. + s, 0., 1.],
        [2. + s, 1., 1.],
        [s, 1., 1.],
    ];
    for (i, c) in corners.iter().enumerate() {
        nodes += &format!("{}\n", i + 1);
        let _ = c;
    }
    for c in corners {
        nodes += &format!("{} {} {}\n", c[0], c[1], c[2]);
    }
    let text = format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n2 9 1 9\n3 1 0 8\n{nodes}3 2 0 1\n9\n0 0 -1\n$EndNodes\n$Elements\n2 2 1 2\n3 1 5 1\n1 1 2 3 4 5 6 7 8\n3 2 4 1\n2 1 3 2 9\n$EndElements\n");
    let m = read_msh(text.as_bytes(), 3).unwrap_or_else(|e| panic!("{e}"));
    assert!((m.cells.measure[0] - 2.0).abs() < 1e-15);
    let c = m.cells.centroid[0];
    assert!(
        (c[0] - (1.0 + s / 2.0)).abs() < 1e-15
            && (c[1] - 0.5).abs() < 1e-15
            && (c[2] - 0.5).abs() < 1e-15,
        "{c:?}"
    );
    // tet (0,0,0), (2,1,0), (2,0,0), (0,0,-1): volume |det|/6 = 2/6
    assert!((m.cells.measure[1] - 1.0 / 3.0).abs() < 1e-15);
    assert!(m.groups.is_empty() && m.cells.groups.iter().all(|g| g.is_empty())); // no $Entities
                                                                                 // the same tet with two nodes swapped is inverted
    let e = read_msh(text.replace("2 1 3 2 9", "2 1 2 3 9").as_bytes(), 3).unwrap_err();
    assert!(
        e.message.contains("element 2") && e.message.contains("inverted"),
        "{e}"
    );
    // a hexahedron with a top and bottom face swapped is inverted
    let e = read_msh(
        text.replace("1 1 2 3 4 5 6 7 8", "1 5 6 7 8 1 2 3 4")
            .as_bytes(),
        3,
    )
    .unwrap_err();
    assert!(e.message.contains("element 1"), "{e}");
}

fn err(text: &str, dim: usize) -> String {
    match catch_unwind(AssertUnwindSafe(|| read_msh(text.as_bytes(), dim))) {
        Ok(Ok(_)) => panic!("accepted: {text}"),
        Ok(Err(e)) => e.message,
        Err(_) => panic!("panicked on: {text}"),
    }
}

#[test]
fn malformed_input_is_an_error() {
    let cases: Vec<(String, &str)> = vec![
        (TINY.replace("4.1 0 8", "2.2 0 8"), "version 2.2"),
        (TINY.replace("4.1 0 8", "4.1 0 3"), "data size"),
        (
            TINY.replace("$MeshFormat\n", ""),
            "must start with $MeshFormat",
        ),
        (
            TINY.replace("2 20 30 40", "2 20 30 99"),
            "element 2 refers to node 99",
        ),
        (
            TINY.replace("11 10 70", "11 10 71"),
            "element 11 refers to node 71",
        ),
        (
            TINY.replace("2 20 30 40", "2 20 30 20"),
            "element 2 repeats a node",
        ),
        (
            TINY.replace("0 1 0\n2 2 0 2", "1 0 0\n2 2 0 2"),
            "element 1 has zero area",
        ),
        (TINY.replace("3 1 0\n", "3 1 0.5\n"), "node 60 has z = 5e-1"),
        (
            TINY.replace("3 20 50 60 30", "3 20 50 30 60"),
            "element 3 has zero area",
        ), // symmetric bow-tie
        (
            TINY.replace("3 20 50 60 30", "3 20 50 30 60")
                .replace("3 1 0\n", "4 0.5 0\n"),
            "element 3 is a non-convex or self-intersecting",
        ),
        (
            TINY.replace("3 1 0\n", "1.5 0.5 0\n"),
            "element 3 is a non-convex or self-intersecting",
        ),
        (
            TINY.replace("2 1 2 2\n", "2 1 9 2\n"),
            "6-node triangle elements (Gmsh type 9, entity 1) are not supported",
        ),
        (TINY.replace("2 1 2 2\n", "2 1 99 2\n"), "element type 99"),
        (TINY.replace("2 1 2 2\n", "3 1 4 2\n"), "read as a 2D mesh"),
        (
            TINY.replace("2 1 2 2\n", "1 1 2 2\n"),
            "in an entity of dimension 1",
        ),
        (
            TINY.replace("4 5 1 20", "4 6 1 20"),
            "the header says 6 elements",
        ),
        (
            TINY.replace("4 7 10 70", "4 1000000000000000 10 70"),
            "the header says 1000000000000000 nodes",
        ),
        (
            TINY.replace("1 1 0 3\n", "1 1 0 1000000000000000\n"),
            "more than the",
        ),
        (
            TINY.replace("2 1 2 2\n", "2 1 2 18446744073709551615\n"),
            "more than the",
        ),
        (
            TINY.replace("4 5 1 20", "18446744073709551615 5 1 20"),
            "more than the",
        ),
        (
            TINY.replace("1 1 2 0\n", "1000000000000000 1 2 0\n"),
            "more than the",
        ),
        (TINY.replace("1 1 0 3\n", "1 1 0 -3\n"), "unsigned integer"),
        (
            TINY.replace("30\n40", "30\n30"),
            "node tag 30 appears twice",
        ),
        (TINY.replace("1 1 0\n0 1 0", "1 1 0\nnan 1 0"), "non-finite"),
        (TINY.replace("3 0 0", "inf 0 0"), "non-finite"),
        (TINY.replace("$EndNodes", "$EndNode"), "expected $EndNodes"),
        (
            TINY.replace("$EndComments\n", ""),
            "section $Comments has no $EndComments",
        ),
        (
            TINY.replace("2 2 3 1\n", "2 3 3 1\n"),
            "entity (2, 3), which is not in $Entities",
        ),
        (TINY.replace("\"quad\"", "quad"), "double quotes"),
        (
            TINY.replace("0 5 0 1\n", "0 5 2 1\n"),
            "the parametric flag",
        ),
        (
            TINY.replace("1 1 0 1\n70", "1 1 1 1\n70"),
            "expected a parametric node coordinate",
        ),
        (
            TINY.replace("$Elements\n", "$Nodes\n")
                .replace("$EndElements", "$EndNodes"),
            "a second $Nodes section",
        ),
        (
            TINY.replace("$Elements\n", "$Elemnts\n")
                .replace("$EndElements", "$EndElemnts"),
            "no $Elements section",
        ),
        (
            TINY.replace(
                "2 1 2 2\n1 10 20 40\n2 20 30 40\n2 2 3 1\n3 20 50 60 30\n",
                "1 1 1 1\n1 10 20\n1 1 1 1\n3 10 70\n",
            )
            .replace("4 5 1 20", "4 4 1 20"),
            "no 2D elements (found: 0D, 1D)",
        ),
        ("".to_string(), "must start with $MeshFormat"),
        ("\u{feff}".to_string(), "must start with $MeshFormat"),
        (
            "$MeshFormat\n4.1 1 8\n\x02\x00\x00\x00\n$EndMeshFormat\n".to_string(),
            "endianness",
        ),
    ];
    for (text, want) in &cases {
        let m = err(text, 2);
        assert!(m.contains(want), "expected {want:?} in {m:?}");
    }
    assert!(err(TINY, 4).contains("must be 2 or 3"));
}

#[test]
fn truncated_and_mutated_input_never_panics() {
    // every prefix of the tiny file, ASCII and binary
    let bin = to_binary(&tiny(), false);
    for text in [TINY.as_bytes(), &bin[..]] {
        for n in 0..text.len() {
            let r = catch_unwind(|| read_msh(&text[..n], 2));
            let r = r.unwrap_or_else(|_| panic!("panic on a {n}-byte prefix"));
            // a prefix ending inside the trailing skipped section may still be valid
            if n + 40 < text.len() {
                assert!(r.is_err(), "a {n}-byte prefix was accepted");
            }
        }
    }
    // every byte of the binary file set to a few values; every ASCII byte replaced by a digit
    for text in [TINY.as_bytes(), &bin[..]] {
        for i in 0..text.len() {
            for v in [0u8, 1, 0x7f, 0xff, b'9', b'-', b' '] {
                let mut d = text.to_vec();
                d[i] = v;
                for dim in [2, 3] {
                    let _ = catch_unwind(|| read_msh(&d, dim))
                        .unwrap_or_else(|_| panic!("panic: byte {i} = {v}"));
                }
            }
        }
    }
}

#[test]
fn gmsh_files_truncated_are_errors() {
    for name in [
        "bimaterial_strip.msh",
        "bimaterial_strip_bin.msh",
        "cube_tet_h0.25.msh",
        "cube_tet_h0.25_bin.msh",
    ] {
        let bytes = std::fs::read(dir().join(name)).unwrap();
        let dim = if name.starts_with("cube") { 3 } else { 2 };
        for n in (0..bytes.len() - 20).step_by(7) {
            assert!(
                read_msh(&bytes[..n], dim).is_err(),
                "{name}: {n}-byte prefix accepted"
            );
        }
    }
}
