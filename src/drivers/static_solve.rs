//! The static driver: from the setup, assemble the linearised `K`, factorise,
//! solve, check the residual and compute the reaction of every constrained
//! set (and, when the scene asks, the recovered stress).

use super::setup::{Plan, Setup, Timings};
use super::shares::{bond_counts, bonds_held, total_bonds};
use super::system::{agreed, check_range, reactions, right_hand_side, Reaction, System};
use super::{forward, Observer};
use crate::assembly::dofs::DofMap;
use crate::assembly::forces::internal_forces;
use crate::assembly::loads::AppliedLoad;
use crate::assembly::pattern::Pattern;
use crate::assembly::stiffness::Stiffness;
use crate::discretization::Discretization;
use crate::error::Error;
use crate::model::{AnyModel, Block};
use crate::notes::Notes;
use crate::scene::{Dimension, ModelKind, Scene, SolverMethod};
use crate::solve::cholesky::PivotStats;
use crate::solve::gmres::GmresReport;
use crate::solve::pipeline::{Pipeline, SolveReport};
use crate::solve::route::OrderingReport;
use serde::Serialize;
use std::time::Instant;

/// Problem sizes.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Counts {
    /// Points.
    pub points: usize,
    /// Bonds (ordered pairs).
    pub bonds: usize,
    /// Free degrees of freedom.
    pub dofs: usize,
    /// Prescribed degrees of freedom.
    pub prescribed_dofs: usize,
    /// Stored entries of the reduced `K` (both triangles).
    pub nnz_k: usize,
    /// The solver route taken (`iterative` when a direct factor was too costly).
    pub solver: SolverMethod,
    /// Stored entries of the Cholesky factor (None for LU; the coarse factor
    /// for the iterative route).
    pub nnz_l: Option<usize>,
    /// The factor's fill-reducing ordering and the sizes of those analysed.
    pub ordering: Option<OrderingReport>,
    /// Pivot range of the Cholesky factor (None for LU).
    pub pivots: Option<PivotStats>,
    /// `‖K − Kᵀ‖_F / ‖K‖_F` (round-off for the bond-based model).
    pub asymmetry: f64,
    /// Steps of iterative refinement applied after the solve.
    pub refinement_steps: usize,
    /// GMRES iterations and final residual, when GMRES was used.
    pub gmres: Option<GmresReport>,
    /// Isolated points removed.
    pub removed_points: usize,
    /// The bonds each process holds when the body is discretised over
    /// several processes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bonds_held: Option<Vec<usize>>,
    /// What PETSc used and did (`solver.method = "petsc"`).
    #[cfg(feature = "mpi")]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub petsc: Option<crate::solve::petsc::PetscReport>,
}

/// The reduced linear system, kept for export.
pub struct LinearSystem {
    /// Pattern of `K`.
    pub pattern: Pattern,
    /// Values of `K`.
    pub stiffness: Stiffness,
    /// Right-hand side.
    pub rhs: Vec<f64>,
}

/// Everything a static run produces.
pub struct StaticSolution {
    /// The discretisation.
    pub disc: Discretization,
    /// Degrees of freedom.
    pub dofs: DofMap,
    /// Displacement of every point.
    pub u: Vec<[f64; 3]>,
    /// Reactions per constrained set.
    pub reactions: Vec<Reaction>,
    /// Applied loads.
    pub loads: Vec<AppliedLoad>,
    /// `‖K u − b‖/‖b‖` of the reduced system.
    pub residual: f64,
    /// Wall time per phase.
    pub timings: Timings,
    /// Sizes.
    pub counts: Counts,
    /// Recovered stress per point, when the scene asks for it.
    pub stress: Option<Vec<Block>>,
    /// Intact bonds touching each point (as owner or neighbour).
    pub bond_counts: Vec<u32>,
    /// The reduced system.
    pub system: LinearSystem,
    /// The points the outputs read.
    pub plan: Plan,
}

impl Counts {
    /// The sizes of a solve of `pipeline` on `disc`, with what `report` says.
    fn of(
        disc: &Discretization,
        dofs: &DofMap,
        pipeline: &Pipeline,
        asymmetry: f64,
        report: &SolveReport,
    ) -> Self {
        Counts {
            points: disc.points.len(),
            bonds: total_bonds(disc),
            dofs: dofs.n_free(),
            prescribed_dofs: disc.points.len() * disc.d - dofs.n_free(),
            nnz_k: pipeline.stored_entries(),
            solver: pipeline.method(),
            nnz_l: pipeline.nnz_factor(),
            ordering: pipeline.ordering,
            pivots: pipeline.pivot_stats(),
            asymmetry,
            refinement_steps: report.refinement_steps,
            gmres: report.gmres,
            removed_points: disc.removed_isolated,
            bonds_held: bonds_held(disc),
            #[cfg(feature = "mpi")]
            petsc: pipeline.petsc_report().cloned(),
        }
    }
}

impl StaticSolution {
    /// The reaction force of the constrained set `name`, if there is one.
    pub fn reaction(&self, name: &str) -> Option<[f64; 3]> {
        self.reactions
            .iter()
            .find(|r| r.name == name)
            .map(|r| r.force)
    }
}

/// The setup of `scene` (notes dropped): for the crate's tests and studies.
#[cfg(feature = "fixtures")]
pub fn prepare(scene: &Scene) -> Result<Setup, Error> {
    super::check(scene, &mut ())
}

/// Solves the static problem of `scene` (notes dropped): for the crate's
/// tests and studies.
#[cfg(feature = "fixtures")]
pub fn solve(scene: &Scene) -> Result<StaticSolution, Error> {
    run(scene, prepare(scene)?, &mut ())
}

/// Solves the static problem of `scene` from its `setup`; notes go to `observer`.
pub fn run(
    scene: &Scene,
    setup: Setup,
    observer: &mut dyn Observer,
) -> Result<StaticSolution, Error> {
    let mut notes = Notes::default();
    note_near_incompressible(scene, &mut notes);
    forward(&mut notes, observer);
    let model = agreed(
        &scene.solver,
        AnyModel::new(scene, &setup.disc).map_err(Error::from),
    )?;
    model.warnings().into_iter().for_each(|w| notes.push(w));
    let result = solve_with(&model, scene, setup, &mut notes);
    forward(&mut notes, observer);
    result
}

/// Suggests the gradient dilatation for nearly incompressible shear-model
/// materials in plane strain and 3D (plane stress stays compressible), with
/// the paper's force (the energy formulation's dilatation is already the
/// trace of its gradient).
fn note_near_incompressible(scene: &Scene, notes: &mut Notes) {
    if scene.model.kind != ModelKind::Shear
        || scene.model.energy_shear()
        || scene.model.gradient_dilatation()
        || scene.model.dimension == Dimension::PlaneStress
    {
        return;
    }
    if let Some(m) = scene
        .materials
        .iter()
        .find(|m| m.poisson_ratio >= crate::model::shear::NEAR_INCOMPRESSIBLE)
    {
        notes.push(format!(
            "note: material {:?} has ν = {}: nearly incompressible; the weighted dilatation's \
             error at boundary points is multiplied by λ there (spurious boundary stresses); \
             model.dilatation = \"gradient\" is more accurate (validation/stability)",
            m.name, m.poisson_ratio
        ));
    }
}

/// Solves with a given model on a given setup.
fn solve_with(
    model: &AnyModel,
    scene: &Scene,
    setup: Setup,
    notes: &mut Notes,
) -> Result<StaticSolution, Error> {
    let Setup {
        disc,
        dofs,
        f_ext,
        loads,
        plan,
        mut timings,
        ..
    } = setup;
    // The pattern's memory check counts each process's own entries: one may
    // refuse while the others go on (a collective call).
    let system = System::new(scene, &disc, &dofs, model, &mut timings, notes);
    let mut system = agreed(&scene.solver, system)?;
    let t = Instant::now();
    let rhs = right_hand_side(model, &disc, &dofs, &f_ext, 1.0);
    timings.assembly += t.elapsed().as_secs_f64();
    let in_range = check_range(
        &system.stiffness,
        system.pipeline.pattern(),
        &dofs,
        &disc,
        None,
    );
    agreed(&scene.solver, in_range)?;
    let asymmetry = system
        .pipeline
        .asymmetry(&system.stiffness, super::system::layout(&disc, &dofs))?;
    // The model's residual, from the bond forces (Pipeline::solve_with_residual).
    let model_residual = |x: &[f64]| -> Vec<f64> {
        let f_int = internal_forces(model, &disc, &dofs.expand(x), true);
        dofs.free_dofs
            .iter()
            .map(|&(i, c)| f_ext[i as usize][c as usize] + f_int[i as usize][c as usize])
            .collect()
    };
    let layout = super::system::layout(&disc, &dofs);
    let (pipeline, matrices) = system.parts();
    let solved = pipeline.solve_with_residual(layout, matrices, &rhs, &model_residual, notes)?;
    let report = &solved.report;
    timings.numeric_factorization = report.factor_seconds;
    if report.refinement_steps > 0 {
        notes.push(format!(
            "note: {} step(s) of iterative refinement brought the relative residual to {:.1e}",
            report.refinement_steps, report.residual
        ));
    }
    let t = Instant::now();
    let u = dofs.expand(&solved.x);
    let reactions = reactions(model, &disc, &dofs, &f_ext, &u, 1.0);
    timings.solve = report.solve_seconds + t.elapsed().as_secs_f64();
    let stress = match scene.output.stress {
        true => Some(super::stress::field(model, &disc, &u)?),
        false => None,
    };
    let counts = Counts::of(&disc, &dofs, &system.pipeline, asymmetry, report);
    let bond_counts = bond_counts(&disc);
    let residual = report.residual;
    Ok(StaticSolution {
        disc,
        dofs,
        u,
        reactions,
        loads,
        residual,
        timings,
        counts,
        stress,
        bond_counts,
        system: LinearSystem {
            pattern: system.pipeline.into_pattern(),
            stiffness: system.stiffness,
            rhs,
        },
        plan,
    })
}
