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
//! - the assembled stiffness is symmetric.

mod common;

use common::{disc, scene};
use dhpd::assembly::forces::internal_forces;
use dhpd::discretization::Discretization;
use dhpd::model::bond_based::BondBased;
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
