//! The linear system of the implicit drivers (static, quasi-static): the
//! patterns and the solver pipeline, `K` and, when the solver route factorises
//! one, the bond-based surrogate (the assembly builds it, the solver only
//! factorises it); the right-hand side, the stiffness range check and the
//! reaction of every constrained set (formulation Sec. 7).
//!
//! Constraints are eliminated: `K` is assembled on the free unknowns only, and
//! the prescribed values enter the right-hand side through the linearised
//! internal force, `b = f_ext,free + F_int(u_prescribed)_free`.

use super::setup::Timings;
use super::shares::sum_shares;
use crate::assembly::dofs::DofMap;
use crate::assembly::forces::{internal_forces, internal_forces_on};
use crate::assembly::pattern::Pattern;
use crate::assembly::stiffness::Stiffness;
use crate::discretization::{self, Discretization};
use crate::error::Error;
use crate::model::bond_based::BondBased;
use crate::model::{AnyModel, Coupling, Model};
use crate::notes::Notes;
use crate::scene::solver::SolverSettings;
#[cfg(feature = "mpi")]
use crate::scene::SolverMethod;
use crate::scene::{ModelKind, Scene};
use crate::solve::pipeline::Pipeline;
use crate::solve::route::{self, Hints};
use crate::solve::{Layout, Matrices};
use serde::Serialize;
use std::time::Instant;

/// The linear system of a scene's model on its points.
pub struct System {
    /// The solver pipeline; it owns the patterns.
    pub pipeline: Pipeline,
    /// `K` on the pipeline's pattern.
    pub stiffness: Stiffness,
    /// The bond-based surrogate and its values, while the solver route
    /// factorises one.
    pub surrogate: Option<(BondBased, Stiffness)>,
}

impl System {
    /// Builds the pattern of `K` (and the surrogate's, when the route asks
    /// for one) and runs the symbolic analysis, before any value is assembled,
    /// so that a factor too large for memory is refused early; then assembles
    /// `K` and the surrogate. Timed into `timings`; notes go to `notes`.
    pub fn new(
        scene: &Scene,
        disc: &Discretization,
        dofs: &DofMap,
        model: &AnyModel,
        timings: &mut Timings,
        notes: &mut Notes,
    ) -> Result<Self, Error> {
        let settings = &scene.solver;
        let hints = solver_hints(scene, model.coupling());
        route::check_size(settings, dofs.n_free())?;
        let t = Instant::now();
        let limit = settings.memory_limit_bytes;
        let pattern = stiffness_pattern(settings, disc, dofs, model.coupling())?;
        let surrogate = route::wants_surrogate(settings, hints)
            .then(|| Pattern::new(disc, dofs, Coupling::Star, limit))
            .transpose()?;
        timings.pattern = t.elapsed().as_secs_f64();
        let pipeline = Pipeline::analyse(
            pattern,
            surrogate,
            layout(disc, dofs),
            *settings,
            hints,
            notes,
        )?;
        timings.symbolic_factorization = pipeline.symbolic_seconds;
        let t = Instant::now();
        let stiffness = Stiffness::assemble(model, disc, dofs, pipeline.pattern());
        let surrogate = pipeline.surrogate_pattern().map(|p| {
            let bond_based = BondBased::of(scene, disc);
            let values = Stiffness::assemble(&bond_based, disc, dofs, p);
            (bond_based, values)
        });
        timings.assembly = t.elapsed().as_secs_f64();
        Ok(System {
            pipeline,
            stiffness,
            surrogate,
        })
    }

    /// The pipeline, and the values a solve works with.
    pub fn parts(&mut self) -> (&mut Pipeline, Matrices<'_>) {
        let matrices = Matrices {
            k: &self.stiffness,
            surrogate: self.surrogate.as_ref().map(|(_, values)| values),
            changed: None,
        };
        (&mut self.pipeline, matrices)
    }
}

/// A check that each process of the `petsc` route makes on its own columns
/// of `K`, made every process's (an error on one stops all of them, none
/// going on alone into PETSc's collective calls); as it is on other routes.
pub fn agreed<T>(settings: &SolverSettings, result: Result<T, Error>) -> Result<T, Error> {
    #[cfg(feature = "mpi")]
    if settings.method == SolverMethod::Petsc {
        return crate::solve::petsc::on_every_process(result);
    }
    let _ = settings;
    result
}

/// The pattern of `K`: whole, or on the `petsc` route the columns this
/// process assembles (`solve::petsc::assembled_columns`: its own points and
/// their ghosts).
fn stiffness_pattern(
    settings: &SolverSettings,
    disc: &Discretization,
    dofs: &DofMap,
    coupling: Coupling,
) -> Result<Pattern, Error> {
    let limit = settings.memory_limit_bytes;
    #[cfg(feature = "mpi")]
    if settings.method == SolverMethod::Petsc {
        return Pattern::with_columns(disc, dofs, coupling, limit, |points| {
            crate::solve::petsc::assembled_columns(points, layout(disc, dofs))
        });
    }
    Ok(Pattern::new(disc, dofs, coupling, limit)?)
}

/// What the solver should know about `scene` besides its matrix: a symmetric
/// `K` (a star coupling, or the shear model's energy formulation), a fracture run, or a shear-model body with a nearly
/// incompressible material ([`crate::model::shear::NEAR_INCOMPRESSIBLE`]).
pub fn solver_hints(scene: &Scene, coupling: Coupling) -> Hints {
    Hints {
        symmetric: coupling == Coupling::Star || scene.model.energy_shear(),
        fracture: scene.quasi_static.is_some(),
        near_incompressible: scene.model.kind == ModelKind::Shear
            && scene
                .materials
                .iter()
                .any(|m| m.poisson_ratio >= crate::model::shear::NEAR_INCOMPRESSIBLE),
    }
}

/// What the solver knows of the body.
pub fn layout<'a>(disc: &'a Discretization, dofs: &'a DofMap) -> Layout<'a> {
    Layout {
        x: &disc.points.x,
        spacing: &disc.points.spacing,
        #[cfg(feature = "mpi")]
        part: disc.share.as_ref().map(|s| &s.part[..]),
        dofs,
    }
}

/// Refuses a stiffness that left the floating-point range
/// ([`Stiffness::out_of_range`]; `columns`: only the point columns refilled),
/// naming the point's source.
pub fn check_range(
    k: &Stiffness,
    pattern: &Pattern,
    dofs: &DofMap,
    disc: &Discretization,
    columns: Option<&[bool]>,
) -> Result<(), Error> {
    match k.out_of_range(pattern, dofs, disc, columns) {
        Some((point, value)) => {
            Err(
                discretization::beyond_double_precision(disc, point, "a stiffness entry", value)
                    .into(),
            )
        }
        None => Ok(()),
    }
}

/// The right-hand side of the reduced system for the loads and prescribed
/// displacements scaled by `load_factor`: `b = λ (f_ext + F_int(u_prescribed))`
/// on the free unknowns (the linearised `F_int = −K u` moves the prescribed
/// columns to the right-hand side).
pub fn right_hand_side<M: Model>(
    model: &M,
    disc: &Discretization,
    dofs: &DofMap,
    f_ext: &[[f64; 3]],
    load_factor: f64,
) -> Vec<f64> {
    let f_prescribed = internal_forces(model, disc, &dofs.prescribed, true);
    dofs.free_dofs
        .iter()
        .map(|&(i, c)| {
            load_factor * (f_ext[i as usize][c as usize] + f_prescribed[i as usize][c as usize])
        })
        .collect()
}

/// Reaction force on a constrained set: the force the support exerts on the body.
#[derive(Debug, Clone, Serialize)]
pub struct Reaction {
    /// Set name.
    pub name: String,
    /// Number of points in the set.
    pub points: usize,
    /// Sum of `K u − f_ext` over the prescribed components the set owns (N);
    /// zero for components it does not prescribe or shares with an earlier set.
    pub force: [f64; 3],
}

/// The reaction of every constrained set for displacements `u` under the
/// external forces `f_ext` scaled by `load_factor`: the force the supports
/// exert on the body, `−Σ (F_int + f_ext)` over the prescribed components the
/// set owns (formulation Sec. 7; overlapping sets:
/// [`crate::assembly::dofs::ConstrainedSet`]), so the reactions of all sets sum
/// to the total support force. Only the bonds touching the sets are evaluated;
/// on a body discretised over several processes each sums its own points and
/// the sums are added up (a collective call).
pub fn reactions<M: Model>(
    model: &M,
    disc: &Discretization,
    dofs: &DofMap,
    f_ext: &[[f64; 3]],
    u: &[[f64; 3]],
    load_factor: f64,
) -> Vec<Reaction> {
    let mut reactions: Vec<Reaction> = dofs
        .sets
        .iter()
        .map(|set| {
            let f_int = internal_forces_on(model, disc, u, true, &set.points);
            // Only the components this set owns (the first set to prescribe a
            // component counts its reaction: `ConstrainedSet`).
            let mut force = [0.0; 3];
            for &(i, c) in &set.owned {
                let (i, c) = (i as usize, c as usize);
                if !disc.reports(i) {
                    continue;
                }
                let k = set
                    .points
                    .binary_search(&i)
                    .expect("owned point in its set");
                force[c] -= f_int[k][c] + load_factor * f_ext[i][c];
            }
            Reaction {
                name: set.name.clone(),
                points: set.points.len(),
                force,
            }
        })
        .collect();
    if disc.partial_share().is_some() {
        let mut forces: Vec<f64> = reactions.iter().flat_map(|r| r.force).collect();
        sum_shares(disc, &mut forces);
        for (r, f) in reactions.iter_mut().zip(forces.chunks(3)) {
            r.force.copy_from_slice(f);
        }
    }
    reactions
}
