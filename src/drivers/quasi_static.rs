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
//!   run, reporting the step.

use super::static_solve::{reactions, right_hand_side, Prepared, Reaction, Timings};
use crate::assembly::dofs::DofMap;
use crate::assembly::loads::AppliedLoad;
use crate::assembly::rigid_modes;
use crate::assembly::stiffness::{self, Stiffness};
use crate::damage::{self, Criterion};
use crate::discretization::Discretization;
use crate::error::{Error, NumericalError};
use crate::model::bond_based::BondBased;
use crate::model::shear::Shear;
use crate::model::{Coupling, Model};
use crate::scene::{ModelKind, QuasiStatic, Scene, Strategy};
use crate::solve::low_rank::Term;
use crate::solve::pipeline::{Pipeline, SolveReport, Solved, SolverSettings};
use serde::Serialize;
use std::time::Instant;

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
    /// Routes of the step's solves: `factor`, `reuse`, both, or `-` (none).
    pub route: String,
    /// Krylov iterations of the step's solves.
    pub iterations: usize,
    /// Largest relative residual of the step's solves (0 without a solve).
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

/// A state handed to observers when the scene asks for a snapshot.
pub struct Snapshot<'a> {
    /// Step number.
    pub step: usize,
    /// Load factor.
    pub load_factor: f64,
    /// Points and bonds (with the current intact flags).
    pub disc: &'a Discretization,
    /// Displacements.
    pub u: &'a [[f64; 3]],
    /// Damage per point.
    pub damage: &'a [f64],
}

/// Watches a run: every record, with a snapshot at the steps the scene's output asks for.
pub trait Observer {
    /// Called for every record, in order.
    fn record(&mut self, record: &StepRecord, snapshot: Option<&Snapshot>) -> Result<(), Error>;
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
    /// What breaking did to the system (held points, released mechanisms, free pieces).
    pub log: Vec<String>,
    /// How the run ended.
    pub outcome: Outcome,
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
    /// Reaction of each constrained set in the final state.
    pub final_reactions: Vec<Reaction>,
}

/// Runs the quasi-static fracture analysis of `scene`.
pub fn run(
    scene: &Scene,
    prepared: Prepared,
    observer: &mut dyn Observer,
) -> Result<QuasiStaticSolution, Error> {
    match scene.model {
        ModelKind::BondBased => {
            let model = BondBased::new(
                &prepared.disc,
                scene.dimension,
                &scene.materials,
                scene.thickness,
            );
            run_with(model, scene, prepared, observer)
        }
        ModelKind::Shear => {
            let model = Shear::new(
                &prepared.disc,
                scene.dimension,
                &scene.materials,
                scene.gradient_dilatation,
            )?;
            run_with(model, scene, prepared, observer)
        }
    }
}

/// The state of a run between solves.
struct Run<'s, M: Model> {
    scene: &'s Scene,
    settings: &'s QuasiStatic,
    model: M,
    disc: Discretization,
    dofs: DofMap,
    f_ext: Vec<[f64; 3]>,
    criterion: Criterion,
    pipeline: Pipeline,
    stiffness: Stiffness,
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
    /// Points held since the last assembly.
    newly_held: Vec<usize>,
    /// Right-hand side at λ = 1 (before pinning).
    rhs: Vec<f64>,
    peak_reaction: f64,
    reference_displacement: f64,
    solves: Vec<ResolveRecord>,
    log: Vec<String>,
    start: Instant,
}

fn run_with<M: Model>(
    model: M,
    scene: &Scene,
    prepared: Prepared,
    observer: &mut dyn Observer,
) -> Result<QuasiStaticSolution, Error> {
    let settings = scene.quasi_static.as_ref().expect("a quasi-static scene");
    let start = Instant::now();
    let Prepared {
        disc,
        dofs,
        f_ext,
        loads,
        mut timings,
    } = prepared;
    let surrogate = (model.coupling() == Coupling::Family)
        .then(|| BondBased::new(&disc, scene.dimension, &scene.materials, scene.thickness));
    let pipeline = Pipeline::analyse(
        &disc,
        &dofs,
        model.coupling(),
        SolverSettings::of(scene),
        surrogate,
    )?;
    timings.pattern = pipeline.pattern_seconds;
    timings.symbolic_factorization = pipeline.symbolic_seconds;
    let t = Instant::now();
    let stiffness = Stiffness::assemble(&model, &disc, &dofs, pipeline.pattern());
    let diagonal = mean_diagonal(&stiffness, pipeline.pattern());
    let criterion = Criterion::new(scene, &disc);
    timings.assembly = t.elapsed().as_secs_f64();
    let reference_displacement = scene
        .boundaries
        .iter()
        .flat_map(|b| b.values.iter().flatten().copied())
        .fold(0.0, |m: f64, v| if v.abs() > m.abs() { v } else { m });
    let n_bonds = disc.bonds.len();
    let n_points = disc.points.len();
    let mut run = Run {
        scene,
        settings,
        model,
        disc,
        dofs,
        f_ext,
        criterion,
        pipeline,
        stiffness,
        x: Vec::new(),
        unit_reactions: Vec::new(),
        held: vec![None; n_points],
        pin_diagonal: diagonal,
        ratios: vec![0.0; n_bonds],
        broken_total: 0,
        pending: 0,
        touched: Vec::new(),
        recent: Vec::new(),
        newly_held: Vec::new(),
        rhs: Vec::new(),
        peak_reaction: 0.0,
        reference_displacement,
        solves: Vec::new(),
        log: Vec::new(),
        start,
    };
    run.solve(0, true)?;
    timings.numeric_factorization = run.solves[0].report.factor_seconds;
    timings.solve = run.solves[0].report.solve_seconds;
    let initial = run.record(0, StateKind::Initial, 0.0, 0, &[]);
    run.observe(observer, &initial)?;
    let mut records = vec![initial];
    let (outcome, load_factor) = match settings.strategy {
        Strategy::Event => run.events(observer, &mut records)?,
        Strategy::All | Strategy::MostCritical => run.stepped(observer, &mut records)?,
    };
    let u = run.displacement(load_factor);
    let damage = damage::damage(&run.disc);
    let final_reactions = run
        .unit_reactions
        .iter()
        .map(|r| Reaction {
            force: r.force.map(|f| load_factor * f),
            ..r.clone()
        })
        .collect();
    let nnz_l = run.pipeline.nnz_factor();
    Ok(QuasiStaticSolution {
        set_names: run.dofs.sets.iter().map(|s| s.name.clone()).collect(),
        nnz_k: run.pipeline.pattern().nnz(),
        dofs_free: run.dofs.n_free(),
        bonds: n_bonds,
        disc: run.disc,
        dofs: run.dofs,
        u,
        damage,
        load_factor,
        reference_displacement,
        records,
        solves: run.solves,
        log: run.log,
        outcome,
        timings,
        loads,
        nnz_l,
        final_reactions,
    })
}

/// Mean diagonal entry of `K` (the stiffness scale given to held unknowns).
fn mean_diagonal(k: &Stiffness, pattern: &crate::assembly::pattern::Pattern) -> f64 {
    let mut sum = 0.0;
    for col in 0..k.n {
        for idx in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
            if pattern.row_idx[idx] == col {
                sum += k.values[idx].abs();
            }
        }
    }
    if sum > 0.0 && k.n > 0 {
        sum / k.n as f64
    } else {
        1.0
    }
}

impl<M: Model> Run<'_, M> {
    /// The event strategy (module docs). Returns the outcome and the final load factor.
    fn events(
        &mut self,
        observer: &mut dyn Observer,
        records: &mut Vec<StepRecord>,
    ) -> Result<(Outcome, f64), Error> {
        let mut load_factor = 0.0;
        for event in 1..=self.settings.max_events {
            self.update_ratios(1.0);
            let largest = self.ratios.iter().fold(0.0f64, |m, &r| m.max(r));
            let critical = if largest > 0.0 {
                1.0 / largest
            } else {
                f64::INFINITY
            };
            if critical > self.settings.max_load_factor {
                let max = self.settings.max_load_factor;
                let record = self.record(event, StateKind::Equilibrium, max, 0, &[]);
                self.observe(observer, &record)?;
                records.push(record);
                let outcome = if largest > 0.0 {
                    Outcome::Completed
                } else {
                    Outcome::NothingToBreak
                };
                return Ok((outcome, max));
            }
            load_factor = critical;
            let before = self.record(event, StateKind::Critical, load_factor, 0, &[]);
            self.observe(observer, &before)?;
            records.push(before);
            let threshold = (1.0 - self.settings.tolerance) * largest;
            let chosen: Vec<usize> = (0..self.ratios.len())
                .filter(|&b| self.ratios[b] > 0.0 && self.ratios[b] >= threshold)
                .collect();
            let (broken_before, first_solve) = (self.broken_total, self.solves.len());
            self.break_bonds(&chosen);
            let ended = self.settle(event, load_factor)?;
            let solves = self.solves[first_solve..].to_vec();
            let broken = self.broken_total - broken_before;
            let record = self.record(event, StateKind::Broken, load_factor, broken, &solves);
            self.observe(observer, &record)?;
            records.push(record);
            if let Some(outcome) = ended {
                return Ok((outcome, load_factor));
            }
            if let Some(outcome) = self.ended(event, load_factor) {
                return Ok((outcome, load_factor));
            }
        }
        Ok((Outcome::EventCap, load_factor))
    }

    /// The `all` and `most_critical` strategies (module docs).
    fn stepped(
        &mut self,
        observer: &mut dyn Observer,
        records: &mut Vec<StepRecord>,
    ) -> Result<(Outcome, f64), Error> {
        let max = self.settings.max_load_factor;
        let uniform = max / self.settings.steps as f64;
        let smallest = uniform * self.settings.min_step_fraction;
        let mut step_size = uniform;
        let mut load_factor = 0.0;
        let mut step = 0;
        while load_factor < max * (1.0 - 1e-12) {
            let target = (load_factor + step_size).min(max);
            if let Some(limit) = self.settings.max_broken_per_step {
                self.update_ratios(target);
                let over = self.ratios.iter().filter(|&&r| r >= 1.0).count();
                if over > limit && step_size > smallest {
                    step_size = (0.5 * step_size).max(smallest);
                    continue;
                }
            }
            step += 1;
            load_factor = target;
            let first_solve = self.solves.len();
            let broken_before = self.broken_total;
            let mut resolves = 0;
            let mut outcome = None;
            loop {
                self.update_ratios(load_factor);
                let largest = self.ratios.iter().fold(0.0f64, |m, &r| m.max(r));
                if largest < 1.0 {
                    break;
                }
                if resolves == self.settings.max_resolves {
                    self.log.push(format!(
                        "step {step}: stopped re-solving after quasi_static.max_resolves = {} \
                         re-solves with bonds still over their critical value",
                        self.settings.max_resolves
                    ));
                    break;
                }
                let threshold = match self.settings.strategy {
                    Strategy::MostCritical => (1.0 - self.settings.tolerance) * largest,
                    _ => 1.0,
                };
                let chosen: Vec<usize> = (0..self.ratios.len())
                    .filter(|&b| self.ratios[b] >= threshold.max(1.0))
                    .collect();
                self.break_bonds(&chosen);
                resolves += 1;
                outcome = self.settle(step, load_factor)?;
                if outcome.is_some() || self.separated() {
                    break;
                }
            }
            let solves = self.solves[first_solve..].to_vec();
            let record = self.record(
                step,
                StateKind::Equilibrium,
                load_factor,
                self.broken_total - broken_before,
                &solves,
            );
            self.observe(observer, &record)?;
            records.push(record);
            if let Some(outcome) = outcome {
                return Ok((outcome, load_factor));
            }
            if let Some(outcome) = self.ended(step, load_factor) {
                return Ok((outcome, load_factor));
            }
            step_size = (2.0 * step_size).min(uniform);
        }
        Ok((Outcome::Completed, load_factor))
    }

    /// The ratio of every bond at `load_factor` for the current bonds.
    fn update_ratios(&mut self, load_factor: f64) {
        let u = self.unit_displacement();
        self.criterion
            .ratios(&self.model, &self.disc, &u, true, &mut self.ratios);
        if load_factor != 1.0 {
            self.ratios.iter_mut().for_each(|r| *r *= load_factor);
        }
    }

    /// Displacements at λ = 1 (held points at zero: they do not deform).
    fn unit_displacement(&self) -> Vec<[f64; 3]> {
        let mut u = self.dofs.expand(&self.x);
        for (i, h) in self.held.iter().enumerate() {
            if h.is_some() {
                u[i] = [0.0; 3];
            }
        }
        u
    }

    /// Displacements at `load_factor`, held points where they are held.
    fn displacement(&self, load_factor: f64) -> Vec<[f64; 3]> {
        let mut u = self.dofs.expand(&self.x);
        for (i, ui) in u.iter_mut().enumerate() {
            *ui = match self.held[i] {
                Some(h) => h,
                None => ui.map(|v| load_factor * v),
            };
        }
        u
    }

    /// Breaks `bonds`; returns how many were intact. Their owners and
    /// neighbours are remembered for [`Run::consequences`].
    fn break_bonds(&mut self, bonds: &[usize]) -> usize {
        let mut count = 0;
        for &b in bonds {
            if self.disc.bonds.intact[b] {
                self.disc.bonds.intact[b] = false;
                let owner = self.disc.bonds.offsets.partition_point(|&o| o <= b) - 1;
                self.touched.push(owner);
                self.touched.push(self.disc.bonds.neighbour[b] as usize);
                self.recent.push(b);
                count += 1;
            }
        }
        self.broken_total += count;
        self.pending += count;
        count
    }

    /// Brings the system up to date after bonds broke (module docs) and
    /// re-solves. Returns an outcome when the run must end.
    fn settle(&mut self, step: usize, load_factor: f64) -> Result<Option<Outcome>, Error> {
        let mut releases = 0;
        loop {
            self.consequences(step, load_factor);
            if let Some(reason) = self.hold_free_pieces(step, load_factor) {
                return Ok(Some(Outcome::Failed { step, reason }));
            }
            match self.solve(step, false) {
                Ok(()) => return Ok(None),
                Err(Error::Numerical(
                    NumericalError::NonPositivePivot { point, .. }
                    | NumericalError::NearlySingular { point, .. }
                    | NumericalError::StructurallySingular { point, .. },
                )) if releases < MAX_RELEASES && self.held[point].is_none() => {
                    releases += 1;
                    let count = self.release(point);
                    self.log.push(format!(
                        "step {step}: point {point} (x = {:?}) is a mechanism (singular in the \
                         factorisation); its {count} remaining bond(s) broke",
                        self.disc.points.x[point]
                    ));
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// Breaks every intact bond touching `point`; returns how many.
    fn release(&mut self, point: usize) -> usize {
        let mut touching: Vec<usize> = self.disc.bonds.owned_by(point).collect();
        touching.extend(
            self.pipeline
                .pattern()
                .incoming(point)
                .iter()
                .map(|&(_, b)| b as usize),
        );
        self.break_bonds(&touching)
    }

    /// Shear-model owners that can no longer carry their bonds, and bond-based
    /// mechanisms, until none is left; then points without bonds are held.
    fn consequences(&mut self, step: usize, load_factor: f64) {
        while !self.touched.is_empty() {
            let mut touched = std::mem::take(&mut self.touched);
            touched.sort_unstable();
            touched.dedup();
            for i in self.model.refresh_owners(&self.disc, &touched) {
                let bonds: Vec<usize> = self.disc.bonds.owned_by(i).collect();
                let count = self.break_bonds(&bonds);
                self.log.push(format!(
                    "step {step}: the bonds of point {i} (x = {:?}) no longer span the space \
                     (singular shape tensor); its {count} remaining bond(s) broke",
                    self.disc.points.x[i]
                ));
            }
            if self.model.coupling() == Coupling::Star {
                for i in self.unsupported(&touched) {
                    let count = self.release(i);
                    self.log.push(format!(
                        "step {step}: point {i} (x = {:?}) is held by bonds along one line or \
                         plane only (a mechanism); its {count} remaining bond(s) broke",
                        self.disc.points.x[i]
                    ));
                }
            }
            let u = self.displacement(load_factor);
            for &i in &touched {
                if self.held[i].is_none() && self.dofs.free_count(i) > 0 && !self.has_bond(i) {
                    self.held[i] = Some(u[i]);
                    self.newly_held.push(i);
                    self.log.push(format!(
                        "step {step}: point {i} (x = {:?}) has no intact bond left; held at its \
                         displacement",
                        self.disc.points.x[i]
                    ));
                }
            }
        }
    }

    /// Whether any intact bond touches `i`.
    fn has_bond(&self, i: usize) -> bool {
        let bonds = &self.disc.bonds;
        bonds.owned_by(i).any(|b| bonds.intact[b])
            || self
                .pipeline
                .pattern()
                .incoming(i)
                .iter()
                .any(|&(_, b)| bonds.intact[b as usize])
    }

    /// The points of `candidates` with intact bonds whose directions do not span the space.
    fn unsupported(&self, candidates: &[usize]) -> Vec<usize> {
        let d = self.disc.d;
        let p = &self.disc.points;
        let bonds = &self.disc.bonds;
        let pattern = self.pipeline.pattern();
        candidates
            .iter()
            .copied()
            .filter(|&i| {
                let mut t = [[0.0f64; 3]; 3];
                let mut any = false;
                let mut add = |j: usize| {
                    let e = crate::geometry::sub(&p.x[j], &p.x[i]);
                    let len2 = crate::geometry::dot(&e, &e);
                    for r in 0..3 {
                        for c in 0..3 {
                            t[r][c] += e[r] * e[c] / len2;
                        }
                    }
                    any = true;
                };
                for b in bonds.owned_by(i).filter(|&b| bonds.intact[b]) {
                    add(bonds.neighbour[b] as usize);
                }
                for &(o, b) in pattern.incoming(i) {
                    if bonds.intact[b as usize] {
                        add(o as usize);
                    }
                }
                any && !spans(&t, d)
            })
            .collect()
    }

    /// Holds the pieces that no support holds any more; returns the reason to
    /// stop when such a piece carries an applied load.
    fn hold_free_pieces(&mut self, step: usize, load_factor: f64) -> Option<String> {
        let u = self.displacement(load_factor);
        for piece in rigid_modes::unheld_bodies(&self.disc, &self.dofs) {
            // Fully prescribed points need no holding (a lone one has a
            // "free" rotation about itself only).
            if piece
                .iter()
                .all(|&i| self.held[i].is_some() || self.dofs.free_count(i) == 0)
            {
                continue;
            }
            let loaded = piece
                .iter()
                .any(|&i| self.f_ext[i].iter().any(|&f| f != 0.0));
            if loaded {
                return Some(format!(
                    "a piece of {} point(s) containing point {} (x = {:?}) carries an applied \
                     load and no support holds it any more",
                    piece.len(),
                    piece[0],
                    self.disc.points.x[piece[0]]
                ));
            }
            for &i in &piece {
                if self.held[i].is_none() && self.dofs.free_count(i) > 0 {
                    self.held[i] = Some(u[i]);
                    self.newly_held.push(i);
                }
            }
            if piece.len() > 1 {
                self.log.push(format!(
                    "step {step}: a piece of {} point(s) containing point {} (x = {:?}) broke \
                     free of every support; held where it is",
                    piece.len(),
                    piece[0],
                    self.disc.points.x[piece[0]]
                ));
            }
        }
        None
    }

    /// The rank-one terms `k g gᵀ` that the bonds broken since the last solve
    /// removed from `K` (one per broken pair of points), when the model's bonds
    /// are rank-one ([`Model::bond_stiffness`]) and no point was newly held.
    fn low_rank_terms(&self) -> Option<Vec<Term>> {
        if !self.newly_held.is_empty() {
            return None;
        }
        let bonds = &self.disc.bonds;
        let mut pairs: std::collections::BTreeMap<(usize, usize), (f64, [f64; 3])> =
            Default::default();
        for &b in &self.recent {
            let owner = bonds.offsets.partition_point(|&o| o <= b) - 1;
            let j = bonds.neighbour[b] as usize;
            let (k, e) = self.model.bond_stiffness(&self.disc, owner, b)?;
            // Oriented from the lower to the higher point index.
            let (key, e) = if owner < j {
                ((owner, j), e)
            } else {
                ((j, owner), e.map(|v| -v))
            };
            pairs.entry(key).or_insert((0.0, e)).0 += k;
        }
        let d = self.disc.d;
        let free = |i: usize, c: usize| {
            let k = self.dofs.free_index[3 * i + c];
            (k != crate::assembly::dofs::PRESCRIBED).then_some(k as usize)
        };
        Some(
            pairs
                .into_iter()
                .map(|((a, b), (stiffness, e))| Term {
                    entries: (0..d)
                        .filter_map(|c| free(a, c).map(|k| (k, e[c])))
                        .chain((0..d).filter_map(|c| free(b, c).map(|k| (k, -e[c]))))
                        .filter(|&(_, v)| v != 0.0)
                        .collect(),
                    stiffness,
                })
                .filter(|t| !t.entries.is_empty())
                .collect(),
        )
    }

    /// The point columns of `K` that changed since the last solve: the ends of
    /// the broken bonds (star coupling) or every point of the families of their
    /// owners (family coupling), and the newly held points. `None`: all.
    fn changed_columns(&mut self, first: bool) -> Option<Vec<bool>> {
        let recent = std::mem::take(&mut self.recent);
        let held = std::mem::take(&mut self.newly_held);
        if first {
            return None;
        }
        let bonds = &self.disc.bonds;
        let mut columns = vec![false; self.disc.points.len()];
        for &b in &recent {
            let owner = bonds.offsets.partition_point(|&o| o <= b) - 1;
            columns[owner] = true;
            columns[bonds.neighbour[b] as usize] = true;
            if self.model.coupling() == Coupling::Family {
                for k in bonds.owned_by(owner) {
                    columns[bonds.neighbour[k] as usize] = true;
                }
            }
        }
        for i in held {
            columns[i] = true;
        }
        Some(columns)
    }

    /// Assembles `K` and `b` for the current bonds (held unknowns pinned) and
    /// solves at λ = 1: afresh for the first solve, else reusing the factor.
    /// Only the columns of `K` that bonds broken since the last solve touch are
    /// refilled, and `b` only when those include a prescribed point.
    fn solve(&mut self, step: usize, first: bool) -> Result<(), Error> {
        let terms = if first { None } else { self.low_rank_terms() };
        let columns = self.changed_columns(first);
        stiffness::fill_columns(
            &self.model,
            &self.disc,
            &self.dofs,
            self.pipeline.pattern(),
            &mut self.stiffness.values,
            columns.as_deref(),
        );
        let prescribed_changed = columns
            .as_ref()
            .is_none_or(|c| (0..c.len()).any(|i| c[i] && self.dofs.free_count(i) < self.disc.d));
        if prescribed_changed {
            self.rhs = right_hand_side(&self.model, &self.disc, &self.dofs, &self.f_ext, 1.0);
        }
        let mut rhs = self.rhs.clone();
        let pinned: Vec<bool> = self
            .dofs
            .free_dofs
            .iter()
            .map(|&(i, _)| self.held[i as usize].is_some())
            .collect();
        if pinned.iter().any(|&p| p) {
            let dof_columns: Option<Vec<bool>> = columns.as_ref().map(|c| {
                self.dofs
                    .free_dofs
                    .iter()
                    .map(|&(i, _)| c[i as usize])
                    .collect()
            });
            self.stiffness.pin(
                self.pipeline.pattern(),
                &pinned,
                self.pin_diagonal,
                dof_columns.as_deref(),
            );
            for (r, &p) in rhs.iter_mut().zip(&pinned) {
                if p {
                    *r = 0.0;
                }
            }
        }
        self.pipeline.set_pinned(pinned, self.pin_diagonal);
        let Solved { x, report } = if first {
            self.pipeline
                .solve(&self.disc, &self.dofs, &self.stiffness, &rhs)?
        } else if let Some(terms) = terms {
            self.pipeline.resolve_update(
                &self.disc,
                &self.dofs,
                &self.stiffness,
                &rhs,
                &self.x,
                terms,
            )?
        } else {
            self.pipeline
                .resolve(&self.disc, &self.dofs, &self.stiffness, &rhs, &self.x)?
        };
        self.x = x;
        let u = self.unit_displacement();
        self.unit_reactions = reactions(
            &self.model,
            &self.disc,
            &self.dofs,
            self.pipeline.pattern(),
            &self.f_ext,
            &u,
            1.0,
        );
        self.solves.push(ResolveRecord {
            step,
            bonds_broken: self.pending,
            report,
        });
        self.pending = 0;
        Ok(())
    }

    /// Whether the run ends after this state: separated, or past the peak as
    /// `stop_after_peak` asks (`load_factor`: that of the state just recorded).
    fn ended(&self, step: usize, load_factor: f64) -> Option<Outcome> {
        if self.separated() {
            return Some(Outcome::Separated { step });
        }
        let fraction = self.settings.stop_after_peak?;
        let largest = self
            .unit_reactions
            .iter()
            .map(|r| load_factor * crate::geometry::norm(&r.force))
            .fold(0.0, f64::max);
        (self.peak_reaction > 0.0 && largest < fraction * self.peak_reaction)
            .then_some(Outcome::PastPeak { step })
    }

    /// Whether every reaction has fallen below [`SEPARATED`] of its peak.
    fn separated(&self) -> bool {
        let largest = self
            .unit_reactions
            .iter()
            .map(|r| crate::geometry::norm(&r.force))
            .fold(0.0, f64::max);
        self.peak_reaction > 0.0
            && largest * self.settings.max_load_factor <= SEPARATED * self.peak_reaction
    }

    /// A record of the current bonds at `load_factor`; updates the peak reaction.
    fn record(
        &mut self,
        step: usize,
        state: StateKind,
        load_factor: f64,
        broken_in_step: usize,
        solves: &[ResolveRecord],
    ) -> StepRecord {
        let reactions: Vec<[f64; 3]> = self
            .unit_reactions
            .iter()
            .map(|r| r.force.map(|f| load_factor * f))
            .collect();
        for r in &reactions {
            self.peak_reaction = self.peak_reaction.max(crate::geometry::norm(r));
        }
        let has = |route| solves.iter().any(|s| s.report.route == route);
        use crate::solve::pipeline::Route;
        let route = match (has(Route::Factor), has(Route::Reuse)) {
            (true, true) => "factor+reuse",
            (true, false) => "factor",
            (false, true) => "reuse",
            (false, false) => "-",
        };
        StepRecord {
            step,
            state,
            load_factor,
            displacement: load_factor * self.reference_displacement,
            reactions,
            broken_in_step,
            broken_total: self.broken_total,
            resolves: solves.len(),
            route: route.into(),
            iterations: solves.iter().map(|s| s.report.iterations).sum(),
            residual: solves.iter().map(|s| s.report.residual).fold(0.0, f64::max),
            wall_time: self.start.elapsed().as_secs_f64(),
        }
    }

    /// Hands a record to the observer, with a snapshot when the scene asks for one.
    fn observe(&self, observer: &mut dyn Observer, record: &StepRecord) -> Result<(), Error> {
        let output = &self.scene.output;
        let due = output.every.is_some_and(|n| record.step % n == 0)
            || output.steps.contains(&record.step);
        // For an event, the snapshot shows the state after the break.
        let due = due && record.state != StateKind::Critical;
        if !due {
            return observer.record(record, None);
        }
        let u = self.displacement(record.load_factor);
        let damage = damage::damage(&self.disc);
        observer.record(
            record,
            Some(&Snapshot {
                step: record.step,
                load_factor: record.load_factor,
                disc: &self.disc,
                u: &u,
                damage: &damage,
            }),
        )
    }
}

/// Whether the direction tensor `t` (sum of `e ⊗ e` over unit bond directions)
/// spans the first `d` dimensions (smallest eigenvalue above 1e-8 of the trace).
fn spans(t: &[[f64; 3]; 3], d: usize) -> bool {
    let trace: f64 = (0..d).map(|a| t[a][a]).sum();
    match d {
        1 => trace > 0.0,
        2 => {
            let det = t[0][0] * t[1][1] - t[0][1] * t[1][0];
            // λ_min ≈ det / trace for a 2 × 2 tensor.
            det > 1e-8 * trace * trace
        }
        _ => {
            let m = nalgebra::Matrix3::from_fn(|r, c| t[r][c]);
            let eig = m.symmetric_eigenvalues();
            eig.min() > 1e-8 * trace
        }
    }
}
