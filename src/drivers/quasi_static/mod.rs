//! The quasi-static driver: fracture under prescribed displacement by
//! sequentially linear analysis (formulation Sec. 5).
//!
//! Every prescribed displacement and load of the scene is scaled by a load
//! factor `λ`. With the bond set `D` frozen, the linearised problem is linear
//! in `λ`:
//!
//! ```text
//! K(D) x = λ b(D),   so   x(λ) = λ x₁,   u(λ) = λ u₁,   R(λ) = λ R₁
//! ```
//!
//! (`x₁`, `u₁`, `R₁`: free unknowns, displacements and reactions at `λ = 1`). A
//! bond's ratio `r_b = value / critical value` (stretch or deviatoric strain,
//! [`crate::damage`]) is positively homogeneous of degree one in `u`, so
//! `r_b(λ) = λ r_b(1)`. Strategies (`quasi_static.strategy`):
//!
//! - `event`: the next bond reaches its critical value at exactly
//!   `λ* = 1 / max_b r_b(1)`. Record the state there (`critical`), break that
//!   bond (with any tied within `tolerance`), re-solve, record again at the same
//!   `λ*` (`broken`): the exact saw-tooth load-displacement curve of the
//!   discrete model, snap-back included (`λ*` may fall), with no step size.
//! - `all`: at each load step `λ_n`, break every bond with `r_b(λ_n) ≥ 1`,
//!   re-solve at the same `λ_n`, until none breaks (`max_resolves`).
//! - `most_critical`: as `all`, but break only the bonds within `tolerance` of
//!   the largest ratio each time.
//!
//! Stepped strategies take uniform steps of `max_load_factor / steps`; with
//! `max_broken_per_step`, a step at which more bonds are over their critical
//! value before any re-solve is halved (down to `min_step_fraction` of the
//! uniform step), and the step doubles back after an accepted one.
//!
//! **What breaking does to the system** (each logged):
//! - shear-model owners whose intact bonds stop spanning the space lose their
//!   remaining bonds (formulation Sec. 4) — [`Model::refresh_owners`];
//! - bond-based points whose intact bonds (owned or not) stop spanning the
//!   space are mechanisms: their remaining bonds break; a point the
//!   factorisation finds singular is released the same way;
//! - points left without any intact bond, and pieces that break free of every
//!   support, are held where they are (their unknowns are pinned, their
//!   displacement stays the one they had when they broke free); a free piece
//!   that carries an applied load ends the run (the body has failed);
//! - complete separation (every reaction below `1e-6` of its peak) ends the
//!   run, reporting the step; so does `stop_after_peak`, once every reaction
//!   has fallen below that fraction of its peak. A load step checks it after
//!   every re-solve: once past it, the rest of the step (more bonds breaking
//!   at the same grip displacement) can only lower the reactions further, so
//!   the run ends there and records the step as [`StateKind::Unsettled`].
//!
//! **Solves** (module docs of [`crate::solve::pipeline`]): one at λ = 1 per
//! bond set. The first factorises; after bonds break only the stiffness
//! columns they touch are refilled, and the re-solve either updates the old
//! Cholesky factor exactly by the rank-one terms of the broken bonds
//! (bond-based, [`crate::solve::low_rank`]) or iterates with the old factor
//! as preconditioner (shear model, or when points were newly held).

use super::setup::{Plan, Setup, Timings};
use super::system::{agreed, check_range, layout, reactions, right_hand_side, Reaction, System};
use super::{forward, Observer, Progress, Snapshot};
use crate::assembly::dofs::DofMap;
use crate::assembly::loads::AppliedLoad;
use crate::assembly::rigid_modes;
use crate::assembly::stiffness;
use crate::damage::{self, CalibrationReport, Criterion};
use crate::discretization::Discretization;
use crate::error::{Error, NumericalError};
use crate::model::{AnyModel, Block, Coupling, Model};
use crate::notes::Notes;
use crate::scene::{QuasiStatic, Scene, SolverMethod, Strategy};
use crate::solve::low_rank::Term;
use crate::solve::pipeline::{SolveReport, Solved};
use serde::Serialize;
use std::time::Instant;

mod breakage;
mod ranking;
mod resolves;
mod strategies;

pub use ranking::RankingStats;

/// Reaction magnitude, relative to its peak, below which the body counts as separated.
const SEPARATED: f64 = 1e-6;

/// Largest number of points released as mechanisms in a row before giving up.
const MAX_RELEASES: usize = 10_000;

/// Which state a record describes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StateKind {
    /// The unloaded start.
    Initial,
    /// Converged at a load step: no bond over its critical value.
    Equilibrium,
    /// `event`: the old bond set at the load factor where the next bond reaches
    /// its critical value.
    Critical,
    /// `event`: the same load factor after breaking and re-solving.
    Broken,
    /// `all` / `most_critical`: a load step that ended with bonds still over
    /// their critical value: every reaction fell below `stop_after_peak` of its
    /// peak while bonds were breaking (breaking more at the same grip
    /// displacement only lowers the reactions), or `max_resolves` was reached.
    Unsettled,
}

/// One row of `load_displacement.csv`.
#[derive(Debug, Clone, Serialize)]
pub struct StepRecord {
    /// Step (load step or event) number, from 0.
    pub step: usize,
    /// Which state.
    pub state: StateKind,
    /// Load factor λ.
    pub load_factor: f64,
    /// λ times the scene's largest prescribed displacement component.
    pub displacement: f64,
    /// Reaction of each constrained set (N).
    pub reactions: Vec<[f64; 3]>,
    /// Bonds broken in this step (including those its consequences broke).
    pub broken_in_step: usize,
    /// Bonds broken so far.
    pub broken_total: usize,
    /// Re-solves in this step.
    pub resolves: usize,
    /// Routes of the step's solves: `factor`, `update`, `reuse` (Krylov with the
    /// old factor), joined by `+`, or `-` (no solve).
    pub route: String,
    /// Krylov iterations of the step's solves.
    pub iterations: usize,
    /// Relative residual of the solve of the recorded state: the step's last
    /// (0 without a solve; the `all` strategy's intermediate re-solves stop
    /// earlier, module docs of `ranking`).
    pub residual: f64,
    /// Wall time since the start of the run (s).
    pub wall_time: f64,
}

/// One solve of the run, for `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct ResolveRecord {
    /// Step it belongs to.
    pub step: usize,
    /// Bonds broken since the previous solve.
    pub bonds_broken: usize,
    /// What the solve did.
    #[serde(flatten)]
    pub report: SolveReport,
}

/// How the run ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind", content = "detail")]
pub enum Outcome {
    /// The maximal load factor was reached.
    Completed,
    /// No intact bond is loaded toward its critical value (event strategy).
    NothingToBreak,
    /// Every reaction fell below 1e-6 of its peak: the body separated.
    Separated {
        /// The step at which it happened.
        step: usize,
    },
    /// A piece carrying an applied load broke free of every support.
    Failed {
        /// The step at which it happened.
        step: usize,
        /// What broke free.
        reason: String,
    },
    /// The event cap (`max_events`) was reached.
    EventCap,
    /// Every reaction fell below `stop_after_peak` of its peak.
    PastPeak {
        /// The step at which it happened.
        step: usize,
    },
}

impl Outcome {
    /// A sentence for the terminal.
    pub fn describe(&self) -> String {
        match self {
            Outcome::Completed => "reached the maximal load factor".into(),
            Outcome::NothingToBreak => "no intact bond is loaded toward its critical value".into(),
            Outcome::Separated { step } => format!("complete separation at step {step}"),
            Outcome::Failed { step, reason } => format!("failure at step {step}: {reason}"),
            Outcome::EventCap => "stopped at quasi_static.max_events".into(),
            Outcome::PastPeak { step } => format!(
                "stopped at step {step}: every reaction below quasi_static.stop_after_peak of its peak"
            ),
        }
    }
}

/// Everything a quasi-static run produces.
pub struct QuasiStaticSolution {
    /// Points and bonds, with the final intact flags.
    pub disc: Discretization,
    /// Degrees of freedom.
    pub dofs: DofMap,
    /// Final displacement.
    pub u: Vec<[f64; 3]>,
    /// Final damage per point.
    pub damage: Vec<f64>,
    /// Final recovered stress per point, when the scene asks for it.
    pub stress: Option<Vec<Block>>,
    /// Final load factor.
    pub load_factor: f64,
    /// The scene's largest prescribed displacement component (the `displacement` column is λ times it).
    pub reference_displacement: f64,
    /// Names of the constrained sets (reaction columns).
    pub set_names: Vec<String>,
    /// Every record.
    pub records: Vec<StepRecord>,
    /// Every solve.
    pub solves: Vec<ResolveRecord>,
    /// What breaking did to the system (held points, released mechanisms, free
    /// pieces), after the notes of the fracture calibration.
    pub log: Vec<String>,
    /// How every owner's critical value was calibrated.
    pub calibration: CalibrationReport,
    /// How the run ended.
    pub outcome: Outcome,
    /// How the decisions after Krylov re-solves were made (`event`: the
    /// rankings; `all`: the bonds over their critical value).
    pub ranking: RankingStats,
    /// Setup time per phase.
    pub timings: Timings,
    /// Applied loads at λ = 1.
    pub loads: Vec<AppliedLoad>,
    /// Bonds in all.
    pub bonds: usize,
    /// Free unknowns.
    pub dofs_free: usize,
    /// Stored entries of `K`.
    pub nnz_k: usize,
    /// Stored entries of the factor.
    pub nnz_l: Option<usize>,
    /// The solver route taken.
    pub solver: SolverMethod,
    /// What the last PETSc solve used and did (`solver.method = "petsc"`).
    #[cfg(feature = "mpi")]
    pub petsc: Option<crate::solve::petsc::PetscReport>,
    /// Reaction of each constrained set in the final state.
    pub final_reactions: Vec<Reaction>,
    /// The points the outputs read.
    pub plan: Plan,
}

/// Runs the quasi-static fracture analysis of `scene` from its `setup`;
/// `observer` sees every record, the snapshots the scene asks for, the
/// progress and the notes.
pub fn run(
    scene: &Scene,
    setup: Setup,
    observer: &mut dyn Observer,
) -> Result<QuasiStaticSolution, Error> {
    let model = AnyModel::new(scene, &setup.disc)?;
    let mut notes = Notes::default();
    model.warnings().into_iter().for_each(|w| notes.push(w));
    let result = run_with(model, scene, setup, observer, &mut notes);
    forward(&mut notes, observer);
    result
}

/// The state of a run between solves.
struct Run<'s> {
    scene: &'s Scene,
    settings: &'s QuasiStatic,
    model: AnyModel,
    disc: Discretization,
    dofs: DofMap,
    f_ext: Vec<[f64; 3]>,
    criterion: Criterion,
    /// `K`, the surrogate (kept up to date as bonds break, pinned like `K`)
    /// and the pipeline.
    system: System,
    /// Notes of the solves not yet handed on.
    notes: Notes,
    /// Free unknowns at λ = 1 for the current bonds.
    x: Vec<f64>,
    /// Reactions at λ = 1 for the current bonds.
    unit_reactions: Vec<Reaction>,
    /// Held points: the displacement each keeps.
    held: Vec<Option<[f64; 3]>>,
    /// Diagonal given to held unknowns.
    pin_diagonal: f64,
    ratios: Vec<f64>,
    broken_total: usize,
    /// Bonds broken since the last solve.
    pending: usize,
    /// Points whose bonds broke since the last [`Run::consequences`].
    touched: Vec<usize>,
    /// Bonds broken since the last assembly.
    recent: Vec<usize>,
    /// Bonds broken since the last search for pieces broken free
    /// ([`Run::hold_free_pieces`]); `None` before the first search.
    unsearched: Option<Vec<usize>>,
    /// Points held since the last assembly.
    newly_held: Vec<usize>,
    /// Right-hand side at λ = 1 (before pinning).
    rhs: Vec<f64>,
    /// Right-hand side of the last solve (pinned).
    solve_rhs: Vec<f64>,
    /// The last Krylov solve's checkpoint iterate ([`Solved::earlier`]).
    earlier: Option<Vec<f64>>,
    /// How the decisions after Krylov re-solves were made.
    ranking: RankingStats,
    /// Largest reaction magnitude so far, including what a step's old bonds
    /// carried at its load factor before they broke (the separation test).
    peak_reaction: f64,
    /// Largest reaction magnitude of the recorded states (`stop_after_peak`:
    /// the peak the records and the summary report).
    recorded_peak: f64,
    reference_displacement: f64,
    solves: Vec<ResolveRecord>,
    log: Vec<String>,
    start: Instant,
}

fn run_with(
    model: AnyModel,
    scene: &Scene,
    setup: Setup,
    observer: &mut dyn Observer,
    notes: &mut Notes,
) -> Result<QuasiStaticSolution, Error> {
    let settings = scene.quasi_static.as_ref().expect("a quasi-static scene");
    let start = Instant::now();
    let Setup {
        disc,
        dofs,
        f_ext,
        loads,
        plan,
        mut timings,
        ..
    } = setup;
    let system = System::new(scene, &disc, &dofs, &model, &mut timings, notes);
    forward(notes, observer);
    // The memory checks count each process's own entries (a collective call).
    let system = agreed(&scene.solver, system)?;
    let t = Instant::now();
    let diagonal = system
        .pipeline
        .mean_diagonal(&system.stiffness, layout(&disc, &dofs))?;
    let (criterion, calibration) = Criterion::with_report(scene, &disc);
    timings.assembly += t.elapsed().as_secs_f64();
    let mut run = Run::new(
        scene,
        model,
        (disc, dofs, f_ext),
        criterion,
        system,
        diagonal,
    );
    run.log = calibration.notes();
    run.start = start;
    run.solve(0, true)?;
    run.check_load_factor_range()?;
    timings.numeric_factorization = run.solves[0].report.factor_seconds;
    timings.solve = run.solves[0].report.solve_seconds;
    let initial = run.record(0, StateKind::Initial, 0.0, 0, &[]);
    run.observe(observer, &initial)?;
    let mut records = vec![initial];
    let (outcome, load_factor) = match settings.strategy {
        Strategy::Event => run.events(observer, &mut records)?,
        Strategy::All | Strategy::MostCritical => run.stepped(observer, &mut records)?,
    };
    forward(&mut run.notes, observer);
    let end = End {
        records,
        outcome,
        load_factor,
        calibration,
        timings,
        loads,
        plan,
    };
    run.solution(end)
}

/// How a run ended, and what it carries to its solution.
struct End {
    records: Vec<StepRecord>,
    outcome: Outcome,
    load_factor: f64,
    calibration: CalibrationReport,
    timings: Timings,
    loads: Vec<AppliedLoad>,
    plan: Plan,
}

impl<'s> Run<'s> {
    /// The state before the first solve.
    fn new(
        scene: &'s Scene,
        model: AnyModel,
        (disc, dofs, f_ext): (Discretization, DofMap, Vec<[f64; 3]>),
        criterion: Criterion,
        system: System,
        pin_diagonal: f64,
    ) -> Self {
        let reference_displacement = scene
            .boundaries
            .iter()
            .flat_map(|b| b.values.iter().flatten().copied())
            .fold(0.0, |m: f64, v| if v.abs() > m.abs() { v } else { m });
        let (n_bonds, n_points) = (disc.bonds.len(), disc.points.len());
        Run {
            scene,
            settings: scene.quasi_static.as_ref().expect("a quasi-static scene"),
            model,
            disc,
            dofs,
            f_ext,
            criterion,
            system,
            notes: Notes::default(),
            x: Vec::new(),
            unit_reactions: Vec::new(),
            held: vec![None; n_points],
            pin_diagonal,
            ratios: vec![0.0; n_bonds],
            broken_total: 0,
            pending: 0,
            touched: Vec::new(),
            recent: Vec::new(),
            unsearched: None,
            newly_held: Vec::new(),
            rhs: Vec::new(),
            solve_rhs: Vec::new(),
            earlier: None,
            ranking: RankingStats::default(),
            peak_reaction: 0.0,
            recorded_peak: 0.0,
            reference_displacement,
            solves: Vec::new(),
            log: Vec::new(),
            start: Instant::now(),
        }
    }

    /// The recovered stress of the current bonds for displacements `u`, when
    /// the scene asks for it.
    fn stress(&self, u: &[[f64; 3]]) -> Result<Option<Vec<Block>>, Error> {
        match self.scene.output.stress {
            true => Ok(Some(crate::drivers::stress::field(
                &self.model,
                &self.disc,
                u,
            )?)),
            false => Ok(None),
        }
    }

    /// The solution at the end of the run.
    fn solution(self, end: End) -> Result<QuasiStaticSolution, Error> {
        let load_factor = end.load_factor;
        let u = self.displacement(load_factor);
        let damage = damage::damage(&self.disc);
        let stress = self.stress(&u)?;
        let final_reactions = self
            .unit_reactions
            .iter()
            .map(|r| Reaction {
                force: r.force.map(|f| load_factor * f),
                ..r.clone()
            })
            .collect();
        Ok(QuasiStaticSolution {
            stress,
            set_names: self.dofs.sets.iter().map(|s| s.name.clone()).collect(),
            nnz_k: self.system.pipeline.stored_entries(),
            dofs_free: self.dofs.n_free(),
            bonds: self.disc.bonds.len(),
            nnz_l: self.system.pipeline.nnz_factor(),
            solver: self.system.pipeline.method(),
            #[cfg(feature = "mpi")]
            petsc: self.system.pipeline.petsc_report().cloned(),
            disc: self.disc,
            dofs: self.dofs,
            u,
            damage,
            load_factor,
            reference_displacement: self.reference_displacement,
            records: end.records,
            solves: self.solves,
            log: self.log,
            calibration: end.calibration,
            outcome: end.outcome,
            ranking: self.ranking,
            timings: end.timings,
            loads: end.loads,
            final_reactions,
            plan: end.plan,
        })
    }
}

impl QuasiStaticSolution {
    /// The record at which the reaction of constrained set `k` is largest in
    /// magnitude (the last of equal ones).
    pub fn peak(&self, k: usize) -> Option<&StepRecord> {
        self.records.iter().max_by(|a, b| {
            crate::vector::magnitude(&a.reactions[k])
                .total_cmp(&crate::vector::magnitude(&b.reactions[k]))
        })
    }
}

/// Largest displacement, force or reaction any state of the run may reach, in
/// SI units: outputs and the sums over them need headroom below the largest
/// double (1.8e308), as the point forces do.
const MAX_STATE_MAGNITUDE: f64 = 1e250;

impl Run<'_> {
    /// Refuses a `max_load_factor` whose states cannot be represented: every
    /// state is `λ` times the unit solution (module docs), so `λ_max` times its
    /// largest displacement, reaction or applied force must stay below
    /// [`MAX_STATE_MAGNITUDE`].
    fn check_load_factor_range(&self) -> Result<(), Error> {
        let unit = self
            .x
            .iter()
            .map(|v| v.abs())
            .chain(
                self.unit_reactions
                    .iter()
                    .flat_map(|r| r.force.map(f64::abs)),
            )
            .chain(self.f_ext.iter().flatten().map(|v| v.abs()))
            .chain([self.reference_displacement.abs()])
            .fold(0.0, f64::max);
        let lambda = self.settings.max_load_factor;
        if lambda * unit <= MAX_STATE_MAGNITUDE {
            return Ok(());
        }
        Err(crate::error::InputError::new(
            "quasi_static.max_load_factor",
            format!(
                "{lambda:e} times the largest displacement, force or reaction at load factor 1 \
                 ({unit:.3e}) is {:.3e}, outside the range a result can be written in (above \
                 {MAX_STATE_MAGNITUDE:e}); give a max_load_factor of at most {:.3e}",
                lambda * unit,
                MAX_STATE_MAGNITUDE / unit
            ),
        )
        .into())
    }
}
