//! The static driver: discretise, assemble the linearised `K`, eliminate the
//! prescribed degrees of freedom, factorise, solve, check the residual and
//! compute the reaction of every constrained set.

use crate::assembly::dofs::DofMap;
use crate::assembly::forces::{internal_forces, internal_forces_on};
use crate::assembly::loads::{external_forces, AppliedLoad};
use crate::assembly::pattern::Pattern;
use crate::assembly::rigid_modes;
use crate::assembly::stiffness::Stiffness;
use crate::discretization::{self, Discretization};
use crate::error::{Error, NumericalError};
use crate::model::bond_based::BondBased;
use crate::model::shear::Shear;
use crate::model::Coupling;
use crate::model::Model;
use crate::notes::Notes;
use crate::scene::SolverSettings;
use crate::scene::{Dimension, ModelKind, Scene};
use crate::solve::cholesky::PivotStats;
use crate::solve::pipeline::Pipeline;
use crate::solve::route::{self, Hints};
use crate::solve::{Layout, Matrices};
use serde::Serialize;
use std::time::Instant;

/// Wall time per phase in seconds.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Timings {
    /// Point generation (grids, files, holes).
    pub discretization: f64,
    /// Neighbour search and bond construction.
    pub neighbour_search: f64,
    /// Sparsity pattern.
    pub pattern: f64,
    /// Stiffness values, loads and right-hand side.
    pub assembly: f64,
    /// Symbolic factorisation (ordering).
    pub symbolic_factorization: f64,
    /// Numeric factorisation.
    pub numeric_factorization: f64,
    /// Triangular solves, residual and reactions.
    pub solve: f64,
}

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
    pub solver: crate::scene::SolverMethod,
    /// Stored entries of the Cholesky factor (None for LU; the coarse factor
    /// for the iterative route).
    pub nnz_l: Option<usize>,
    /// The factor's fill-reducing ordering and the sizes of those analysed.
    pub ordering: Option<crate::solve::route::OrderingReport>,
    /// Pivot range of the Cholesky factor (None for LU).
    pub pivots: Option<PivotStats>,
    /// `‖K − Kᵀ‖_F / ‖K‖_F` (round-off for the bond-based model).
    pub asymmetry: f64,
    /// Steps of iterative refinement applied after the solve.
    pub refinement_steps: usize,
    /// GMRES iterations and final residual, when GMRES was used.
    pub gmres: Option<crate::solve::gmres::GmresReport>,
    /// Isolated points removed.
    pub removed_points: usize,
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
    pub stress: Option<Vec<crate::model::Block>>,
    /// The reduced system.
    pub system: LinearSystem,
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

/// A discretised scene, ready to solve (lets callers check output requests
/// against the points before any numerics).
pub struct Prepared {
    /// Points and bonds.
    pub disc: Discretization,
    /// Degrees of freedom and constrained sets.
    pub dofs: DofMap,
    /// External force on every point.
    pub f_ext: Vec<[f64; 3]>,
    /// Applied loads.
    pub loads: Vec<AppliedLoad>,
    /// Time spent so far.
    pub timings: Timings,
}

/// Discretises `scene` (points, then bonds), selects the constrained and loaded
/// points, and checks that no rigid motion is left free: every check that does
/// not need the stiffness matrix.
pub fn prepare(scene: &Scene) -> Result<Prepared, Error> {
    let mut timings = Timings::default();
    let t = Instant::now();
    let raw = discretization::generate_points(scene)?;
    timings.discretization = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let disc = discretization::discretize(scene, raw)?;
    timings.neighbour_search = t.elapsed().as_secs_f64();
    let dofs = DofMap::new(&disc, &scene.boundaries)?;
    dofs.overlap_notes().iter().for_each(|n| eprintln!("{n}"));
    let (f_ext, loads) = external_forces(&disc, &scene.loads)?;
    if dofs.n_free() == 0 {
        return Err(NumericalError::NothingToSolve.into());
    }
    rigid_modes::check(&disc, &dofs)?;
    Ok(Prepared {
        disc,
        dofs,
        f_ext,
        loads,
        timings,
    })
}

impl Prepared {
    /// Solves with the scene's model.
    pub fn solve(self, scene: &Scene) -> Result<StaticSolution, Error> {
        match scene.model {
            ModelKind::BondBased => {
                let model = BondBased::new(
                    &self.disc,
                    scene.dimension,
                    &scene.materials,
                    scene.thickness,
                );
                solve_with(&model, scene, self)
            }
            ModelKind::Shear => {
                warn_near_incompressible(scene);
                let model = Shear::new(
                    &self.disc,
                    scene.dimension,
                    &scene.materials,
                    scene.gradient_dilatation,
                )?;
                solve_with(&model, scene, self)
            }
        }
    }
}

/// Suggests the gradient dilatation for nearly incompressible shear-model
/// materials in plane strain and 3D (plane stress stays compressible).
fn warn_near_incompressible(scene: &Scene) {
    if scene.gradient_dilatation || scene.dimension == Dimension::PlaneStress {
        return;
    }
    if let Some(m) = scene
        .materials
        .iter()
        .find(|m| m.poisson_ratio >= crate::model::shear::NEAR_INCOMPRESSIBLE)
    {
        eprintln!(
            "note: material {:?} has ν = {}: nearly incompressible; the weighted dilatation's \
             error at boundary points is multiplied by λ there (spurious boundary stresses); \
             model.dilatation = \"gradient\" is more accurate (validation/stability)",
            m.name, m.poisson_ratio
        );
    }
}

/// What the solver should know about `scene` besides its matrix: a symmetric
/// `K` (a star coupling), a fracture run, or a shear-model body with a nearly
/// incompressible material ([`crate::model::shear::NEAR_INCOMPRESSIBLE`]).
pub fn solver_hints(scene: &Scene, coupling: Coupling) -> Hints {
    Hints {
        symmetric: coupling == Coupling::Star,
        fracture: scene.quasi_static.is_some(),
        near_incompressible: scene.model == ModelKind::Shear
            && scene
                .materials
                .iter()
                .any(|m| m.poisson_ratio >= crate::model::shear::NEAR_INCOMPRESSIBLE),
    }
}

/// The patterns of `K` and, when the route asks for one, of the bond-based
/// surrogate, with the time they took; a route that cannot take this many
/// unknowns is refused first.
pub fn patterns(
    disc: &Discretization,
    dofs: &DofMap,
    coupling: Coupling,
    settings: &SolverSettings,
    hints: Hints,
) -> Result<((Pattern, f64), Option<Pattern>), Error> {
    route::check_size(settings, dofs.n_free())?;
    let t = Instant::now();
    let limit = settings.memory_limit_bytes;
    let pattern = Pattern::new(disc, dofs, coupling, limit)?;
    let surrogate = route::wants_surrogate(settings, hints)
        .then(|| Pattern::new(disc, dofs, Coupling::Star, limit))
        .transpose()?;
    Ok(((pattern, t.elapsed().as_secs_f64()), surrogate))
}

/// What the solver knows of the body.
pub fn layout<'a>(disc: &'a Discretization, dofs: &'a DofMap) -> Layout<'a> {
    Layout {
        x: &disc.points.x,
        spacing: &disc.points.spacing,
        dofs,
    }
}

/// Refuses a stiffness that left the floating-point range
/// ([`Stiffness::out_of_range`]), naming the point's source.
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

/// Prints the notes so far on stderr.
pub fn print_notes(notes: &mut Notes) {
    notes.take().iter().for_each(|n| eprintln!("{n}"));
}

/// Discretises and solves the static problem of `scene`.
pub fn solve(scene: &Scene) -> Result<StaticSolution, Error> {
    prepare(scene)?.solve(scene)
}

/// Solves with a given model on a given discretisation.
pub fn solve_with<M: Model>(
    model: &M,
    scene: &Scene,
    prepared: Prepared,
) -> Result<StaticSolution, Error> {
    let Prepared {
        disc,
        dofs,
        f_ext,
        loads,
        mut timings,
    } = prepared;

    // The symbolic analysis needs only the pattern: it runs before any value is
    // assembled, so a factor too large for memory is refused early.
    let mut notes = Notes::default();
    let hints = solver_hints(scene, model.coupling());
    let (pattern, surrogate) = patterns(&disc, &dofs, model.coupling(), &scene.solver, hints)?;
    timings.pattern = pattern.1;
    let layout = layout(&disc, &dofs);
    let analysed = Pipeline::analyse(
        pattern.0,
        surrogate,
        layout,
        scene.solver,
        hints,
        &mut notes,
    );
    print_notes(&mut notes);
    let mut pipeline = analysed?;
    timings.symbolic_factorization = pipeline.symbolic_seconds;

    let t = Instant::now();
    let stiffness = Stiffness::assemble(model, &disc, &dofs, pipeline.pattern());
    let rhs = right_hand_side(model, &disc, &dofs, &f_ext, 1.0);
    let surrogate = pipeline.surrogate_pattern().map(|p| {
        let bond_based = BondBased::new(&disc, scene.dimension, &scene.materials, scene.thickness);
        Stiffness::assemble(&bond_based, &disc, &dofs, p)
    });
    timings.assembly = t.elapsed().as_secs_f64();
    check_range(&stiffness, pipeline.pattern(), &dofs, &disc, None)?;

    let asymmetry = pipeline.asymmetry(&stiffness);
    // The model's residual, from the bond forces (pipeline::solve_with_residual).
    let model_residual = |x: &[f64]| -> Vec<f64> {
        let f_int = internal_forces(model, &disc, &dofs.expand(x), true);
        dofs.free_dofs
            .iter()
            .map(|&(i, c)| f_ext[i as usize][c as usize] + f_int[i as usize][c as usize])
            .collect()
    };
    let matrices = Matrices {
        k: &stiffness,
        surrogate: surrogate.as_ref(),
    };
    let solved = pipeline.solve_with_residual(layout, matrices, &rhs, &model_residual, &mut notes);
    print_notes(&mut notes);
    let solved = solved?;
    let report = &solved.report;
    timings.numeric_factorization = report.factor_seconds;
    if report.refinement_steps > 0 {
        eprintln!(
            "note: {} step(s) of iterative refinement brought the relative residual to {:.1e}",
            report.refinement_steps, report.residual
        );
    }
    let t = Instant::now();
    let u = dofs.expand(&solved.x);
    let reactions = reactions(model, &disc, &dofs, &f_ext, &u, 1.0);
    timings.solve = report.solve_seconds + t.elapsed().as_secs_f64();
    let stress = scene.output.stress.then(|| {
        use rayon::prelude::*;
        (0..disc.points.len())
            .into_par_iter()
            .map(|i| model.stress(&disc, i, &u).unwrap_or_default())
            .collect::<Vec<_>>()
    });
    if let Some(i) = stress.as_ref().and_then(|s| {
        s.iter()
            .position(|b| b.iter().flatten().any(|v| !v.is_finite()))
    }) {
        return Err(NumericalError::NonFinite {
            what: format!(
                "the recovered stress of point {i} (x = {:?}); nothing was written",
                disc.points.x[i]
            ),
        }
        .into());
    }

    let counts = Counts {
        points: disc.points.len(),
        bonds: disc.bonds.len(),
        dofs: dofs.n_free(),
        prescribed_dofs: disc.points.len() * disc.d - dofs.n_free(),
        nnz_k: pipeline.pattern().nnz(),
        solver: pipeline.method(),
        nnz_l: pipeline.nnz_factor(),
        ordering: pipeline.ordering,
        pivots: pipeline.pivot_stats(),
        asymmetry,
        refinement_steps: report.refinement_steps,
        gmres: report.gmres,
        removed_points: disc.removed_isolated,
    };
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
        system: LinearSystem {
            pattern: pipeline.into_pattern(),
            stiffness,
            rhs,
        },
    })
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

/// The reaction of every constrained set for displacements `u` under the
/// external forces `f_ext` scaled by `load_factor`: the force the supports
/// exert on the body, `−Σ (F_int + f_ext)` over the prescribed components the
/// set owns (formulation Sec. 7; overlapping sets: [`crate::assembly::dofs::ConstrainedSet`]), so the
/// reactions of all sets sum to the total support force. Only the
/// bonds touching the sets are evaluated.
pub fn reactions<M: Model>(
    model: &M,
    disc: &Discretization,
    dofs: &DofMap,
    f_ext: &[[f64; 3]],
    u: &[[f64; 3]],
    load_factor: f64,
) -> Vec<Reaction> {
    dofs.sets
        .iter()
        .map(|set| {
            let f_int = internal_forces_on(model, disc, u, true, &set.points);
            // Only the components this set owns (the first set to prescribe a
            // component counts its reaction: `ConstrainedSet`).
            let mut force = [0.0; 3];
            for &(i, c) in &set.owned {
                let (i, c) = (i as usize, c as usize);
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
        .collect()
}
