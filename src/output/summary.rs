//! `summary.json`: counts, wall time per phase, residual, reactions and loads.

use crate::assembly::loads::AppliedLoad;
use crate::damage::CalibrationReport;
use crate::drivers::quasi_static::{
    Outcome, QuasiStaticSolution, RankingStats, ResolveRecord, StepRecord,
};
use crate::drivers::setup::Timings;
use crate::drivers::static_solve::{Counts, StaticSolution};
use crate::drivers::system::Reaction;
use crate::error::{Error, NumericalError};
use crate::scene::Scene;
use crate::solve::pipeline::Route;
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
            .map(|u| crate::vector::norm(u))
            .fold(0.0, f64::max);
    let summary = Summary {
        scene: &scene.name,
        version: env!("CARGO_PKG_VERSION"),
        model: format!("{:?} {:?}", scene.model.kind, scene.model.dimension),
        counts: &s.counts,
        timings: &s.timings,
        total_seconds,
        relative_residual: s.residual,
        max_displacement,
        reactions: &s.reactions,
        loads: &s.loads,
    };
    let bad = [
        ("relative_residual", s.residual),
        ("max_displacement", max_displacement),
    ]
    .into_iter()
    .map(|(c, v)| (c.to_string(), v))
    .chain(s.reactions.iter().flat_map(|r| {
        r.force
            .iter()
            .map(move |v| (format!("reaction of {}", r.name), *v))
    }))
    .find(|(_, v)| !v.is_finite());
    if let Some((what, value)) = bad {
        return Err(NumericalError::NonFinite {
            what: format!(
                "the {what} ({value}) to be written to summary.json; nothing was written"
            ),
        }
        .into());
    }
    let text = serde_json::to_string_pretty(&summary).map_err(|e| NumericalError::NonFinite {
        what: format!("summary ({e})"),
    })?;
    super::write_file(path, &text)
}

/// Solves of one route: how many, and their time.
#[derive(Debug, Serialize)]
pub struct RouteStats {
    /// Number of solves.
    pub count: usize,
    /// Krylov iterations in all.
    pub iterations: usize,
    /// Median time of one solve, factorisation included (s).
    pub median_seconds: f64,
    /// Total time (s).
    pub total_seconds: f64,
}

impl RouteStats {
    fn of(solves: &[&ResolveRecord]) -> Self {
        let mut times: Vec<f64> = solves
            .iter()
            .map(|s| s.report.factor_seconds + s.report.solve_seconds)
            .collect();
        times.sort_by(f64::total_cmp);
        let median = match times.len() {
            0 => 0.0,
            n if n % 2 == 1 => times[n / 2],
            n => 0.5 * (times[n / 2 - 1] + times[n / 2]),
        };
        Self {
            count: solves.len(),
            iterations: solves.iter().map(|s| s.report.iterations).sum(),
            median_seconds: median,
            total_seconds: times.iter().sum(),
        }
    }
}

/// The peak reaction of one constrained set over the run.
#[derive(Debug, Serialize)]
pub struct Peak {
    /// Set name.
    pub name: String,
    /// Largest magnitude of the set's reaction (N).
    pub magnitude: f64,
    /// The reaction there.
    pub force: [f64; 3],
    /// Step and load factor where it occurred.
    pub step: usize,
    /// Load factor there.
    pub load_factor: f64,
    /// Prescribed displacement there (λ × the largest prescribed component).
    pub displacement: f64,
}

/// The JSON document of a quasi-static run.
#[derive(Debug, Serialize)]
pub struct QuasiStaticSummary<'a> {
    /// Scene name.
    pub scene: &'a str,
    /// dhpd version.
    pub version: &'static str,
    /// Model and dimension.
    pub model: String,
    /// Breakage strategy.
    pub strategy: String,
    /// How the run ended.
    pub outcome: &'a Outcome,
    /// Points, bonds, free unknowns, nnz(K), nnz(L).
    pub counts: serde_json::Value,
    /// Setup time per phase (s).
    pub timings: &'a Timings,
    /// Whole run (s), including output.
    pub total_seconds: f64,
    /// Final load factor.
    pub final_load_factor: f64,
    /// Bonds broken in all.
    pub bonds_broken: usize,
    /// Peak reaction of each constrained set.
    pub peaks: Vec<Peak>,
    /// Solves with a fresh factorisation.
    pub fresh_factorisations: RouteStats,
    /// Solves reusing the previous factor.
    pub reuses: RouteStats,
    /// `event`: how the rankings after Krylov re-solves were decided.
    pub ranking: &'a RankingStats,
    /// How `fracture_energy` became every owner's critical value.
    pub fracture_calibration: &'a CalibrationReport,
    /// What breaking did to the system.
    pub log: &'a [String],
    /// Applied loads at load factor 1.
    pub loads: &'a [AppliedLoad],
    /// Every record (the rows of load_displacement.csv).
    pub steps: &'a [StepRecord],
    /// Every solve: step, bonds broken since the previous one, route, iterations, times.
    pub solves: &'a [ResolveRecord],
}

/// Writes the summary of a quasi-static run; refuses to write non-finite numbers.
pub fn write_quasi_static(
    path: &Path,
    scene: &Scene,
    s: &QuasiStaticSolution,
    total_seconds: f64,
) -> Result<(), Error> {
    let peaks = peaks(s);
    let route = |r: Route| -> Vec<&ResolveRecord> {
        s.solves.iter().filter(|x| x.report.route == r).collect()
    };
    let strategy = scene
        .quasi_static
        .as_ref()
        .map(|q| format!("{:?}", q.strategy))
        .unwrap_or_default();
    let summary = QuasiStaticSummary {
        scene: &scene.name,
        version: env!("CARGO_PKG_VERSION"),
        model: format!("{:?} {:?}", scene.model.kind, scene.model.dimension),
        strategy,
        outcome: &s.outcome,
        counts: quasi_static_counts(s),
        timings: &s.timings,
        total_seconds,
        final_load_factor: s.load_factor,
        bonds_broken: s.records.last().map_or(0, |r| r.broken_total),
        peaks,
        fresh_factorisations: RouteStats::of(&route(Route::Factor)),
        reuses: RouteStats::of(&route(Route::Reuse)),
        ranking: &s.ranking,
        fracture_calibration: &s.calibration,
        log: &s.log,
        loads: &s.loads,
        steps: &s.records,
        solves: &s.solves,
    };
    let text = serde_json::to_string_pretty(&summary).map_err(|e| NumericalError::NonFinite {
        what: format!("summary ({e})"),
    })?;
    check_finite(s)?;
    super::write_file(path, &text)
}

/// Points, bonds, free unknowns, nnz(K), nnz(L), the solver route and, on
/// the `petsc` route, what PETSc's last solve used and did.
fn quasi_static_counts(s: &QuasiStaticSolution) -> serde_json::Value {
    #[cfg_attr(not(feature = "mpi"), allow(unused_mut))]
    let mut counts = serde_json::json!({
        "points": s.disc.points.len(),
        "bonds": s.bonds,
        "dofs": s.dofs_free,
        "nnz_k": s.nnz_k,
        "nnz_l": s.nnz_l,
        "solver": s.solver,
    });
    #[cfg(feature = "mpi")]
    if let Some(petsc) = &s.petsc {
        counts["petsc"] = serde_json::json!(petsc);
    }
    counts
}

/// The peak reaction of every constrained set.
fn peaks(s: &QuasiStaticSolution) -> Vec<Peak> {
    s.set_names
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let best = s.peak(k).expect("a run has its initial record");
            Peak {
                name: name.clone(),
                magnitude: crate::vector::magnitude(&best.reactions[k]),
                force: best.reactions[k],
                step: best.step,
                load_factor: best.load_factor,
                displacement: best.displacement,
            }
        })
        .collect()
}

/// Refuses a non-finite number in the records or the solves (serde_json
/// would write it as null).
fn check_finite(s: &QuasiStaticSolution) -> Result<(), Error> {
    let bad = s
        .records
        .iter()
        .find_map(|r| {
            [
                ("load factor", r.load_factor),
                ("displacement", r.displacement),
                ("residual", r.residual),
            ]
            .into_iter()
            .chain(r.reactions.iter().flatten().map(|v| ("reaction", *v)))
            .find(|(_, v)| !v.is_finite())
            .map(|(c, v)| (format!("{c} of step {}", r.step), v))
        })
        .or_else(|| {
            s.solves
                .iter()
                .find(|x| !x.report.residual.is_finite())
                .map(|x| {
                    (
                        format!("residual of the solve at step {}", x.step),
                        x.report.residual,
                    )
                })
        });
    if let Some((what, value)) = bad {
        return Err(NumericalError::NonFinite {
            what: format!(
                "the {what} ({value}) to be written to summary.json; nothing was written"
            ),
        }
        .into());
    }
    Ok(())
}
