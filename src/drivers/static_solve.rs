//! The static driver: discretise, assemble the linearised `K`, eliminate the
//! prescribed degrees of freedom, factorise, solve, check the residual and
//! compute the reaction of every constrained set.

use crate::assembly::dofs::DofMap;
use crate::assembly::forces::internal_forces;
use crate::assembly::loads::{external_forces, AppliedLoad};
use crate::assembly::pattern::Pattern;
use crate::assembly::rigid_modes;
use crate::assembly::stiffness::Stiffness;
use crate::discretization::{self, Discretization};
use crate::error::{Error, NumericalError};
use crate::model::bond_based::BondBased;
use crate::model::shear::Shear;
use crate::model::{Coupling, Model};
use crate::scene::{Dimension, ModelKind, Scene, SolverMethod};
use crate::solve::{
    refine, relative_residual, Cholesky, FactorError, LinearSolver, PivotStats, SparseLu,
};
use serde::Serialize;
use std::time::Instant;

/// GMRES iterations allowed with the bond-based preconditioner before switching
/// to the symmetric part of the shear tangent.
const PRECONDITIONER_BUDGET: usize = 120;

/// Largest relative residual accepted from a direct solve.
pub const RESIDUAL_THRESHOLD: f64 = 1e-8;

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
    /// Stored entries of the Cholesky factor (None for LU).
    pub nnz_l: Option<usize>,
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
    /// Sum over the set of `K u − f_ext` (N).
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
    let dofs = DofMap::new(&disc.points, disc.d, &scene.boundaries)?;
    let (f_ext, loads) = external_forces(&disc.points, disc.d, &scene.loads)?;
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

/// Poisson ratio from which the weighted dilatation's boundary error, multiplied
/// by λ, dominates (validation/stability: L2(u) error 1.2× the ν = 0.3 value at
/// ν = 0.49, 1.7× at 0.4999, and spurious boundary stresses of several times the
/// peak stress).
const NEAR_INCOMPRESSIBLE: f64 = 0.49;

/// Suggests the gradient dilatation for nearly incompressible shear-model
/// materials in plane strain and 3D (plane stress stays compressible).
fn warn_near_incompressible(scene: &Scene) {
    if scene.gradient_dilatation || scene.dimension == Dimension::PlaneStress {
        return;
    }
    if let Some(m) = scene
        .materials
        .iter()
        .find(|m| m.poisson_ratio >= NEAR_INCOMPRESSIBLE)
    {
        eprintln!(
            "note: material {:?} has ν = {}: nearly incompressible; the weighted dilatation's \
             error at boundary points is multiplied by λ there (spurious boundary stresses); \
             model.dilatation = \"gradient\" is more accurate (validation/stability)",
            m.name, m.poisson_ratio
        );
    }
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
    let d = disc.d;

    let t = Instant::now();
    let pattern = Pattern::new(&disc, &dofs, model.coupling());
    // GMRES factorises the symmetric part restricted to bonded pairs (the star
    // pattern); the other methods factorise K itself.
    let star = (scene.solver == SolverMethod::Gmres && model.coupling() == Coupling::Family)
        .then(|| Pattern::new(&disc, &dofs, Coupling::Star));
    let factored_pattern = star.as_ref().unwrap_or(&pattern);
    timings.pattern = t.elapsed().as_secs_f64();

    // The symbolic Cholesky factorisation needs only the pattern: it runs before
    // any value is assembled, so a factor too large for memory is refused early.
    let t = Instant::now();
    let cholesky = match scene.solver {
        SolverMethod::Cholesky | SolverMethod::Gmres => {
            let chol = Cholesky::analyse(factored_pattern.symbolic())?;
            crate::solve::check_memory(chol.factor_bytes(), scene.memory_limit_bytes)?;
            Some(chol)
        }
        SolverMethod::Lu => None,
    };
    let symbolic_time = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let stiffness = Stiffness::assemble(model, &disc, &dofs, &pattern);
    let f_prescribed = internal_forces(model, &disc, &dofs.prescribed, true);
    let rhs: Vec<f64> = dofs
        .free_dofs
        .iter()
        .map(|&(i, c)| f_ext[i as usize][c as usize] + f_prescribed[i as usize][c as usize])
        .collect();
    timings.assembly = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let transpose = Stiffness::transpose_positions(&pattern);
    let asymmetry = stiffness.asymmetry(&transpose);
    let symmetric = (scene.solver == SolverMethod::Gmres).then(|| match &star {
        Some(star) => {
            let bb = BondBased::new(&disc, scene.dimension, &scene.materials, scene.thickness);
            Stiffness::assemble(&bb, &disc, &dofs, star)
        }
        None => stiffness.symmetric_part(&transpose),
    });
    let factored = symmetric
        .as_ref()
        .unwrap_or(&stiffness)
        .view(factored_pattern);
    let mut solver = match cholesky {
        // The cheap bond-based preconditioner gets a short budget (see below).
        Some(chol) if scene.solver == SolverMethod::Gmres => LinearSolver::Gmres(
            chol,
            if star.is_some() {
                PRECONDITIONER_BUDGET
            } else {
                600
            },
        ),
        Some(chol) => LinearSolver::Cholesky(chol),
        None => LinearSolver::Lu(SparseLu::analyse(factored)?),
    };
    timings.symbolic_factorization = symbolic_time + t.elapsed().as_secs_f64();

    let t = Instant::now();
    solver
        .factorize(factored)
        .map_err(|e| factor_error(e, &dofs, &disc))?;
    timings.numeric_factorization = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let apply = |v: &[f64]| stiffness.mul(&pattern, v);
    let (mut x, mut iterative) = solver.solve(&apply, &rhs);
    if let (Some(first), Some(_)) = (iterative, &star) {
        if !first.converged {
            // Near incompressibility the bond-based preconditioner (which has no
            // Poisson ratio) stalls: continue with the full symmetric part.
            eprintln!(
                "note: GMRES with the bond-based preconditioner stopped at residual {:.1e} after {} iterations; \
                 continuing with the Cholesky factor of the symmetric part",
                first.relative_residual, first.iterations
            );
            let full = stiffness.symmetric_part(&transpose);
            let mut chol = Cholesky::analyse(pattern.symbolic())?;
            crate::solve::check_memory(chol.factor_bytes(), scene.memory_limit_bytes)?;
            let fallback = match chol.factorize(full.view(&pattern)) {
                Ok(()) => LinearSolver::Gmres(chol, 600),
                Err(FactorError::NonPositivePivot(_) | FactorError::NearlySingular(..)) => {
                    // Possible with the gradient dilatation near ν = 1/2: K is
                    // regular but its symmetric part is indefinite.
                    eprintln!(
                        "note: the symmetric part of the tangent is not positive definite; \
                         solving with sparse LU instead"
                    );
                    drop(chol);
                    let mut lu = LinearSolver::Lu(SparseLu::analyse(stiffness.view(&pattern))?);
                    lu.factorize(stiffness.view(&pattern))
                        .map_err(|e| factor_error(e, &dofs, &disc))?;
                    lu
                }
                Err(e) => return Err(factor_error(e, &dofs, &disc)),
            };
            let kx = apply(&x);
            let r: Vec<f64> = rhs.iter().zip(&kx).map(|(b, k)| b - k).collect();
            let (dx, second) = fallback.solve(&apply, &r);
            x.iter_mut().zip(&dx).for_each(|(xi, di)| *xi += di);
            iterative = second.map(|s| crate::solve::gmres::GmresReport {
                iterations: first.iterations + s.iterations,
                ..s
            });
            solver = fallback;
        }
    }
    if x.iter().any(|v| !v.is_finite()) {
        return Err(NumericalError::NonFinite {
            what: "the displacement solution".into(),
        }
        .into());
    }
    // Direct solvers are refined with their own factor when the residual is
    // above REFINE_THRESHOLD; GMRES already iterates to its tolerance.
    let (residual, refinement_steps) = if iterative.is_none() {
        refine(
            &apply,
            &|v: &mut [f64]| solver.solve_in_place(v),
            &rhs,
            &mut x,
        )
    } else {
        (relative_residual(&apply(&x), &rhs), 0)
    };
    if refinement_steps > 0 {
        eprintln!("note: {refinement_steps} step(s) of iterative refinement brought the relative residual to {residual:.1e}");
    }
    if !(residual <= RESIDUAL_THRESHOLD) {
        return Err(NumericalError::ResidualTooLarge {
            residual,
            threshold: RESIDUAL_THRESHOLD,
            refinement_steps,
        }
        .into());
    }
    let u = dofs.expand(&x);
    let f_int = internal_forces(model, &disc, &u, true);
    let reactions = dofs
        .sets
        .iter()
        .map(|set| {
            let mut force = [0.0; 3];
            for &i in &set.points {
                for c in 0..d {
                    force[c] -= f_int[i][c] + f_ext[i][c];
                }
            }
            Reaction {
                name: set.name.clone(),
                points: set.points.len(),
                force,
            }
        })
        .collect();
    timings.solve = t.elapsed().as_secs_f64();
    let stress = scene.output.stress.then(|| {
        use rayon::prelude::*;
        (0..disc.points.len())
            .into_par_iter()
            .map(|i| model.stress(&disc, i, &u).unwrap_or_default())
            .collect::<Vec<_>>()
    });
    if stress
        .as_ref()
        .is_some_and(|s| s.iter().flatten().flatten().any(|v| !v.is_finite()))
    {
        return Err(NumericalError::NonFinite {
            what: "the recovered stress".into(),
        }
        .into());
    }

    let counts = Counts {
        points: disc.points.len(),
        bonds: disc.bonds.len(),
        dofs: dofs.n_free(),
        prescribed_dofs: disc.points.len() * d - dofs.n_free(),
        nnz_k: pattern.nnz(),
        nnz_l: solver.nnz_factor(),
        pivots: solver.pivot_stats(),
        asymmetry,
        refinement_steps,
        gmres: iterative,
        removed_points: disc.removed_isolated,
    };
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
            pattern,
            stiffness,
            rhs,
        },
    })
}

fn factor_error(e: FactorError, dofs: &DofMap, disc: &Discretization) -> Error {
    let locate = |k: usize| {
        let (i, c) = dofs.free_dofs[k];
        (i as usize, c as usize)
    };
    match e {
        FactorError::NonPositivePivot(k) => {
            let (point, component) = locate(k);
            NumericalError::NonPositivePivot {
                point,
                component,
                position: disc.points.x[point],
            }
            .into()
        }
        FactorError::Singular(k) => {
            let (point, component) = locate(k);
            NumericalError::StructurallySingular { point, component }.into()
        }
        FactorError::NearlySingular(k, ratio) => {
            let (point, component) = locate(k);
            NumericalError::NearlySingular {
                point,
                component,
                position: disc.points.x[point],
                ratio,
            }
            .into()
        }
        FactorError::Generic => {
            NumericalError::Solver("factorisation failed (out of memory?)".into()).into()
        }
    }
}
