//! Shear-deformation model (seed 001): patch test with exact Hooke stress for
//! several Poisson ratios, rigid rotations (001 Sec. 6.2), singular shape tensors.

mod common;

use common::{disc, scene};
use dhpd::assembly::forces::internal_forces;
use dhpd::discretization::partial_volume::PartialVolume;
use dhpd::discretization::Discretization;
use dhpd::model::shear::Shear;
use dhpd::scene::Scene;

const E: f64 = 30e9;

fn plate(dimension: &str, nu: f64, spacing: f64, size: [f64; 3], dilatation: &str) -> Scene {
    block(
        dimension,
        nu,
        spacing,
        size,
        &format!("formulation = \"paper\"\ndilatation = \"{dilatation}\"\n"),
    )
}

/// A shear-model block `[0, size]` on a grid of `spacing`, with further `[model]` lines.
fn block(dimension: &str, nu: f64, spacing: f64, size: [f64; 3], model_lines: &str) -> Scene {
    let (lo, hi) = if dimension == "3d" {
        (
            "[0.0, 0.0, 0.0]".to_string(),
            format!("[{}, {}, {}]", size[0], size[1], size[2]),
        )
    } else {
        (
            "[0.0, 0.0]".to_string(),
            format!("[{}, {}]", size[0], size[1]),
        )
    };
    scene(&format!(
        "[model]\ndimension = \"{dimension}\"\nkind = \"shear\"\n{model_lines}[materials.m]\nyoungs_modulus = {E}\npoisson_ratio = {nu}\n\
         [[regions]]\nmaterial = \"m\"\nspacing = {spacing}\nbox = {{ min = {lo}, max = {hi} }}\n"
    ))
}

/// Hooke's law from the Lamé constants of the setting, written independently of
/// the code's bulk moduli: plane stress λ = Eν/(1−ν²), plane strain and 3D
/// λ = Eν/((1+ν)(1−2ν)); μ = E/(2(1+ν)).
fn hooke(dimension: &str, nu: f64, strain: &[[f64; 3]; 3], d: usize) -> [[f64; 3]; 3] {
    let mu = E / (2.0 * (1.0 + nu));
    let lambda = if dimension == "plane_stress" {
        E * nu / (1.0 - nu * nu)
    } else {
        E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    };
    let trace: f64 = (0..d).map(|a| strain[a][a]).sum();
    std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            if r < d && c < d {
                lambda * trace * f64::from(r == c) + 2.0 * mu * strain[r][c]
            } else {
                0.0
            }
        })
    })
}

/// The shear model of a scene (its shape tensors are regular in these tests).
fn shear_model(scene: &Scene, disc: &Discretization) -> Shear {
    Shear::of(scene, disc).unwrap()
}

/// `u = H x` on the first `d` components.
fn affine(disc: &Discretization, h: &[[f64; 3]; 3]) -> Vec<[f64; 3]> {
    let d = disc.d;
    disc.points
        .x
        .iter()
        .map(|x| {
            std::array::from_fn(|a| {
                if a < d {
                    (0..d).map(|b| h[a][b] * x[b]).sum()
                } else {
                    0.0
                }
            })
        })
        .collect()
}

/// Points whose horizon (plus the bond reach) stays inside the body.
fn interior(disc: &Discretization, scene: &Scene) -> Vec<usize> {
    let pv = PartialVolume {
        rule: scene.discretization.volume_correction,
        d: disc.d,
    };
    let p = &disc.points;
    let lo: Vec<f64> = (0..disc.d)
        .map(|a| p.x.iter().map(|x| x[a]).fold(f64::INFINITY, f64::min))
        .collect();
    let hi: Vec<f64> = (0..disc.d)
        .map(|a| p.x.iter().map(|x| x[a]).fold(f64::NEG_INFINITY, f64::max))
        .collect();
    (0..p.len())
        .filter(|&i| {
            let reach = 2.0 * (p.horizon[i] + pv.reach(p.spacing[i]));
            (0..disc.d).all(|a| {
                p.x[i][a] - lo[a] + 0.5 * p.spacing[i] > reach
                    && hi[a] - p.x[i][a] + 0.5 * p.spacing[i] > reach
            })
        })
        .collect()
}

/// A homogeneous displacement gradient (strain plus rotation) gives zero force at
/// interior points (to 1e-11 of the largest, boundary, force: the round-off of
/// the family sums is about 1e-15 of it) and the exact Hooke stress there (to 1e-10 relative), for
/// ν from −0.3 to 0.4999 (near incompressibility: λ/μ up to 5000; both sides of
/// each check scale with λ, so the relative tolerances stay). "Interior" means two horizons from the boundary: the force
/// on a point also involves the families of its neighbours.
#[test]
fn patch_test_exact_hooke_stress() {
    let gradient = [
        [1.0e-4, 3.0e-5, -2.0e-5],
        [-1.0e-5, -4.0e-5, 1.5e-5],
        [2.5e-5, 0.5e-5, 6.0e-5],
    ];
    for (dimension, size, spacing) in [
        ("plane_stress", [2.0, 2.0, 0.0], 0.1),
        ("plane_strain", [2.0, 2.0, 0.0], 0.1),
        ("3d", [1.8, 1.8, 1.8], 0.1),
    ] {
        for (nu, dilatation) in [-0.3, 0.0, 0.25, 1.0 / 3.0, 0.45, 0.49, 0.499, 0.4999]
            .into_iter()
            .flat_map(|nu| [(nu, "weighted"), (nu, "gradient")])
        {
            let scene = plate(dimension, nu, spacing, size, dilatation);
            let disc = disc(&scene);
            let d = disc.d;
            let model = shear_model(&scene, &disc);
            let u = affine(&disc, &gradient);
            let strain: [[f64; 3]; 3] = std::array::from_fn(|r| {
                std::array::from_fn(|c| 0.5 * (gradient[r][c] + gradient[c][r]))
            });
            let expected = hooke(dimension, nu, &strain, d);
            let scale = expected
                .iter()
                .flatten()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            let inner = interior(&disc, &scene);
            assert!(!inner.is_empty(), "{dimension}: no interior point");
            let f = internal_forces(&model, &disc, &u, true);
            let fmax = f
                .iter()
                .flat_map(|v| v.iter())
                .fold(0.0f64, |m, v| m.max(v.abs()));
            let (mut worst_force, mut worst_stress) = (0.0f64, 0.0f64);
            for &i in &inner {
                let fi = f[i].iter().fold(0.0f64, |m, v| m.max(v.abs()));
                worst_force = worst_force.max(fi / fmax);
                assert!(
                    fi <= 1e-11 * fmax,
                    "{dimension} ν={nu}: force {fi:e} at interior point {i} (boundary {fmax:e})"
                );
                let sigma = model.stress_at(&disc, i, &u, true);
                for r in 0..d {
                    for c in 0..d {
                        worst_stress =
                            worst_stress.max((sigma[r][c] - expected[r][c]).abs() / scale);
                        assert!(
                            (sigma[r][c] - expected[r][c]).abs() <= 1e-10 * scale,
                            "{dimension} ν={nu}: σ[{r}][{c}] = {:e}, Hooke {:e}",
                            sigma[r][c],
                            expected[r][c]
                        );
                    }
                }
            }
            eprintln!(
                "patch {dimension} ν={nu} {dilatation}: interior force {worst_force:.1e} of the largest, \
                 stress error {worst_stress:.1e} of max|σ|, {} interior points",
                inner.len()
            );
        }
    }
}

/// 001 Sec. 6.2: rigid rotations give zero stress at every point, boundary
/// included. Linearised model, infinitesimal rotation: to round-off. Nonlinear
/// model, finite rotations in 15° steps (2D, 1 m × 1 m) and 30° steps about
/// (1,1,1) (3D, 1 × 1 × 0.2 m), E = 30 GPa: the paper reports at most 3e-3 Pa (2D)
/// and 10 Pa (3D); we require the same bounds.
#[test]
fn rigid_rotation_gives_zero_stress() {
    for (dimension, size, spacing, step, bound) in [
        ("plane_stress", [1.0, 1.0, 0.0], 0.05, 15.0, 3e-3),
        ("3d", [1.0, 1.0, 0.2], 0.05, 30.0, 10.0),
    ] {
        for dilatation in ["weighted", "gradient"] {
            let scene = plate(dimension, 1.0 / 3.0, spacing, size, dilatation);
            let disc = disc(&scene);
            let model = shear_model(&scene, &disc);
            let axis = if dimension == "3d" {
                [1.0 / 3f64.sqrt(); 3]
            } else {
                [0.0, 0.0, 1.0]
            };
            let rotate = |angle: f64| -> Vec<[f64; 3]> {
                let (s, c) = (angle.to_radians().sin(), angle.to_radians().cos());
                disc.points
                    .x
                    .iter()
                    .map(|p| {
                        let kxp = dhpd::vector::cross(&axis, p);
                        let kdp = dhpd::vector::dot(&axis, p);
                        std::array::from_fn(|a| {
                            c * p[a] + s * kxp[a] + (1.0 - c) * kdp * axis[a] - p[a]
                        })
                    })
                    .collect()
            };
            let mut worst: f64 = 0.0;
            for k in 1..=(360.0 / step) as usize {
                let u = rotate(step * k as f64);
                for i in 0..disc.points.len() {
                    let sigma = model.stress_at(&disc, i, &u, false);
                    worst = worst.max(sigma.iter().flatten().fold(0.0, |m: f64, v| m.max(v.abs())));
                }
            }
            eprintln!("{dimension}: largest stress under finite rigid rotations {worst:.2e} Pa (paper: {bound:e} Pa)");
            assert!(worst <= bound, "{dimension}: {worst:e} Pa");
            // Infinitesimal rotation u = ω a × x (|ω| = 1e-4), linearised model: zero to
            // round-off, 1e-6 of the stress E ω a strain of the same size would give.
            let small: Vec<[f64; 3]> = disc
                .points
                .x
                .iter()
                .map(|p| dhpd::vector::cross(&axis, p).map(|v| 1e-4 * v))
                .collect();
            let mut lin: f64 = 0.0;
            for i in 0..disc.points.len() {
                let sigma = model.stress_at(&disc, i, &small, true);
                lin = lin.max(sigma.iter().flatten().fold(0.0, |m: f64, v| m.max(v.abs())));
            }
            assert!(
                lin <= 1e-6 * E * 1e-4,
                "{dimension}: linearised stress {lin:e} Pa under an infinitesimal rotation"
            );
        }
    }
}

/// An owner whose bonds all lie on one line has a singular shape tensor: the
/// error names the point.
#[test]
fn singular_shape_tensor_is_reported() {
    // A single row of points: every family is collinear.
    let scene = scene(
        "[model]\ndimension = \"plane_stress\"\nkind = \"shear\"\n[materials.m]\nyoungs_modulus = 1e9\npoisson_ratio = 0.3\n\
         [[regions]]\nmaterial = \"m\"\nspacing = 0.1\nbox = { min = [0.0, 0.0], max = [1.0, 0.1] }\n",
    );
    let disc = disc(&scene);
    let err = Shear::of(&scene, &disc).unwrap_err();
    assert!(err.to_string().contains("shape tensor of point"), "{err}");
}

/// The surface correction (`dilatation = "gradient"`) makes the recovered stress
/// exact under a homogeneous strain at every point, boundary points included
/// (to 1e-9 of |σ|); the paper's weighted dilatation is exact only where the
/// family is full, and is measurably off at the edges (shown for contrast).
#[test]
fn gradient_dilatation_is_exact_at_boundaries() {
    let strain = [[1.0e-4, 2.0e-5, 0.0], [2.0e-5, -3.0e-5, 0.0], [0.0; 3]];
    let mut worst = [0.0f64; 2];
    for (k, dilatation) in ["gradient", "weighted"].into_iter().enumerate() {
        let scene = plate("plane_stress", 0.3, 0.1, [1.0, 1.0, 0.0], dilatation);
        let disc = disc(&scene);
        let model = shear_model(&scene, &disc);
        let u = affine(&disc, &strain);
        let expected = hooke("plane_stress", 0.3, &strain, 2);
        let scale = expected
            .iter()
            .flatten()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..disc.points.len() {
            let sigma = model.stress_at(&disc, i, &u, true);
            for r in 0..2 {
                for c in 0..2 {
                    worst[k] = worst[k].max((sigma[r][c] - expected[r][c]).abs() / scale);
                }
            }
        }
    }
    eprintln!(
        "largest stress error under homogeneous strain: gradient {:.1e}, weighted {:.1e}",
        worst[0], worst[1]
    );
    assert!(worst[0] < 1e-9);
    assert!(worst[1] > 1e-3);
}

/// Surface stiffening of the shear model (validation/bimaterial_bar/README.md,
/// "Shear model: reaction and surface stiffening"). A strip of height H, every
/// point column held at `u_x = εx` (no end supports), `u_y` free: a homogeneous
/// stretch, so each owner's linearised gradient is exactly ε and its force flux
/// `P = (d/m)[(κ − 2μ/d)θK + 2μ εK]`. With ν = 0 (or the gradient dilatation,
/// where θ = tr ε) the flux along the strip is `Eε(1 + α)`, `α = (K_xx − K_yy)/m`
/// of the owner's truncated family, so the force through a cut is
/// `Eε Δx Σ_rows (1 + α_row)`: computed here from the bonds' geometry alone and
/// compared with the cut force the solver produces (minus the reactions of the
/// columns left of the cut) to 1e-9. The excess over `EεH` (6.8 % at H = 10Δx)
/// is the formulation's, not a defect.
#[test]
fn the_strip_section_is_stiffer_by_the_rim_anisotropy() {
    let (h, rows, columns, strain) = (0.01, 10usize, 60usize, 1e-4);
    for (nu, dilatation) in [(0.0, "weighted"), (1.0 / 3.0, "gradient")] {
        let mut text = format!(
            "[model]\ndimension = \"plane_stress\"\nkind = \"shear\"\nformulation = \"paper\"\ndilatation = \"{dilatation}\"\n\
             [materials.m]\nyoungs_modulus = 1.0\npoisson_ratio = {nu}\n\
             [[regions]]\nmaterial = \"m\"\nspacing = {h}\nbox = {{ min = [0.0, 0.0], max = [{}, {}] }}\n\
             [[boundary]]\nname = \"pin\"\nbox = {{ min = [0.0, 0.0], max = [{h}, {h}] }}\ndisplacement = {{ y = 0.0 }}\n",
            h * columns as f64,
            h * rows as f64
        );
        for k in 0..columns {
            let x = (k as f64 + 0.5) * h;
            text += &format!(
                "[[boundary]]\nname = \"c{k}\"\nbox = {{ min = [{}, 0.0], max = [{}, {}] }}\n\
                 displacement = {{ x = {} }}\n",
                x - 0.25 * h,
                x + 0.25 * h,
                h * rows as f64,
                strain * x
            );
        }
        let s = dhpd::drivers::static_solve::solve(&scene(&text)).unwrap();
        let cut: f64 = -(0..columns / 2)
            .map(|k| s.reaction(&format!("c{k}")).unwrap()[0])
            .sum::<f64>();
        // α of each row from a point at the middle of the strip.
        let d = &s.disc;
        let mut predicted = 0.0;
        for r in 0..rows {
            let y = (r as f64 + 0.5) * h;
            let i = (0..d.points.len())
                .find(|&i| {
                    (d.points.x[i][0] - 0.5 * h * columns as f64 - 0.5 * h).abs() < 1e-9
                        && (d.points.x[i][1] - y).abs() < 1e-9
                })
                .unwrap();
            let (mut m, mut kxx, mut kyy) = (0.0, 0.0, 0.0);
            for b in d.bonds.owned_by(i) {
                let j = d.bonds.neighbour[b] as usize;
                let xi = [
                    d.points.x[j][0] - d.points.x[i][0],
                    d.points.x[j][1] - d.points.x[i][1],
                ];
                let w = d.points.volume[j] * d.bonds.volume_factor[b];
                let l2 = xi[0] * xi[0] + xi[1] * xi[1];
                m += w;
                kxx += w * xi[0] * xi[0] / l2;
                kyy += w * xi[1] * xi[1] / l2;
            }
            predicted += strain * h * (1.0 + (kxx - kyy) / m);
        }
        assert!(
            (cut / predicted - 1.0).abs() < 1e-9,
            "ν = {nu}, {dilatation}: cut force {cut:e}, predicted {predicted:e}"
        );
        let excess = cut / (strain * h * rows as f64) - 1.0;
        assert!(excess > 0.06 && excess < 0.075, "section excess {excess}");
    }
}

/// The energy formulation (`model.formulation = "energy"`, src/model/shear.rs):
/// a scene of the plate with that formulation.
fn energy_plate(dimension: &str, nu: f64, spacing: f64, size: [f64; 3]) -> Scene {
    block(dimension, nu, spacing, size, "formulation = \"energy\"\n")
}

/// Energy formulation: under any homogeneous displacement gradient the
/// recovered stress is Hooke's law at every point, surface, edge and corner
/// points included (to 1e-10 of |σ|: its gradient is exact for affine fields
/// in any family), and the interior forces vanish as in the paper's model.
#[test]
fn energy_formulation_is_exact_at_every_point() {
    let gradient = [
        [1.0e-4, 3.0e-5, -2.0e-5],
        [-1.0e-5, -4.0e-5, 1.5e-5],
        [2.5e-5, 0.5e-5, 6.0e-5],
    ];
    for (dimension, size) in [
        ("plane_stress", [1.2, 1.0, 0.0]),
        ("plane_strain", [1.2, 1.0, 0.0]),
        ("3d", [1.4, 1.4, 1.4]),
    ] {
        for nu in [-0.3, 0.0, 1.0 / 3.0, 0.49] {
            let scene = energy_plate(dimension, nu, 0.1, size);
            let disc = disc(&scene);
            let d = disc.d;
            let model = shear_model(&scene, &disc);
            let u = affine(&disc, &gradient);
            let strain: [[f64; 3]; 3] = std::array::from_fn(|r| {
                std::array::from_fn(|c| 0.5 * (gradient[r][c] + gradient[c][r]))
            });
            let expected = hooke(dimension, nu, &strain, d);
            let scale = expected
                .iter()
                .flatten()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            for i in 0..disc.points.len() {
                let sigma = model.stress_at(&disc, i, &u, true);
                for r in 0..d {
                    for c in 0..d {
                        assert!(
                            (sigma[r][c] - expected[r][c]).abs() <= 1e-10 * scale,
                            "{dimension} ν={nu}: point {i} at {:?}: σ[{r}][{c}] = {:e}, Hooke {:e}",
                            disc.points.x[i],
                            sigma[r][c],
                            expected[r][c]
                        );
                    }
                }
            }
            let f = internal_forces(&model, &disc, &u, true);
            let fmax = f.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            for &i in &interior(&disc, &scene) {
                let fi = f[i].iter().fold(0.0f64, |m, v| m.max(v.abs()));
                assert!(
                    fi <= 1e-11 * fmax,
                    "{dimension} ν={nu}: interior force {fi:e}"
                );
            }
        }
    }
}

/// Where the family is full, the energy formulation's linearised bond forces
/// are the paper's (formulation Sec. 4): the same owner forces for any
/// displacement, to round-off (1e-12 of the largest), while at the surface
/// they differ (the paper's force is not the derivative of an energy there).
#[test]
fn energy_formulation_equals_the_papers_force_in_full_families() {
    for dimension in ["plane_stress", "3d"] {
        let size = if dimension == "3d" {
            [1.4, 1.4, 1.4]
        } else {
            [1.6, 1.6, 0.0]
        };
        let energy_scene = energy_plate(dimension, 0.3, 0.1, size);
        let disc = disc(&energy_scene);
        let paper_scene = plate(dimension, 0.3, 0.1, size, "weighted");
        let energy = shear_model(&energy_scene, &disc);
        let paper = shear_model(&paper_scene, &disc);
        let mut rng = common::Rng::new(3);
        let u: Vec<[f64; 3]> = (0..disc.points.len())
            .map(|_| std::array::from_fn(|a| if a < disc.d { 1e-5 * rng.next() } else { 0.0 }))
            .collect();
        // Owners whose own family is full (one horizon plus the reach inside).
        let p = &disc.points;
        let full: Vec<usize> = (0..p.len())
            .filter(|&i| {
                let reach = p.horizon[i] + p.spacing[i];
                (0..disc.d).all(|a| {
                    p.x[i][a] - 0.5 * p.spacing[i] >= reach - 1e-12
                        && size[a] - p.x[i][a] - 0.5 * p.spacing[i] >= reach - 1e-12
                })
            })
            .collect();
        let (mut worst_full, mut worst_rim, mut largest) = (0.0f64, 0.0f64, 0.0f64);
        let inner: std::collections::HashSet<usize> = full.iter().copied().collect();
        for i in 0..disc.points.len() {
            let r = disc.bonds.owned_by(i);
            let mut fe = vec![[0.0; 3]; r.len()];
            let mut fp = vec![[0.0; 3]; r.len()];
            dhpd::model::Model::owner_forces(&energy, &disc, i, &u, true, &mut fe);
            dhpd::model::Model::owner_forces(&paper, &disc, i, &u, true, &mut fp);
            for (a, b) in fe.iter().zip(&fp) {
                let diff = (0..3).map(|c| (a[c] - b[c]).abs()).fold(0.0, f64::max);
                largest = largest.max(b.iter().fold(0.0f64, |m, v| m.max(v.abs())));
                if inner.contains(&i) {
                    worst_full = worst_full.max(diff);
                } else {
                    worst_rim = worst_rim.max(diff);
                }
            }
        }
        assert!(!full.is_empty());
        assert!(
            worst_full <= 1e-12 * largest,
            "{dimension}: {worst_full:e} of {largest:e}"
        );
        assert!(
            worst_rim > 1e-3 * largest,
            "{dimension}: rim forces equal too ({worst_rim:e})"
        );
    }
}

/// Energy formulation, finite rigid rotations (001 Sec. 6.2's test): zero
/// stress at every point within the paper's bounds (3e-3 Pa in 2D, 10 Pa in
/// 3D, E = 30 GPa), as `rigid_rotation_gives_zero_stress` requires of its force.
#[test]
fn energy_formulation_rigid_rotation_gives_zero_stress() {
    for (dimension, size, bound) in [
        ("plane_stress", [1.0, 1.0, 0.0], 3e-3),
        ("3d", [1.0, 1.0, 0.2], 10.0),
    ] {
        let scene = energy_plate(dimension, 1.0 / 3.0, 0.05, size);
        let disc = disc(&scene);
        let model = shear_model(&scene, &disc);
        let axis = if dimension == "3d" {
            [1.0 / 3f64.sqrt(); 3]
        } else {
            [0.0, 0.0, 1.0]
        };
        let mut worst: f64 = 0.0;
        for k in 1..=12 {
            let (s, c) = (
                (30.0 * k as f64).to_radians().sin(),
                (30.0 * k as f64).to_radians().cos(),
            );
            let u: Vec<[f64; 3]> = disc
                .points
                .x
                .iter()
                .map(|p| {
                    let kxp = dhpd::vector::cross(&axis, p);
                    let kdp = dhpd::vector::dot(&axis, p);
                    std::array::from_fn(|a| {
                        c * p[a] + s * kxp[a] + (1.0 - c) * kdp * axis[a] - p[a]
                    })
                })
                .collect();
            for i in 0..disc.points.len() {
                let sigma = model.stress_at(&disc, i, &u, false);
                worst = worst.max(sigma.iter().flatten().fold(0.0, |m: f64, v| m.max(v.abs())));
            }
        }
        eprintln!("energy formulation, {dimension}: largest stress under finite rigid rotations {worst:.2e} Pa");
        assert!(
            worst <= bound,
            "{dimension}: {worst:e} Pa under finite rigid rotations"
        );
    }
}
