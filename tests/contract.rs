//! Model contract tests, generated once and applied to every model and setting:
//! the assembled tangent equals the finite-difference derivative of the
//! nonlinear force; the linearised force is exactly `−K u`; rigid translations
//! and rotations give zero force; internal forces sum to zero; `K` is
//! symmetric where the model claims it.

mod common;

use common::*;
use dhpd::assembly::forces::internal_forces;
use dhpd::assembly::stiffness::row_abs_sums;
use dhpd::discretization::Discretization;
use dhpd::model::bond_based::BondBased;
use dhpd::model::shear::Shear;
use dhpd::model::Model;
use dhpd::scene::Scene;

/// Tangent vs central finite differences of the nonlinear force at the
/// reference configuration. Step `h = 1e-7 × spacing`: the truncation error is
/// O(h²/spacing²) ≈ 1e-14 relative and the cancellation error about
/// 1e-16 × |F| / h, which with |F| ≈ |K| h gives ≈ 1e-9 relative; 1e-6 of the
/// largest entry leaves a wide margin while still catching any wrong term
/// (a wrong sign or factor shows as an O(1) relative difference).
fn check_tangent_fd<M: Model>(model: &M, disc: &Discretization) {
    let d = disc.d;
    let k = dense_stiffness(model, disc);
    let kmax = k.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(kmax > 0.0);
    let h = 1e-7 * disc.points.spacing[0];
    let n = disc.points.len();
    for col in 0..n * d {
        let (p, c) = (col / d, col % d);
        let mut up = vec![[0.0; 3]; n];
        up[p][c] = h;
        let mut um = vec![[0.0; 3]; n];
        um[p][c] = -h;
        let fp = internal_forces(model, disc, &up, false);
        let fm = internal_forces(model, disc, &um, false);
        for row in 0..n * d {
            let fd = -(fp[row / d][row % d] - fm[row / d][row % d]) / (2.0 * h);
            assert!(
                (fd - k[row][col]).abs() <= 1e-6 * kmax,
                "K[{row}][{col}] = {:e} but finite differences give {fd:e}",
                k[row][col]
            );
        }
    }
}

/// The linearised force is `−K u` to round-off, and the nonlinear force agrees
/// with it to O(|u|/spacing) relative: with |u| = 1e-6 spacing the difference
/// must be below 1e-4 of |K u| (a missing geometric term would not be).
fn check_linear_consistency<M: Model>(model: &M, disc: &Discretization) {
    let d = disc.d;
    let n = disc.points.len();
    let k = dense_stiffness(model, disc);
    let mut rng = Rng::new(7);
    let scale = 1e-6 * disc.points.spacing[0];
    let u: Vec<[f64; 3]> = (0..n)
        .map(|_| std::array::from_fn(|a| if a < d { scale * rng.next() } else { 0.0 }))
        .collect();
    let flat: Vec<f64> = u.iter().flat_map(|x| x[..d].to_vec()).collect();
    let ku: Vec<f64> = k
        .iter()
        .map(|row| row.iter().zip(&flat).map(|(a, b)| a * b).sum())
        .collect();
    let kumax = ku.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let lin = internal_forces(model, disc, &u, true);
    let non = internal_forces(model, disc, &u, false);
    for i in 0..n * d {
        let (p, c) = (i / d, i % d);
        assert!(
            (lin[p][c] + ku[i]).abs() <= 1e-12 * kumax,
            "linear force differs from -K u at dof {i}"
        );
        assert!(
            (non[p][c] + ku[i]).abs() <= 1e-4 * kumax,
            "nonlinear force differs from -K u at dof {i}"
        );
    }
}

/// Rigid translation (any size) and rotation: zero force. The linearised force
/// must vanish for an infinitesimal rotation `u = Ω x`, the nonlinear one for a
/// finite rotation of 30°. Tolerance: 1e-10 of the force a unit strain of the
/// same displacement scale would produce (round-off of sums over ~100 bonds).
fn check_rigid_motion<M: Model>(model: &M, disc: &Discretization) {
    let d = disc.d;
    let n = disc.points.len();
    let x = &disc.points.x;
    let stretch: Vec<[f64; 3]> = x.iter().map(|p| [1e-3 * p[0], 0.0, 0.0]).collect();
    let reference = max_abs(&internal_forces(model, disc, &stretch, true), d) / 1e-3;
    assert!(reference > 0.0);
    let translation: Vec<[f64; 3]> = (0..n)
        .map(|_| std::array::from_fn(|a| if a < d { 0.37 * (a as f64 + 1.0) } else { 0.0 }))
        .collect();
    for linear in [true, false] {
        let f = internal_forces(model, disc, &translation, linear);
        assert!(
            max_abs(&f, d) <= 1e-10 * reference,
            "translation gives force (linear = {linear})"
        );
    }
    if d == 1 {
        return;
    }
    let axis = if d == 2 {
        [0.0, 0.0, 1.0]
    } else {
        [1.0 / 3f64.sqrt(); 3]
    };
    let w = 1e-3;
    let small: Vec<[f64; 3]> = x
        .iter()
        .map(|p| std::array::from_fn(|a| w * dhpd::vector::cross(&axis, p)[a]))
        .collect();
    let f = internal_forces(model, disc, &small, true);
    assert!(
        max_abs(&f, d) <= 1e-10 * reference * w,
        "infinitesimal rotation gives linearised force"
    );
    let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
    let finite: Vec<[f64; 3]> = x
        .iter()
        .map(|p| {
            // Rodrigues: R p − p.
            let kxp = dhpd::vector::cross(&axis, p);
            let kdp = dhpd::vector::dot(&axis, p);
            std::array::from_fn(|a| c * p[a] + s * kxp[a] + (1.0 - c) * kdp * axis[a] - p[a])
        })
        .collect();
    let f = internal_forces(model, disc, &finite, false);
    assert!(
        max_abs(&f, d) <= 1e-10 * reference,
        "finite rotation gives nonlinear force"
    );
}

/// Internal forces sum to zero for an arbitrary displacement (Newton's third
/// law, bond by bond): 1e-12 of the sum of magnitudes.
fn check_zero_net_force<M: Model>(model: &M, disc: &Discretization) {
    let d = disc.d;
    let mut rng = Rng::new(11);
    let scale = 0.05 * disc.points.spacing[0];
    let u: Vec<[f64; 3]> = (0..disc.points.len())
        .map(|_| std::array::from_fn(|a| if a < d { scale * rng.next() } else { 0.0 }))
        .collect();
    for linear in [true, false] {
        let f = internal_forces(model, disc, &u, linear);
        for c in 0..d {
            let sum: f64 = f.iter().map(|v| v[c]).sum();
            let mag: f64 = f.iter().map(|v| v[c].abs()).sum();
            assert!(
                sum.abs() <= 1e-12 * mag,
                "net force {sum:e} in component {c} (linear = {linear})"
            );
        }
    }
}

/// `K = Kᵀ` to round-off (bond-based: each bond block is symmetric).
fn check_symmetric<M: Model>(model: &M, disc: &Discretization) {
    let k = dense_stiffness(model, disc);
    let kmax = k.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    for (r, row) in k.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            assert!(
                (v - k[c][r]).abs() <= 1e-14 * kmax,
                "K[{r}][{c}] != K[{c}][{r}]"
            );
        }
    }
}

/// The matrix-free Gershgorin row sums (the explicit driver's stable time step)
/// equal `Σ_c |K_rc|` of the assembled tangent, to round-off of the sum.
fn check_row_sums<M: Model>(model: &M, disc: &Discretization) {
    let d = disc.d;
    let k = dense_stiffness(model, disc);
    let sums = row_abs_sums(model, disc);
    for (r, row) in k.iter().enumerate() {
        let expected: f64 = row.iter().map(|v| v.abs()).sum();
        let got = sums[r / d][r % d];
        assert!(
            (got - expected).abs() <= 1e-12 * expected,
            "row {r}: matrix-free {got:e}, assembled {expected:e}"
        );
    }
}

fn bond_based(scene: &Scene, disc: &Discretization) -> BondBased {
    BondBased::new(
        disc,
        scene.model.dimension,
        &scene.materials,
        scene.model.thickness,
    )
}

/// Generates the contract tests for one model constructor over every setting,
/// with and without a horizon jump.
macro_rules! contract_tests {
    ($module:ident, $build:expr, $extra:expr, symmetric = $sym:expr, settings = [$($setting:literal),*]) => {
        mod $module {
            use super::*;
            fn each(check: impl Fn(&Scene, &Discretization)) {
                for setting in [$($setting),*] {
                    for jump in [false, true] {
                        let scene = small_body(setting, jump, $extra);
                        let disc = disc(&scene);
                        check(&scene, &disc);
                    }
                }
            }
            #[test]
            fn tangent_equals_finite_differences() {
                each(|s, d| check_tangent_fd(&$build(s, d), d));
            }
            #[test]
            fn linear_force_is_minus_k_u() {
                each(|s, d| check_linear_consistency(&$build(s, d), d));
            }
            #[test]
            fn rigid_motion_gives_zero_force() {
                each(|s, d| check_rigid_motion(&$build(s, d), d));
            }
            #[test]
            fn forces_sum_to_zero() {
                each(|s, d| check_zero_net_force(&$build(s, d), d));
            }
            #[test]
            fn matrix_free_row_sums() {
                each(|s, d| check_row_sums(&$build(s, d), d));
            }
            #[test]
            fn symmetry() {
                if $sym {
                    each(|s, d| check_symmetric(&$build(s, d), d));
                }
            }
        }
    };
}

/// The bond-based model with the scene's surface correction.
fn bond_based_corrected(scene: &Scene, disc: &Discretization) -> BondBased {
    BondBased::new(
        disc,
        scene.model.dimension,
        &scene.materials,
        scene.model.thickness,
    )
    .with_surface_correction(
        disc,
        scene.discretization.volume_correction,
        scene.model.thickness,
        !scene.cracks.is_empty(),
    )
}

contract_tests!(
    bond_based_surface_corrected,
    bond_based_corrected,
    "",
    symmetric = true,
    settings = ["1d", "plane_stress", "plane_strain", "3d"]
);

contract_tests!(
    bond_based_model,
    bond_based,
    "",
    symmetric = true,
    settings = ["1d", "plane_stress", "plane_strain", "3d"]
);

/// The shear model the scene names (its formulation and dilatation).
fn shear(scene: &Scene, disc: &Discretization) -> Shear {
    Shear::of(scene, disc).expect("shape tensors are regular")
}

contract_tests!(
    shear_model,
    shear,
    "kind = \"shear\"\nformulation = \"paper\"",
    symmetric = false,
    settings = ["plane_stress", "plane_strain", "3d"]
);

contract_tests!(
    shear_model_gradient_dilatation,
    shear,
    "kind = \"shear\"\nformulation = \"paper\"\ndilatation = \"gradient\"",
    symmetric = false,
    settings = ["plane_stress", "plane_strain", "3d"]
);

contract_tests!(
    shear_model_energy,
    shear,
    "kind = \"shear\"\nformulation = \"energy\"",
    symmetric = true,
    settings = ["plane_stress", "plane_strain", "3d"]
);
