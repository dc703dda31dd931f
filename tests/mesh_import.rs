//! Scenes on imported Gmsh meshes (issue 10): one point per cell, materials and
//! point sets from physical groups, tractions on boundary facets.
//!
//! References: the scikit-fem solution of the plate with a hole
//! (`validation/plate_with_hole/fem/reference.json`), exact geometry (facet
//! lengths and areas, cell areas) and equilibrium.

use dhpd::drivers::static_solve::{self, StaticSolution};
use dhpd::reference::FemReference;
use dhpd::scene::{parse_spec, Scene};
use dhpd::validation::{compare_plate, HOLE_TRACTION};
use std::path::{Path, PathBuf};

fn gmsh_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("validation/plate_with_hole/gmsh")
}

/// A scene whose relative paths resolve in the mesh folder.
fn scene(text: &str) -> Scene {
    let spec = parse_spec(text, false).expect("test scene parses");
    Scene::try_from_spec(spec, &gmsh_dir(), "mesh_test").expect("test scene is valid")
}

fn solve(scene: &Scene) -> StaticSolution {
    static_solve::solve(scene).expect("the mesh scene solves")
}

/// The plate with a hole on the unstructured triangle mesh (h = 0.02, 5,692
/// cells, δ = 3.015 √(cell area) ≈ 0.039 m) against the converged FEM field.
/// PD's error here is the nonlocal boundary layer at the hole and the edges,
/// O(δ/r) (measured: 1.8 % bond-based, 3.7 % shear model; on the 0.02 m grid
/// 2.3 % and 6.1 %, validation/plate_with_hole/README.md). Bound 6 %: a wrong
/// cell area, thickness, traction or material gives errors of tens of percent.
/// The loads balance up to where they act (each facet's force on its cell's
/// centroid), so the statically determinate supports carry almost nothing:
/// below 1e-4 of P × 1 m.
#[test]
fn plate_with_a_hole_on_a_triangle_mesh_matches_fem() {
    let reference = FemReference::from_file(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("validation/plate_with_hole/fem/reference.json"),
    )
    .unwrap();
    for model in ["bond_based", "shear"] {
        let path = gmsh_dir().join(format!("plate_hole_tri_h0.02_{model}.toml"));
        let s = solve(&dhpd::scene::load(&path).unwrap());
        assert_eq!(s.counts.points, 5692);
        let c = compare_plate(&s, &reference);
        assert!(c.points > 5000, "{model}: {} points compared", c.points);
        assert!(
            c.l2_displacement < 0.06,
            "{model}: L2 error {:.2} %",
            100.0 * c.l2_displacement
        );
        for r in &s.reactions {
            assert!(
                r.force.iter().all(|f| f.abs() < 1e-4 * HOLE_TRACTION),
                "{model}: support {} carries {:?}",
                r.name,
                r.force
            );
        }
        // Each edge is 1 m long: the facet tractions add up to P × 1 m exactly.
        for load in &s.loads {
            assert!(
                (load.total_force[0].abs() - HOLE_TRACTION).abs() < 1e-9 * HOLE_TRACTION,
                "{}: {:?}",
                load.name,
                load.total_force
            );
        }
    }
}

/// The same mesh written as ASCII and as binary gives the same answer: the
/// files differ only in the last bit of some coordinates (Gmsh writes ASCII
/// with 16 significant digits), so the displacements agree to 1e-12.
#[test]
fn ascii_and_binary_meshes_give_the_same_solution() {
    let text = |file: &str| {
        format!(
            "[model]\ndimension = \"plane_stress\"\n[materials.m]\nyoungs_modulus = 1e9\n\
             [[meshes]]\npath = \"{file}\"\nmaterial = \"m\"\n\
             [[boundary]]\nname = \"clamp\"\ngroup = \"left\"\ndisplacement = {{ x = 0.0, y = 0.0 }}\n\
             [[loads]]\nname = \"pull\"\nkind = \"traction\"\ngroup = \"right\"\nvalue = [1e6, 2e5]\n"
        )
    };
    let a = solve(&scene(&text("plate_hole_quad_h0.02.msh")));
    let b = solve(&scene(&text("plate_hole_quad_h0.02_bin.msh")));
    let scale = a.u.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    for (p, q) in a.u.iter().zip(&b.u) {
        for c in 0..2 {
            assert!((p[c] - q[c]).abs() < 1e-12 * scale, "{p:?} vs {q:?}");
        }
    }
    // The clamp (cells touching the left curve) holds the whole load.
    let r = a.reaction("clamp").unwrap();
    assert!((r[0] + 1e6).abs() < 1e-9 * 1e6 && (r[1] + 2e5).abs() < 1e-9 * 1e6);
}

/// Physical groups map cells to materials, and a body force on a 2D group acts
/// on its cells: the strip [0, 1] × [0, 0.1] split at x = 0.5 into "soft" and
/// "stiff" (0.05 m² each, 1 m thick).
#[test]
fn groups_give_materials_and_body_forces() {
    let s = solve(&scene(
        "[model]\ndimension = \"plane_stress\"\n\
         [materials.a]\nyoungs_modulus = 1e9\n[materials.b]\nyoungs_modulus = 3e9\n\
         [[meshes]]\npath = \"bimaterial_strip_bin.msh\"\ngroups = { soft = \"a\", stiff = \"b\" }\n\
         [[boundary]]\nname = \"clamp\"\ngroup = \"left\"\ndisplacement = { x = 0.0, y = 0.0 }\n\
         [[loads]]\nname = \"weight\"\nkind = \"body_force\"\ngroup = \"stiff\"\nvalue = [0.0, -1e4]\n",
    ));
    let p = &s.disc.points;
    assert_eq!(p.len(), 418);
    for i in 0..p.len() {
        let expected = u32::from(p.x[i][0] > 0.5);
        assert_eq!(p.material[i], expected, "point {i} at {:?}", p.x[i]);
    }
    let area: f64 = p.volume.iter().sum();
    assert!((area - 0.1).abs() < 1e-14, "cell areas sum to {area}");
    let load = &s.loads[0];
    assert_eq!(load.points, 208);
    assert!((load.total_force[1] + 1e4 * 0.05).abs() < 1e-9, "{load:?}");
}

/// 3D: tetrahedra of the unit cube, clamped on the `xmin` face group, a
/// traction on `xmax` (triangular facets of total area 1 m²).
#[test]
fn tetrahedral_mesh_with_face_groups() {
    let s = solve(&scene(
        "[model]\ndimension = \"3d\"\n[discretization]\nhorizon_factor = 2.5\n\
         [materials.m]\nyoungs_modulus = 1e9\n\
         [[meshes]]\npath = \"cube_tet_h0.25.msh\"\nmaterial = \"m\"\n\
         [[boundary]]\nname = \"clamp\"\ngroup = \"xmin\"\ndisplacement = { x = 0.0, y = 0.0, z = 0.0 }\n\
         [[loads]]\nname = \"pull\"\nkind = \"traction\"\ngroup = \"xmax\"\nvalue = [1e6, 0.0, 0.0]\n",
    ));
    assert_eq!(s.counts.points, 391);
    let volume: f64 = s.disc.points.volume.iter().sum();
    assert!((volume - 1.0).abs() < 1e-13, "cell volumes sum to {volume}");
    assert!((s.loads[0].total_force[0] - 1e6).abs() < 1e-9 * 1e6);
    let r = s.reaction("clamp").unwrap();
    assert!((r[0] + 1e6).abs() < 1e-8 * 1e6, "{r:?}");
}
