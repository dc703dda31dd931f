//! The `[solver]` vocabulary: which route solves `K u = f`
//! ([`SolverMethod`]), with which fill-reducing ordering ([`Ordering`]) and
//! precision ([`Precision`]), within which memory. The scene owns it; the
//! solver (`solve::pipeline`) reads it as [`SolverSettings`], together with
//! hints the driver computes (a fracture run, a nearly incompressible body),
//! and never reads the rest of the scene.

use super::fields::positive;
use super::spec::SolverSpec;
pub use super::spec::{Ordering, PetscSolver, Precision, SolverMethod};
use super::DynamicsMethod;
use crate::error::InputError;

/// Bytes per GiB.
const GIB: f64 = 1073741824.0;

/// The validated `[solver]` section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Route (`solver.method`, or the model's default).
    pub method: SolverMethod,
    /// `solver.method` was not given: a factor that does not fit is replaced by
    /// the `iterative` route, and so is a costly one outside fracture runs.
    pub automatic: bool,
    /// User limit on the size of the bonds, the pattern and a sparse factor in
    /// bytes (`solver.memory_limit_gib`).
    pub memory_limit_bytes: Option<f64>,
    /// Iterations of a re-solve with the previous factor before refactorising
    /// (`solver.refactor_iterations`; None: chosen from measured costs).
    pub refactor_iterations: Option<usize>,
    /// Fill-reducing ordering of the Cholesky factor.
    pub ordering: Ordering,
    /// Precision of the Cholesky factor.
    pub precision: Precision,
    /// What PETSc solves with (the `petsc` route).
    pub petsc_solver: PetscSolver,
}

impl SolverSettings {
    /// The default route of a model whose tangent is `symmetric` (the
    /// bond-based model, the shear model's energy formulation: Cholesky) or not
    /// (the paper's shear force: GMRES), chosen automatically, with every other
    /// setting at its default.
    pub fn automatic(symmetric: bool) -> Self {
        Self {
            method: if symmetric {
                SolverMethod::Cholesky
            } else {
                SolverMethod::Gmres
            },
            automatic: true,
            memory_limit_bytes: None,
            refactor_iterations: None,
            ordering: Ordering::Auto,
            precision: Precision::Auto,
            petsc_solver: PetscSolver::Gamg,
        }
    }
}

/// What kind of run a scene asks for, as far as the solver cares.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct RunKind {
    /// `[dynamics]`: explicit dynamics (its method), no linear solve.
    pub(super) dynamics: Option<DynamicsMethod>,
    /// `[quasi_static]`: fracture, with re-solves as bonds break.
    pub(super) fracture: bool,
}

/// Validates the keys of `[solver]` for a `run` (the `petsc` route solves
/// static and quasi-static problems, the latter with GAMG, and runs Verlet
/// dynamics on the processes of an MPI run).
pub(super) fn validate(
    spec: &SolverSpec,
    symmetric: bool,
    run: RunKind,
) -> Result<SolverSettings, InputError> {
    if spec.method == Some(SolverMethod::Petsc) {
        check_petsc(run.dynamics)?;
    }
    if let Some(method @ (SolverMethod::Iterative | SolverMethod::Petsc)) = spec.method {
        for (key, present) in [
            ("solver.ordering", spec.ordering.is_some()),
            ("solver.precision", spec.precision.is_some()),
        ] {
            if present {
                let name = match method {
                    SolverMethod::Petsc => "\"petsc\"",
                    _ => "\"iterative\"",
                };
                return Err(InputError::new(
                    key,
                    format!(
                        "applies to the direct factor, which solver.method = {name} \
                         does not compute; remove it or choose \"cholesky\" or \"gmres\""
                    ),
                ));
            }
        }
    }
    if spec.petsc_solver.is_some() && spec.method != Some(SolverMethod::Petsc) {
        return Err(InputError::new(
            "solver.petsc_solver",
            "chooses what PETSc solves with, and applies to solver.method = \"petsc\" only; \
             remove it or set the method",
        ));
    }
    if run.dynamics.is_some() && spec.petsc_solver.is_some() {
        return Err(InputError::new(
            "solver.petsc_solver",
            "chooses what PETSc solves with, and an explicit dynamics run solves no linear \
             system; remove it",
        ));
    }
    if run.fracture && spec.petsc_solver == Some(PetscSolver::Mumps) {
        return Err(InputError::new(
            "solver.petsc_solver",
            "\"mumps\" is offered for static solves only: a fracture run re-solves after \
             every break, which MUMPS's factor (applied once, not iterated) could only do by \
             factorising afresh, and it stops at a point that becomes a mechanism instead \
             of naming it; use \"gamg\" (the default), whose re-solves reuse its hierarchy",
        ));
    }
    if spec.refactor_iterations == Some(0) {
        return Err(InputError::new(
            "solver.refactor_iterations",
            "0 would refactorise before every re-solve; give at least 1",
        ));
    }
    let defaults = SolverSettings::automatic(symmetric);
    Ok(SolverSettings {
        method: spec.method.unwrap_or(defaults.method),
        automatic: spec.method.is_none(),
        memory_limit_bytes: match spec.memory_limit_gib {
            Some(gib) => {
                positive("solver.memory_limit_gib", gib)?;
                Some(gib * GIB)
            }
            None => None,
        },
        refactor_iterations: spec.refactor_iterations,
        ordering: spec.ordering.unwrap_or_default(),
        precision: spec.precision.unwrap_or_default(),
        petsc_solver: spec.petsc_solver.unwrap_or_default(),
    })
}

/// Refuses `solver.method = "petsc"` where this build or this run cannot
/// take it: a build without the `mpi` feature, dynamic relaxation.
fn check_petsc(dynamics: Option<DynamicsMethod>) -> Result<(), InputError> {
    if !cfg!(feature = "mpi") {
        return Err(InputError::new(
            "solver.method",
            "\"petsc\" needs dhpd built with the mpi feature and PETSc installed (Debian: \
             apt-get install petsc-dev; then cargo build --release --features mpi); on one \
             machine leave solver.method out or use \"iterative\", which solves the largest \
             bodies without a factor",
        ));
    }
    if dynamics == Some(DynamicsMethod::Relaxation) {
        return Err(InputError::new(
            "solver.method",
            "\"petsc\" runs explicit dynamics with method = \"verlet\" only for now \
             (dynamic relaxation, whose adaptive damping takes sums over the whole body \
             every step, runs on one process); remove solver.method from this [dynamics] \
             scene",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{check_petsc, validate, PetscSolver, RunKind, SolverSpec};
    use crate::scene::DynamicsMethod;

    #[test]
    fn the_petsc_solver_needs_the_petsc_route() {
        let spec = SolverSpec {
            petsc_solver: Some(PetscSolver::Mumps),
            ..Default::default()
        };
        let e = validate(&spec, true, RunKind::default()).unwrap_err();
        assert_eq!(e.field, "solver.petsc_solver");
        assert!(e.message.contains("\"petsc\" only"), "{}", e.message);
    }

    #[test]
    fn mumps_is_refused_for_fracture() {
        let spec = SolverSpec {
            method: Some(super::SolverMethod::Petsc),
            petsc_solver: Some(PetscSolver::Mumps),
            ..Default::default()
        };
        let fracture = RunKind {
            fracture: true,
            ..Default::default()
        };
        let e = validate(&spec, true, fracture).unwrap_err();
        if cfg!(feature = "mpi") {
            assert_eq!(e.field, "solver.petsc_solver");
            assert!(e.message.contains("\"gamg\""), "{}", e.message);
        } else {
            // Without the feature the route itself is refused first.
            assert_eq!(e.field, "solver.method");
        }
    }

    #[test]
    fn an_explicit_run_takes_no_petsc_solver() {
        let spec = SolverSpec {
            method: Some(super::SolverMethod::Petsc),
            petsc_solver: Some(PetscSolver::Gamg),
            ..Default::default()
        };
        let verlet = RunKind {
            dynamics: Some(DynamicsMethod::Verlet),
            ..Default::default()
        };
        let e = validate(&spec, true, verlet).unwrap_err();
        if cfg!(feature = "mpi") {
            assert_eq!(e.field, "solver.petsc_solver");
            assert!(e.message.contains("solves no linear system"));
        } else {
            // Without the feature the route itself is refused first.
            assert_eq!(e.field, "solver.method");
        }
    }

    #[test]
    fn petsc_is_refused_where_it_cannot_run() {
        let dynamic = check_petsc(Some(DynamicsMethod::Relaxation)).unwrap_err();
        assert_eq!(dynamic.field, "solver.method");
        if cfg!(feature = "mpi") {
            assert!(check_petsc(None).is_ok());
            assert!(check_petsc(Some(DynamicsMethod::Verlet)).is_ok());
            assert!(dynamic.message.contains("method = \"verlet\" only"));
        } else {
            let unbuilt = check_petsc(None).unwrap_err();
            assert!(unbuilt.message.contains("built with the mpi feature"));
            assert!(unbuilt.message.contains("\"iterative\""));
            assert_eq!(dynamic, unbuilt);
        }
    }
}
