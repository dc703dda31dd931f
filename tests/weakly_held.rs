//! Weakly held points (issue 4): a point held by a single bond, a point whose
//! bonds are all cut by a pre-crack, and a thin ligament. Each must give either
//! a clear error naming the point that can move, or an answer that passes its
//! checks — never a silent wrong answer.
//!
//! The body is a 0.2 m × 0.1 m plane-stress plate (spacing 0.01 m, δ = 3.015 Δx,
//! points at cell centres), clamped on the left and pulled on the right; the
//! extra point comes from a point file. The partial-volume correction is off in
//! the single-bond cases so that "one bond" is exact: with it, bonds reach
//! δ + r_j and the extra point would pick up the diagonal neighbours too.
//!
//! Expected, from the bond geometry alone:
//! - single bond along x: the bond-based stiffness of the point is `c ξ⊗ξ/|ξ|³`,
//!   rank one, so its y-row is exactly zero → a non-positive pivot at that point,
//!   component y;
//! - single bond at 45°: the same rank-one block in a rotated frame; the pivot of
//!   the second component is zero up to round-off → singular to round-off (or a
//!   non-positive pivot) at that point;
//! - the shear model: one bond cannot span the plane → singular shape tensor
//!   named at that point;
//! - every bond cut by a pre-crack: an isolated point, named by default; with
//!   `isolated_points = "remove"` the answer equals that of the plate without
//!   the point (to round-off), since a bondless point carries no force;
//! - a ligament one point thick and longer than 2δ: its middle points have only
//!   bonds along x → zero transverse stiffness → the pivot check names a
//!   ligament point; two points thick: triangulated, so it solves, with
//!   residual < 1e-10 and the reaction balancing the applied traction to 1e-10.

use dhpd::drivers::static_solve::{solve, StaticSolution};
use dhpd::error::{Error, NumericalError};
use dhpd::scene::{parse_spec, Scene};
use std::path::{Path, PathBuf};

/// The plate; `model` and `discretization` are extra lines for those sections.
fn plate(model: &str, discretization: &str) -> String {
    format!(
        r#"
[model]
dimension = "plane_stress"
thickness = 0.01
{model}

[discretization]
{discretization}

[materials.steel]
youngs_modulus = 2.0e11
poisson_ratio = 0.3333333333333333

[[regions]]
material = "steel"
spacing = 0.01
box = {{ min = [0.0, 0.0], max = [0.2, 0.1] }}

[[boundary]]
name = "left"
box = {{ min = [0.0, 0.0], max = [0.03, 0.1] }}
displacement = {{ x = 0.0, y = 0.0 }}

[[loads]]
name = "pull"
kind = "traction"
face = "+x"
box = {{ min = [0.19, 0.0], max = [0.2, 0.1] }}
value = [1.0e6, 0.0]
"#
    )
}

/// Partial volumes off, so that "one bond" is exact.
const NO_CORRECTION: &str = "volume_correction = \"none\"";

/// A scratch directory removed on drop.
struct Scratch(PathBuf);

impl Scratch {
    fn new(tag: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("dhpd_weakly_held_{tag}_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Solves `text` with an optional point file `extra.xyz` (rows
/// `x y volume [horizon]`) and extra TOML appended.
fn run(
    tag: &str,
    text: String,
    points: Option<&str>,
    extra: &str,
) -> Result<StaticSolution, Error> {
    let scratch = Scratch::new(tag);
    let mut text = text;
    if let Some(rows) = points {
        std::fs::write(scratch.0.join("extra.xyz"), rows).unwrap();
        text.push_str("\n[[point_files]]\npath = \"extra.xyz\"\nmaterial = \"steel\"\n");
    }
    text.push_str(extra);
    let scene = Scene::try_from_spec(parse_spec(&text, false).unwrap(), &scratch.0, tag).unwrap();
    solve(&scene)
}

fn close(a: [f64; 3], b: [f64; 2]) -> bool {
    (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
}

/// The extra point 0.04 m from the edge point (0.195, 0.055) along x; its own
/// horizon 0.0405 m holds only that point (the diagonal ones are 0.0412 m away),
/// and the plate's horizons (0.0302 m) do not reach it.
#[test]
fn single_bond_along_x_is_named() {
    let p = [0.235, 0.055];
    let err = run(
        "bond_x",
        plate("", NO_CORRECTION),
        Some(&format!("{} {} 1e-4 0.0405\n", p[0], p[1])),
        "",
    )
    .err()
    .expect("a point with one bond has no transverse stiffness");
    eprintln!("{err}");
    match err {
        Error::Numerical(NumericalError::NonPositivePivot {
            component,
            position,
            ..
        }) => {
            assert!(close(position, p), "named {position:?}, expected {p:?}");
            assert_eq!(component, 1, "the transverse component");
        }
        other => panic!("expected a non-positive pivot at {p:?}, got: {other}"),
    }
}

/// The same at 45° from the corner point (0.195, 0.095): the other plate points
/// are at least 0.0476 m away.
#[test]
fn single_bond_at_45_degrees_is_named() {
    let s = 0.04 / 2f64.sqrt();
    let p = [0.195 + s, 0.095 + s];
    let err = run(
        "bond_45",
        plate("", NO_CORRECTION),
        Some(&format!("{:.17e} {:.17e} 1e-4 0.0405\n", p[0], p[1])),
        "",
    )
    .err()
    .expect("a point with one bond has no transverse stiffness");
    eprintln!("{err}");
    match err {
        Error::Numerical(NumericalError::NearlySingular {
            position, ratio, ..
        }) => {
            assert!(close(position, p), "named {position:?}, expected {p:?}");
            assert!(ratio < 1e-12, "{ratio:e}");
        }
        Error::Numerical(NumericalError::NonPositivePivot { position, .. }) => {
            assert!(close(position, p), "named {position:?}, expected {p:?}")
        }
        other => panic!("expected a singular pivot at {p:?}, got: {other}"),
    }
}

#[test]
fn single_bond_shear_model_names_the_shape_tensor() {
    let p = [0.235, 0.055];
    let err = run(
        "bond_shear",
        plate("kind = \"shear\"", NO_CORRECTION),
        Some(&format!("{} {} 1e-4 0.0405\n", p[0], p[1])),
        "",
    )
    .err()
    .expect("one bond cannot span the plane");
    eprintln!("{err}");
    match err {
        Error::Numerical(NumericalError::SingularShapeTensor { position, .. }) => {
            assert!(close(position, p), "named {position:?}, expected {p:?}")
        }
        other => panic!("expected a singular shape tensor at {p:?}, got: {other}"),
    }
}

/// A point 0.015 m right of the plate behind a crack along x = 0.2025 that
/// spans the whole edge: every bond it could have is cut.
#[test]
fn point_cut_off_by_a_crack() {
    let crack = "\n[[cracks]]\nfrom = [0.2025, -0.05]\nto = [0.2025, 0.15]\n";
    let rows = "0.215 0.055 1e-4\n";
    let err = run("cut_error", plate("", ""), Some(rows), crack)
        .err()
        .expect("isolated point");
    eprintln!("{err}");
    match err {
        Error::Numerical(NumericalError::IsolatedPoints {
            count, position, ..
        }) => {
            assert_eq!(count, 1);
            assert!(close(position, [0.215, 0.055]), "named {position:?}");
        }
        other => panic!("expected an isolated point, got: {other}"),
    }
    let removed = run(
        "cut_remove",
        plate("", "isolated_points = \"remove\""),
        Some(rows),
        crack,
    )
    .expect("solves without it");
    let reference =
        run("cut_reference", plate("", ""), None, crack).expect("the plate alone solves");
    assert_eq!(removed.counts.removed_points, 1);
    assert_eq!(removed.u.len(), reference.u.len());
    let scale = reference.u.iter().map(|u| u[0].abs()).fold(0.0, f64::max);
    let diff = removed
        .u
        .iter()
        .zip(&reference.u)
        .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
        .fold(0.0, f64::max);
    eprintln!("removed point: max |Δu| = {:.1e} of max |u|", diff / scale);
    assert!(
        diff <= 1e-12 * scale,
        "removing a bondless point changed the answer by {diff:e}"
    );
}

/// Two 0.1 m blocks joined by a 0.1 m ligament (x from 0.1 to 0.2).
fn ligament(rows: usize) -> String {
    let (lo, hi) = (0.05 - 0.005 * rows as f64, 0.05 + 0.005 * rows as f64);
    plate("", "").replace(
        "box = { min = [0.0, 0.0], max = [0.2, 0.1] }\n",
        &format!(
            "box = {{ min = [0.0, 0.0], max = [0.1, 0.1] }}\n\n[[regions]]\nmaterial = \"steel\"\nspacing = 0.01\n\
             box = {{ min = [0.1, {lo}], max = [0.2, {hi}] }}\n\n[[regions]]\nmaterial = \"steel\"\nspacing = 0.01\n\
             box = {{ min = [0.2, 0.0], max = [0.3, 0.1] }}\n"
        ),
    )
    .replace("min = [0.19, 0.0], max = [0.2, 0.1]", "min = [0.29, 0.0], max = [0.3, 0.1]")
}

fn solve_text(text: &str) -> Result<StaticSolution, Error> {
    solve(
        &Scene::try_from_spec(parse_spec(text, false).unwrap(), Path::new("."), "ligament")
            .unwrap(),
    )
}

#[test]
fn one_point_thick_ligament_is_a_mechanism() {
    let err = solve_text(&ligament(1))
        .err()
        .expect("a one-point ligament has no transverse stiffness");
    eprintln!("{err}");
    let position = match err {
        Error::Numerical(NumericalError::NonPositivePivot {
            position,
            component,
            ..
        }) => {
            assert_eq!(component, 1);
            position
        }
        Error::Numerical(NumericalError::NearlySingular {
            position,
            component,
            ..
        }) => {
            assert_eq!(component, 1);
            position
        }
        other => panic!("expected a singular pivot in the ligament, got: {other}"),
    };
    // More than one horizon (0.03015 m) from both blocks.
    assert!(
        position[0] > 0.13 && position[0] < 0.17 && (position[1] - 0.05).abs() < 1e-12,
        "named {position:?}"
    );
}

#[test]
fn two_point_thick_ligament_solves_in_equilibrium() {
    let s = solve_text(&ligament(2)).expect("a triangulated ligament is stable");
    let applied = 1.0e6 * 0.1 * 0.01; // traction × face area (height 0.1 m × thickness)
    let reaction = s.reaction("left").unwrap();
    let pivots = s.counts.pivots.unwrap();
    eprintln!(
        "two-point ligament: residual {:.1e}, reaction {:.6e} N (applied {applied:.6e} N), pivot range {:.1e}, smallest ratio {:.1e}",
        s.residual,
        reaction[0],
        pivots.max / pivots.min,
        pivots.min_ratio
    );
    assert!(s.residual < 1e-10, "{:e}", s.residual);
    assert!(
        (reaction[0] + applied).abs() < 1e-10 * applied,
        "reaction {reaction:?}"
    );
    assert!(reaction[1].abs() < 1e-10 * applied, "reaction {reaction:?}");
    // The ligament carries the whole load on a fifth of the section: its mean
    // strain exceeds that of the blocks.
    let mean_strain = |x0: f64, x1: f64| {
        let at = |x: f64| {
            s.disc
                .points
                .x
                .iter()
                .zip(&s.u)
                .filter(|(p, _)| (p[0] - x).abs() < 1e-9 && (p[1] - 0.045).abs() < 1e-9)
                .map(|(_, u)| u[0])
                .next()
                .unwrap()
        };
        (at(x1) - at(x0)) / (x1 - x0)
    };
    let (block, lig) = (mean_strain(0.045, 0.075), mean_strain(0.135, 0.165));
    eprintln!("mean strain: block {block:.3e}, ligament {lig:.3e}");
    assert!(
        lig > 3.0 * block,
        "ligament strain {lig:e}, block {block:e}"
    );
}
