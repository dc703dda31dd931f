//! Outputs of an explicit run: `history.csv` (energies, balance error, bonds
//! broken, reactions), `probes.csv` (displacement, velocity and damage of each
//! probe), the final state (`points.vtu`, `points.csv`) and `summary.json`
//! (the VTU series is written while the run goes, [`super::series`]).

use super::csv::{header, row};
use super::PointData;
use crate::drivers::dynamics::DynamicsSolution;
use crate::drivers::setup::Plan;
use crate::error::{Error, NumericalError};
use crate::scene::Scene;
use std::fmt::Write;
use std::path::Path;

/// Refuses a non-finite number in the history or the probes, naming its
/// column and step (the run checks its state every step, so this is a last
/// guard).
fn check_finite(solution: &DynamicsSolution) -> Result<(), Error> {
    for r in &solution.records {
        let named = [
            ("time", r.time),
            ("kinetic", r.kinetic),
            ("strain", r.strain),
            ("broken_energy", r.broken_energy),
            ("damping", r.damping),
            ("external_work", r.external_work),
            ("balance_error", r.balance_error),
            ("residual", r.residual),
        ];
        let bad = named
            .iter()
            .find(|(_, v)| !v.is_finite())
            .map(|(c, v)| (format!("{c} of history.csv"), *v))
            .or_else(|| {
                solution
                    .set_names
                    .iter()
                    .zip(&r.reactions)
                    .find_map(|(name, f)| {
                        let v = f.iter().find(|v| !v.is_finite())?;
                        Some((format!("reaction of {name} in history.csv"), *v))
                    })
            })
            .or_else(|| {
                r.probes.iter().enumerate().find_map(|(k, p)| {
                    let v =
                        p.0.iter()
                            .chain(&p.1)
                            .chain([&p.2])
                            .find(|v| !v.is_finite())?;
                    Some((format!("probe {k} in probes.csv"), *v))
                })
            });
        if let Some((what, value)) = bad {
            return Err(NumericalError::NonFinite {
                what: format!(
                    "the {what} ({value}) at step {}; nothing was written",
                    r.step
                ),
            }
            .into());
        }
    }
    Ok(())
}

fn write_history(path: &Path, s: &DynamicsSolution) -> Result<(), Error> {
    let d = s.disc.d;
    let mut t = String::from(
        "step,time,kinetic,strain,broken_energy,damping,external_work,balance_error,broken_bonds,residual",
    );
    for name in &s.set_names {
        let _ = write!(t, ",{}", header(d, &format!("reaction_{name}_")));
    }
    t.push('\n');
    for r in &s.records {
        let _ = write!(
            t,
            "{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e}",
            r.step,
            r.time,
            r.kinetic,
            r.strain,
            r.broken_energy,
            r.damping,
            r.external_work,
            r.balance_error,
            r.broken_bonds,
            r.residual
        );
        for f in &r.reactions {
            let _ = write!(t, ",{}", row(f, d));
        }
        t.push('\n');
    }
    super::write_file(path, &t)
}

fn write_probes(path: &Path, s: &DynamicsSolution, plan: &Plan) -> Result<(), Error> {
    let d = s.disc.d;
    let mut t = String::from("step,time");
    for (name, _) in &plan.probes {
        let _ = write!(
            t,
            ",{},{},{name}_damage",
            header(d, &format!("{name}_u")),
            header(d, &format!("{name}_v"))
        );
    }
    t.push('\n');
    for r in &s.records {
        let _ = write!(t, "{},{:e}", r.step, r.time);
        for (u, v, phi) in &r.probes {
            let _ = write!(t, ",{},{},{phi:e}", row(u, d), row(v, d));
        }
        t.push('\n');
    }
    super::write_file(path, &t)
}

#[derive(serde::Serialize)]
struct Summary<'a> {
    scene: &'a str,
    version: &'static str,
    model: String,
    method: String,
    kernel: &'a str,
    outcome: &'a crate::drivers::dynamics::Outcome,
    points: usize,
    bonds: usize,
    /// The bonds each process held, on several processes.
    #[serde(skip_serializing_if = "Option::is_none")]
    bonds_held: Option<&'a [usize]>,
    steps: usize,
    time_step: f64,
    stable_time_step: Option<f64>,
    end_time: f64,
    timings: &'a crate::drivers::dynamics::DynamicsTimings,
    total_seconds: f64,
    bond_updates_per_second: f64,
    threads: usize,
    bonds_broken: usize,
    max_balance_error: f64,
    final_record: Option<&'a crate::drivers::dynamics::Record>,
    loads: &'a [crate::assembly::loads::AppliedLoad],
    log: &'a [String],
}

/// Writes the final state, the history, the probes and the summary of an
/// explicit run into `tmp` (the staging directory).
pub(crate) fn write(
    tmp: &Path,
    scene: &Scene,
    solution: &DynamicsSolution,
    total_seconds: f64,
) -> Result<(), Error> {
    check_finite(solution)?;
    let plan = &solution.plan;
    let data = PointData {
        disc: &solution.disc,
        u: &solution.u,
        velocity: Some(&solution.v),
        stress: solution.stress.as_deref(),
        damage: Some(&solution.damage),
        bond_counts: solution.bond_counts.as_deref(),
    };
    let point_plan = Plan {
        profiles: plan.profiles.clone(),
        probes: Vec::new(),
    };
    super::write_points(tmp, scene, &point_plan, &data, 1)?;
    write_history(&tmp.join("history.csv"), solution)?;
    if !plan.probes.is_empty() {
        write_probes(&tmp.join("probes.csv"), solution, plan)?;
    }
    let dy = scene.dynamics.as_ref().expect("a dynamics scene");
    let summary = Summary {
        scene: &scene.name,
        version: env!("CARGO_PKG_VERSION"),
        model: format!(
            "{:?} {:?} {:?} horizons",
            scene.model.kind, scene.model.dimension, scene.model.horizons
        ),
        method: format!("{:?}", dy.method),
        kernel: &solution.kernel,
        outcome: &solution.outcome,
        points: solution.disc.points.len(),
        bonds: solution.bonds,
        bonds_held: solution.bonds_held.as_deref(),
        steps: solution.steps,
        time_step: solution.time_step,
        stable_time_step: solution.stable_time_step,
        end_time: solution.time,
        timings: &solution.timings,
        total_seconds,
        bond_updates_per_second: solution.bond_updates_per_second,
        threads: rayon::current_num_threads(),
        bonds_broken: solution.records.last().map_or(0, |r| r.broken_bonds),
        max_balance_error: solution.max_balance_error,
        final_record: solution.records.last(),
        loads: &solution.loads,
        log: &solution.log,
    };
    let text = serde_json::to_string_pretty(&summary).map_err(|e| NumericalError::NonFinite {
        what: format!("summary ({e})"),
    })?;
    super::write_file(&tmp.join("summary.json"), &text)
}
