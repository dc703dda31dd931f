//! `summary.json`: counts, wall time per phase, residual, reactions and loads.

use crate::assembly::loads::AppliedLoad;
use crate::drivers::static_solve::{Counts, Reaction, StaticSolution, Timings};
use crate::error::{Error, NumericalError};
use crate::scene::Scene;
use serde::Serialize;
use std::path::Path;

/// The JSON document.
#[derive(Debug, Serialize)]
pub struct Summary<'a> {
    /// Scene name.
    pub scene: &'a str,
    /// dhpd version.
    pub version: &'static str,
    /// Model and dimension.
    pub model: String,
    /// Sizes.
    pub counts: &'a Counts,
    /// Wall time per phase (s).
    pub timings: &'a Timings,
    /// Whole run (s), including output.
    pub total_seconds: f64,
    /// Relative residual of the reduced system.
    pub relative_residual: f64,
    /// Largest displacement magnitude.
    pub max_displacement: f64,
    /// Reaction of each constrained set.
    pub reactions: &'a [Reaction],
    /// Applied loads.
    pub loads: &'a [AppliedLoad],
}

/// Writes the summary; refuses to write non-finite numbers.
pub fn write(
    path: &Path,
    scene: &Scene,
    s: &StaticSolution,
    total_seconds: f64,
) -> Result<(), Error> {
    let max_displacement =
        s.u.iter()
            .map(|u| crate::geometry::norm(u))
            .fold(0.0, f64::max);
    let summary = Summary {
        scene: &scene.name,
        version: env!("CARGO_PKG_VERSION"),
        model: format!("{:?} {:?}", scene.model, scene.dimension),
        counts: &s.counts,
        timings: &s.timings,
        total_seconds,
        relative_residual: s.residual,
        max_displacement,
        reactions: &s.reactions,
        loads: &s.loads,
    };
    let finite = s.residual.is_finite()
        && max_displacement.is_finite()
        && s.reactions
            .iter()
            .all(|r| r.force.iter().all(|v| v.is_finite()));
    if !finite {
        return Err(NumericalError::NonFinite {
            what: "the summary (residual, displacement or reactions)".into(),
        }
        .into());
    }
    let text = serde_json::to_string_pretty(&summary).map_err(|e| NumericalError::NonFinite {
        what: format!("summary ({e})"),
    })?;
    super::write_file(path, &text)
}
