//! The bond-based surface correction (src/model/surface.rs, issue 33):
//!
//! - every owner's stiffness under homogeneous strain equals its full family's,
//!   at surface, edge and corner points too (the moments it matches, checked
//!   through the energy of axis strains and of their combinations, to 1e-9 of
//!   the bulk energy: the Newton tolerance is 1e-11 of the largest moment);
//! - factors are positive and the correction leaves every bond of a full
//!   family bitwise unchanged;
//! - rigid motions give no force (translation and rotation, linearised and
//!   nonlinear: a bond force stays along its bond, whatever its factor);
//! - the assembled stiffness is symmetric;
//! - the bond-based stress (`output.stress`) under a homogeneous strain is the
//!   full family's at every point, and Hooke's law on imported points.

mod common;

use common::{disc, scene};
use dhpd::assembly::forces::internal_forces;
use dhpd::discretization::Discretization;
use dhpd::model::bond_based::BondBased;
use dhpd::model::Model;
use dhpd::scene::Scene;
use dhpd::vector::{norm, sub};

/// A box of `n` spacings per side (2D or 3D, spacing 0.1) with a through hole
/// in 2D (a curved surface), corrected or not.
fn body(dimension: &str, correction: &str, hole: bool) -> Scene {
    let (lo, hi) = if dimension == "3d" {
        ("[0.0, 0.0, 0.0]", "[1.2, 1.0, 1.0]")
    } else {
        ("[0.0, 0.0]", "[2.0, 1.2]")
    };
    let hole = if hole {
        "[[holes]]\ncenter = [1.0, 0.6]\nradius = 0.3\n"
    } else {
        ""
    };
    scene(&format!(
        "[model]\ndimension = \"{dimension}\"\n[discretization]\nsurface_correction = \"{correction}\"\n\
         [materials.a]\nyoungs_modulus = 2.0e9\n[[regions]]\nmaterial = \"a\"\nspacing = 0.1\n\
         box = {{ min = {lo}, max = {hi} }}\n{hole}"
    ))
}

fn model(scene: &Scene, disc: &Discretization) -> BondBased {
    BondBased::of(scene, disc)
}

/// Energy of owner `i`'s bonds under the homogeneous strain `eps` (linearised).
fn owner_energy(m: &BondBased, disc: &Discretization, i: usize, eps: &[[f64; 3]; 3]) -> f64 {
    let p = &disc.points;
    disc.bonds
        .owned_by(i)
        .map(|b| {
            let j = disc.bonds.neighbour[b] as usize;
            let xi = sub(&p.x[j], &p.x[i]);
            let len = norm(&xi);
            let e = xi.map(|v| v / len);
            let s: f64 = (0..3)
                .map(|a| (0..3).map(|c| e[a] * eps[a][c] * e[c]).sum::<f64>())
                .sum();
            0.5 * m.bond_weight(disc, i, b) * len * s * s
        })
        .sum()
}

/// Owners whose family is the lattice's (farther than δ + r from every face).
fn interior(disc: &Discretization, lo: &[f64; 3], hi: &[f64; 3]) -> Vec<bool> {
    let p = &disc.points;
    (0..p.len())
        .map(|i| {
            let reach = p.horizon[i] + p.spacing[i];
            (0..disc.d).all(|a| p.x[i][a] - lo[a] > reach && hi[a] - p.x[i][a] > reach)
        })
        .collect()
}

#[test]
fn owner_stiffness_is_the_bulks_at_every_point() {
    for (dimension, hi) in [("plane_stress", [2.0, 1.2, 0.0]), ("3d", [1.2, 1.0, 1.0])] {
        let scene = body(dimension, "energy", false);
        let disc = disc(&scene);
        let m = model(&scene, &disc);
        assert_eq!(m.unmatched_owners, 0);
        let d = disc.d;
        let inside = interior(&disc, &[0.0; 3], &hi);
        let bulk = (0..disc.points.len()).find(|&i| inside[i]).unwrap();
        // Axis strains and a combination of them: the even moments decide.
        let mut strains = Vec::new();
        for a in 0..d {
            let mut e = [[0.0; 3]; 3];
            e[a][a] = 1e-3;
            strains.push(e);
        }
        let mut mix = [[0.0; 3]; 3];
        for a in 0..d {
            mix[a][a] = [1e-3, -0.4e-3, 0.7e-3][a];
        }
        strains.push(mix);
        let mut worst_plain: f64 = 0.0;
        let plain_scene = body(dimension, "none", false);
        let plain = model(&plain_scene, &disc);
        for eps in &strains {
            let w0 = owner_energy(&m, &disc, bulk, eps);
            for i in 0..disc.points.len() {
                let w = owner_energy(&m, &disc, i, eps);
                assert!(
                    (w / w0 - 1.0).abs() < 1e-9,
                    "{dimension}: point {i} at {:?} stores {w:e} against the bulk's {w0:e}",
                    disc.points.x[i]
                );
                worst_plain = worst_plain.max(1.0 - owner_energy(&plain, &disc, i, eps) / w0);
            }
        }
        // Without the correction a corner point keeps a small part of it.
        assert!(worst_plain > 0.5, "{dimension}: {worst_plain}");
    }
}

#[test]
fn full_families_are_untouched_and_factors_positive() {
    for (dimension, hi) in [("plane_stress", [2.0, 1.2, 0.0]), ("3d", [1.2, 1.0, 1.0])] {
        let scene = body(dimension, "energy", false);
        let disc = disc(&scene);
        let m = model(&scene, &disc);
        let plain = model(&body(dimension, "none", false), &disc);
        assert!(m.surface_factor.iter().all(|&g| g > 0.0 && g.is_finite()));
        let inside = interior(&disc, &[0.0; 3], &hi);
        let mut checked = 0;
        for i in (0..disc.points.len()).filter(|&i| inside[i]) {
            for b in disc.bonds.owned_by(i) {
                assert_eq!(m.surface_factor[b], 1.0);
                assert_eq!(
                    m.bond_weight(&disc, i, b).to_bits(),
                    plain.bond_weight(&disc, i, b).to_bits()
                );
                checked += 1;
            }
        }
        assert!(checked > 0, "{dimension}: no interior bond");
        // The correction does something at the surface.
        assert!(m.surface_factor.iter().any(|&g| g > 1.5));
    }
}

#[test]
fn rigid_motions_give_no_force_and_k_is_symmetric() {
    for (dimension, hole) in [("plane_stress", true), ("3d", false)] {
        let scene = body(dimension, "energy", hole);
        let disc = disc(&scene);
        let m = model(&scene, &disc);
        // A finite rotation about z (nonlinear) and an infinitesimal one (linear), plus a translation.
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let finite: Vec<[f64; 3]> = disc
            .points
            .x
            .iter()
            .map(|x| {
                [
                    c * x[0] - s * x[1] - x[0] + 0.1,
                    s * x[0] + c * x[1] - x[1] - 0.2,
                    0.0,
                ]
            })
            .collect();
        let small: Vec<[f64; 3]> = disc
            .points
            .x
            .iter()
            .map(|x| [-1e-4 * x[1] + 1e-5, 1e-4 * x[0], 0.0])
            .collect();
        // Round-off: a stretch of ~1e-16 of the motion's size on bonds of weight ≤ `unit`.
        for (u, linear, size) in [(&finite, false, 0.3), (&small, true, 1e-4)] {
            let f = internal_forces(&m, &disc, u, linear);
            // Bond-force scale: the largest bond force a unit strain would give.
            let unit: f64 = (0..disc.points.len())
                .map(|i| {
                    disc.bonds
                        .owned_by(i)
                        .map(|b| m.bond_weight(&disc, i, b))
                        .sum::<f64>()
                })
                .fold(0.0, f64::max);
            let worst = f.iter().map(norm).fold(0.0f64, f64::max);
            assert!(
                worst < 1e-12 * unit * size,
                "{dimension} (linear {linear}): force {worst:e} under a rigid motion (scale {unit:e})"
            );
        }
        // K symmetric: every bond adds g k e⊗e symmetrically; checked on the
        // assembled matrix of the 2D body (the 3D one would be 3000² dense).
        if disc.d == 3 {
            continue;
        }
        let k = common::dense_stiffness(&m, &disc);
        let n = k.len();
        let mut asym: f64 = 0.0;
        let mut big: f64 = 0.0;
        for r in 0..n {
            for c in 0..n {
                asym = asym.max((k[r][c] - k[c][r]).abs());
                big = big.max(k[r][c].abs());
            }
        }
        assert!(
            asym <= 1e-14 * big,
            "{dimension}: |K − Kᵀ| {asym:e} of {big:e}"
        );
    }
}

/// Hooke's stress `λ tr(ε) I + 2 μ ε` of Young's modulus `e` and Poisson ratio
/// `nu` in `dimension` (plane stress: `λ = E ν / (1 − ν²)`).
fn hooke(dimension: &str, e: f64, nu: f64, eps: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mu = e / (2.0 * (1.0 + nu));
    let lambda = match dimension {
        "plane_stress" => e * nu / (1.0 - nu * nu),
        _ => e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
    };
    let tr = eps[0][0] + eps[1][1] + eps[2][2];
    let d = if dimension == "3d" { 3 } else { 2 };
    std::array::from_fn(|r| {
        std::array::from_fn(|c| match r < d && c < d {
            true => 2.0 * mu * eps[r][c] + if r == c { lambda * tr } else { 0.0 },
            false => 0.0,
        })
    })
}

fn frobenius(a: &[[f64; 3]; 3]) -> f64 {
    a.iter().flatten().map(|v| v * v).sum::<f64>().sqrt()
}

fn homogeneous(disc: &Discretization, eps: &[[f64; 3]; 3]) -> Vec<[f64; 3]> {
    let p = &disc.points;
    p.x.iter()
        .map(|x| std::array::from_fn(|r| (0..3).map(|c| eps[r][c] * x[c]).sum()))
        .collect()
}

/// The bond-based stress (`model::bond_based`, "Stress") under a homogeneous
/// strain: the full family's at every point of a corrected grid body (it is
/// linear in the owner's fourth moments: 1e-9 as above), the whole tensor at
/// points that see at most one face, and the normal components under strains
/// along the lattice axes at every point, corners included (at an edge or a
/// corner the odd moments, which no positive factor can cancel, couple shear
/// and normal components, as they couple them in the stiffness:
/// `model::surface`); equal to
/// the energy's derivative (`σ : ε = 2 W_i / V_i`, round-off); at the bulk
/// within the lattice's own anisotropy of Hooke's law with the model's
/// Poisson ratio (the square lattice at m = 3 with overlap volumes is +1.6 %
/// in σxx and −3.1 % in σxy under this strain, 2.4 % in norm; the cubic one
/// 1.1 %: below 3 % in norm; the scale is checked exactly on imported points
/// below); and without the correction a corner point reports a small part of it.
#[test]
fn the_bond_based_stress_is_the_bulks_at_every_point() {
    for (dimension, hi, nu) in [
        ("plane_stress", [2.0, 1.2, 0.0], 1.0 / 3.0),
        ("3d", [1.2, 1.0, 1.0], 0.25),
    ] {
        let scene = body(dimension, "energy", false);
        let disc = disc(&scene);
        let m = model(&scene, &disc);
        let plain = model(&body(dimension, "none", false), &disc);
        let d = disc.d;
        let inside = interior(&disc, &[0.0; 3], &hi);
        let bulk = (0..disc.points.len()).find(|&i| inside[i]).unwrap();
        let p = &disc.points;
        let faces_seen = |i: usize| {
            let reach = p.horizon[i] + p.spacing[i];
            (0..d)
                .map(|a| usize::from(p.x[i][a] < reach) + usize::from(hi[a] - p.x[i][a] < reach))
                .sum::<usize>()
        };
        let mut axial = [[0.0; 3]; 3];
        for a in 0..d {
            axial[a][a] = [1e-3, -0.4e-3, 0.7e-3][a];
        }
        let mut eps = axial;
        eps[0][1] = 0.3e-3;
        eps[1][0] = 0.3e-3;
        let mut worst_plain: f64 = 0.0;
        for (strain, on_edges) in [(&axial, true), (&eps, false)] {
            let u = homogeneous(&disc, strain);
            let sigma = |m: &BondBased, i: usize| m.stress(&disc, i, &u).unwrap();
            let s0 = sigma(&m, bulk);
            let size = frobenius(&s0);
            for i in (0..p.len()).filter(|&i| on_edges || faces_seen(i) <= 1) {
                let s = sigma(&m, i);
                let whole = faces_seen(i) <= 1;
                let diff: [[f64; 3]; 3] = std::array::from_fn(|r| {
                    std::array::from_fn(|c| match whole || r == c {
                        true => s[r][c] - s0[r][c],
                        false => 0.0,
                    })
                });
                assert!(
                    frobenius(&diff) < 1e-9 * size,
                    "{dimension}: point {i} at {:?}: σ {s:?} against the bulk's {s0:?}",
                    p.x[i]
                );
                assert!((0..3).all(|r| (0..3).all(|c| s[r][c] == s[c][r])));
                worst_plain = worst_plain.max(1.0 - frobenius(&sigma(&plain, i)) / size);
            }
        }
        let u = homogeneous(&disc, &eps);
        let s0 = m.stress(&disc, bulk, &u).unwrap();
        let work: f64 = (0..3)
            .map(|r| (0..3).map(|c| s0[r][c] * eps[r][c]).sum::<f64>())
            .sum();
        let energy = 2.0 * owner_energy(&m, &disc, bulk, &eps) / disc.points.volume[bulk];
        assert!(
            (work / energy - 1.0).abs() < 1e-12,
            "{dimension}: σ:ε {work:e}, 2W/V {energy:e}"
        );
        let h = hooke(dimension, 2.0e9, nu, &eps);
        let diff: [[f64; 3]; 3] =
            std::array::from_fn(|r| std::array::from_fn(|c| s0[r][c] - h[r][c]));
        let bias = frobenius(&diff) / frobenius(&h);
        assert!(
            bias < 0.03,
            "{dimension}: the bulk's σ {s0:?} against Hooke's {h:?} ({bias:e})"
        );
        assert!(worst_plain > 0.5, "{dimension}: {worst_plain}");
    }
}

/// Imported points are matched to the continuum ball (`model::surface`,
/// "Targets"), whose moments are those 000 Eq. 11 calibrates the micromodulus
/// on: the stress under a homogeneous strain is Hooke's law with the model's
/// Poisson ratio at every point of a point cloud, its faces included (the
/// whole tensor where a point sees at most one face, the normal components
/// everywhere; 1e-9 as above). This is the check of the stress's scale
/// independent of the lattice's bias.
#[test]
fn the_bond_based_stress_of_imported_points_is_hookes() {
    let dir = std::env::temp_dir().join(format!("dhpd_stress_cloud_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("cloud.txt");
    let (h, nx, ny, thickness) = (0.1, 16, 10, 0.01);
    let rows: String = (0..nx * ny)
        .map(|k| {
            let (x, y) = ((k % nx) as f64 * h + 0.05, (k / nx) as f64 * h + 0.05);
            format!("{x} {y} {}\n", h * h * thickness)
        })
        .collect();
    std::fs::write(&file, rows).unwrap();
    let scene = scene(&format!(
        "[model]\ndimension = \"plane_stress\"\nthickness = {thickness}\n\
         [materials.a]\nyoungs_modulus = 2.0e9\n\
         [[point_files]]\npath = \"{}\"\nmaterial = \"a\"\n",
        file.display()
    ));
    let disc = disc(&scene);
    let m = model(&scene, &disc);
    assert_eq!(m.unmatched_owners, 0);
    let p = &disc.points;
    let hi = [nx as f64 * h, ny as f64 * h];
    let faces_seen = |i: usize| {
        let reach = p.horizon[i] + p.spacing[i];
        (0..2)
            .map(|a| usize::from(p.x[i][a] < reach) + usize::from(hi[a] - p.x[i][a] < reach))
            .sum::<usize>()
    };
    let mut axial = [[0.0; 3]; 3];
    axial[0][0] = 1e-3;
    axial[1][1] = -0.4e-3;
    let mut eps = axial;
    eps[0][1] = 0.3e-3;
    eps[1][0] = 0.3e-3;
    for (strain, on_edges) in [(&axial, true), (&eps, false)] {
        let u = homogeneous(&disc, strain);
        let target = hooke("plane_stress", 2.0e9, 1.0 / 3.0, strain);
        let size = frobenius(&target);
        for i in (0..p.len()).filter(|&i| on_edges || faces_seen(i) <= 1) {
            let s = m.stress(&disc, i, &u).unwrap();
            let whole = faces_seen(i) <= 1;
            let miss = (0..2)
                .flat_map(|r| (0..2).map(move |c| (r, c)))
                .filter(|&(r, c)| whole || r == c)
                .map(|(r, c)| (s[r][c] - target[r][c]).abs())
                .fold(0.0, f64::max);
            assert!(
                miss < 1e-9 * size,
                "point {i} at {:?}: σ {s:?}, Hooke {target:?}",
                p.x[i]
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
