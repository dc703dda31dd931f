//! The scene `dhpd` runs without arguments: the 2D bimaterial strip of
//! `validation/bimaterial_bar`, coarse enough to run in a second, and its
//! comparison with the committed scikit-fem P2 reference.

use crate::drivers::static_solve::StaticSolution;
use crate::error::InputError;
use crate::reference::{ErrorStats, FemReference, BIMATERIAL_STRIP_FEM};
use crate::scene::{parse_spec, Scene};
use std::path::Path;

/// The scene's text.
pub const TEXT: &str = include_str!("../validation/bimaterial_bar/strip_2d.toml");

/// Displacement of the right grip (m): the scale of the errors.
const GRIP_DISPLACEMENT: f64 = 1e-4;

/// The default scene, validated.
pub fn scene() -> Result<Scene, InputError> {
    Scene::try_from_spec(parse_spec(TEXT, false)?, Path::new("."), "default")
}

/// How a solution of the default scene compares with the FEM reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Comparison {
    /// Free points compared (interior to the reference's grid).
    pub points: usize,
    /// Largest error of `u_x`, relative to the grip displacement.
    pub max_relative: f64,
    /// RMS error of `u_x`, relative to the grip displacement.
    pub rms_relative: f64,
    /// The reaction at the right grip: `(dhpd, FEM)` in N.
    pub reaction: Option<(f64, f64)>,
}

/// Compares `s`, the solution of [`scene`], with the embedded reference.
pub fn compare(s: &StaticSolution) -> Comparison {
    let reference =
        FemReference::from_json(BIMATERIAL_STRIP_FEM).expect("embedded reference is valid JSON");
    let pairs: Vec<(f64, f64)> = (0..s.disc.points.len())
        .filter(|&i| s.dofs.free_count(i) == 2)
        .filter_map(|i| {
            let x = s.disc.points.x[i];
            reference
                .grid
                .interpolate("ux", x[0], x[1])
                .map(|r| (s.u[i][0], r))
        })
        .collect();
    let stats = ErrorStats::of(pairs, GRIP_DISPLACEMENT);
    Comparison {
        points: stats.count,
        max_relative: stats.max_relative,
        rms_relative: stats.rms_relative,
        reaction: reference
            .reaction_x
            .zip(s.reaction("right"))
            .map(|(fem, r)| (r[0], fem)),
    }
}
