//! The `[solver]` vocabulary: which route solves `K u = f`, with which
//! fill-reducing ordering and precision, within which memory. The scene owns
//! it; the solver (`solve::pipeline`) reads it as [`SolverSettings`], together
//! with hints the driver computes (a fracture run, a nearly incompressible
//! body), and never reads the rest of the scene.

use super::spec::{ModelKind, SolverSpec};
use super::validate::positive;
use crate::error::InputError;
use serde::{Deserialize, Serialize};

/// Linear solver route (`solver.method`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverMethod {
    /// Sparse Cholesky (symmetric positive definite); the default for the
    /// bond-based model.
    #[default]
    Cholesky,
    /// Sparse LU of `K` (small problems only: up to 20,000 free unknowns).
    Lu,
    /// GMRES on `K`, preconditioned by the Cholesky factor of a symmetric
    /// surrogate (the bond-based stiffness on the bond pattern, or
    /// `(K + Kᵀ)/2`); the default for the shear model.
    Gmres,
    /// CG on `K` (GMRES for a non-symmetric `K`) preconditioned by a two-level
    /// cycle (Chebyshev smoothing, a coarse space of the rigid motions of small
    /// point aggregates): no factor of `K` is stored, memory linear in the points.
    Iterative,
}

/// The fill-reducing ordering of the Cholesky factor (`solver.ordering`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Ordering {
    /// Both analysed; the one whose factorisation needs fewer operations kept
    /// (nested dissection alone above 5e7 stored entries of `K`).
    #[default]
    Auto,
    /// faer's approximate minimum degree.
    Amd,
    /// Geometric nested dissection on the points.
    NestedDissection,
}

/// The precision of the Cholesky factor (`solver.precision`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// Single precision for large factors (from 1e8 entries, where it halves
    /// the factorisation time) or when only that fits in memory; double
    /// otherwise.
    #[default]
    Auto,
    /// Double precision.
    Double,
    /// Single-precision factor; double-precision accuracy recovered by CG
    /// (Cholesky route) or GMRES (shear model) preconditioned by it.
    Mixed,
}

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
}

impl SolverSettings {
    /// The model's default route, chosen automatically, with every other
    /// setting at its default.
    pub fn automatic(model: ModelKind) -> Self {
        Self {
            method: match model {
                ModelKind::BondBased => SolverMethod::Cholesky,
                ModelKind::Shear => SolverMethod::Gmres,
            },
            automatic: true,
            memory_limit_bytes: None,
            refactor_iterations: None,
            ordering: Ordering::Auto,
            precision: Precision::Auto,
        }
    }
}

/// Validates the keys of `[solver]` that need no other section.
pub(super) fn validate(spec: &SolverSpec, model: ModelKind) -> Result<SolverSettings, InputError> {
    if spec.method == Some(SolverMethod::Iterative) {
        for (key, present) in [
            ("solver.ordering", spec.ordering.is_some()),
            ("solver.precision", spec.precision.is_some()),
        ] {
            if present {
                return Err(InputError::new(
                    key,
                    "applies to the direct factor, which solver.method = \"iterative\" \
                     does not compute; remove it or choose \"cholesky\" or \"gmres\"",
                ));
            }
        }
    }
    if spec.refactor_iterations == Some(0) {
        return Err(InputError::new(
            "solver.refactor_iterations",
            "0 would refactorise before every re-solve; give at least 1",
        ));
    }
    let defaults = SolverSettings::automatic(model);
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
    })
}
