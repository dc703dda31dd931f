//! Drivers: from a validated scene to a solution. Every run starts from one
//! [`setup::Setup`] (points, bonds, degrees of freedom, loads, output points);
//! [`run`] picks the driver the scene asks for, as the command line does:
//! [`static_solve`], [`quasi_static`] (`[quasi_static]`: fracture under
//! prescribed displacement) or [`dynamics`] (`[dynamics]`: explicit dynamics or
//! dynamic relaxation). One [`Observer`] watches every run: its notes, its
//! progress, the records of a fracture run and the snapshots the scene's
//! output asks for.

pub mod dynamics;
pub mod quasi_static;
pub mod setup;
pub mod shares;
pub mod static_solve;
mod stress;
pub mod system;

use crate::discretization::Discretization;
use crate::error::Error;
use crate::notes::Notes;
use crate::scene::Scene;
use dynamics::DynamicsSolution;
use quasi_static::{QuasiStaticSolution, StepRecord};
use setup::Setup;
use static_solve::StaticSolution;

/// Watches a run. Every method has a default that does nothing, so an
/// observer implements what it wants (`()` watches nothing).
pub trait Observer {
    /// A note (its text starts with `note:` or `warning:`): a route that
    /// changed, points that were removed, an answer at the round-off floor.
    fn note(&mut self, _note: &str) {}

    /// How far a fracture or explicit run has come (called often; cheap).
    fn progress(&mut self, _progress: &Progress) {}

    /// A recorded state of a fracture run (a row of `load_displacement.csv`), in order.
    fn record(&mut self, _record: &StepRecord) -> Result<(), Error> {
        Ok(())
    }

    /// A state the scene's output asks to keep (`output.every`, `output.steps`;
    /// explicit runs: the last one too).
    fn snapshot(&mut self, _snapshot: &Snapshot) -> Result<(), Error> {
        Ok(())
    }
}

impl Observer for () {}

/// How far a run has come.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Progress {
    /// A fracture run at a recorded state.
    Fracture {
        /// Load step (stepped strategies) or event number.
        step: usize,
        /// Load steps in all (stepped strategies; events are not known ahead).
        steps: Option<usize>,
        /// The load factor reached.
        load_factor: f64,
        /// The run's maximal load factor.
        max_load_factor: f64,
        /// Bonds broken so far.
        broken: usize,
    },
    /// An explicit run after a step.
    Dynamics {
        /// Step.
        step: usize,
        /// Steps in all.
        steps: usize,
        /// Simulated time (s).
        time: f64,
        /// Bonds broken so far.
        broken: usize,
    },
    /// A dynamic relaxation after a step (it ends at its tolerance, at the
    /// latest after `steps`).
    Relaxation {
        /// Step.
        step: usize,
        /// The largest number of steps.
        steps: usize,
    },
}

/// A state of a fracture or explicit run.
pub struct Snapshot<'a> {
    /// Step number.
    pub step: usize,
    /// Where the state sits in the series (the `timestep` of `series.pvd`):
    /// the load factor (fracture), the time (dynamics), the step (relaxation).
    pub timestep: f64,
    /// Points and bonds (with the current intact flags).
    pub disc: &'a Discretization,
    /// Displacements.
    pub u: &'a [[f64; 3]],
    /// Velocities (explicit runs).
    pub velocity: Option<&'a [[f64; 3]]>,
    /// Damage per point.
    pub damage: &'a [f64],
    /// Recovered stress per point, when the scene asks for it.
    pub stress: Option<&'a [crate::model::Block]>,
    /// Intact bonds touching each point, when `disc` does not hold every
    /// bond (an explicit run on several processes: gathered); `None`:
    /// counted from `disc`.
    pub bond_counts: Option<&'a [u32]>,
}

/// What a run produced.
pub enum Solution {
    /// A static solve.
    Static(StaticSolution),
    /// A quasi-static fracture run.
    QuasiStatic(QuasiStaticSolution),
    /// An explicit dynamics or dynamic relaxation run.
    Dynamics(DynamicsSolution),
}

impl Solution {
    /// The static solution, if the run was one.
    pub fn into_static(self) -> Option<StaticSolution> {
        match self {
            Solution::Static(s) => Some(s),
            _ => None,
        }
    }

    /// The fracture run's solution, if the run was one.
    pub fn into_quasi_static(self) -> Option<QuasiStaticSolution> {
        match self {
            Solution::QuasiStatic(s) => Some(s),
            _ => None,
        }
    }

    /// The explicit run's solution, if the run was one.
    pub fn into_dynamics(self) -> Option<DynamicsSolution> {
        match self {
            Solution::Dynamics(s) => Some(s),
            _ => None,
        }
    }
}

/// Runs `scene` with the driver it asks for: quasi-static fracture with
/// `[quasi_static]`, explicit dynamics or dynamic relaxation with `[dynamics]`,
/// a static solve otherwise. `observer` watches the run.
pub fn run(scene: &Scene, observer: &mut dyn Observer) -> Result<Solution, Error> {
    let setup = check(scene, observer)?;
    Ok(if scene.quasi_static.is_some() {
        Solution::QuasiStatic(quasi_static::run(scene, setup, observer)?)
    } else if scene.dynamics.is_some() {
        Solution::Dynamics(dynamics::run(scene, setup, observer)?)
    } else {
        Solution::Static(static_solve::run(scene, setup, observer)?)
    })
}

/// Everything [`run`] checks before any numerics (points, bonds, supports,
/// loads, output points): the setup of `scene`, or the error a run would stop at.
pub fn check(scene: &Scene, observer: &mut dyn Observer) -> Result<Setup, Error> {
    let mut notes = Notes::default();
    let setup = Setup::new(scene, &mut notes);
    forward(&mut notes, observer);
    setup
}

/// Hands the notes so far to `observer`.
pub(crate) fn forward(notes: &mut Notes, observer: &mut dyn Observer) {
    for note in notes.take() {
        observer.note(&note);
    }
}
