//! The linear solver: it sees matrices, not physics.
//!
//! Its input is the pattern of `K` (built by the assembly), a [`Layout`] of
//! the unknowns (where each sits, for the geometric orderings, the two-level
//! aggregates and the messages that name a point), the scene's `[solver]`
//! settings and hints the driver computes ([`route::Hints`]); then, per
//! solve, the values of `K` and, for the `gmres` route, of a symmetric
//! surrogate the assembly provides ([`Matrices`]). It never sees bonds,
//! materials or models.
//!
//! - [`route`]: which route a system takes (method, ordering, precision; the
//!   automatic switch to the iterative route), decided from the pattern before
//!   any value is assembled;
//! - [`pipeline`]: the state machine of one system: fresh solves with the
//!   residual check, re-solves after bonds broke (low-rank update of the
//!   factor, or Krylov iterations preconditioned by it);
//! - [`cholesky`], [`lu`]: the sparse factors (faer); [`refine`]: iterative
//!   refinement; [`cg`], [`gmres`]: the Krylov methods; [`low_rank`]: the
//!   Sherman–Morrison–Woodbury update; [`triangular`]: the halves of a
//!   Cholesky solve and sparse forward solves along the elimination tree;
//!   [`ordering`]: geometric nested
//!   dissection; [`two_level`]: the preconditioner of the iterative route;
//!   `petsc` (the `mpi` feature): PETSc's distributed Krylov solvers and
//!   algebraic multigrid on the processes of an MPI run.

pub mod cg;
pub mod cholesky;
pub mod gmres;
pub mod low_rank;
pub mod lu;
pub mod ordering;
#[cfg(feature = "mpi")]
pub mod petsc;
pub mod pipeline;
pub mod refine;
pub mod route;
pub mod triangular;
pub mod two_level;

use crate::assembly::dofs::DofMap;
use crate::assembly::stiffness::Stiffness;

/// Relative residual GMRES and CG aim at.
pub const GMRES_TOLERANCE: f64 = 1e-12;

/// Krylov iterations allowed with the two-level preconditioner (it needs
/// 15-25 on the bodies measured, independent of their size), and with
/// PETSc's GAMG.
pub const ITERATIVE_BUDGET: usize = 2000;

/// GMRES restart length (dhpd's GMRES and PETSc's).
pub(crate) const GMRES_RESTART: usize = 60;

/// Where the unknowns sit: what the solver knows of the body (no bond,
/// material or model).
#[derive(Debug, Clone, Copy)]
pub struct Layout<'a> {
    /// Position of every point (the geometric orderings, the aggregates).
    pub x: &'a [[f64; 3]],
    /// Spacing of every point (the aggregates reach 1.5 spacings).
    pub spacing: &'a [f64],
    /// The process of every point when the body is split over several
    /// (the driver's setup cuts them); `None`: one process.
    #[cfg(feature = "mpi")]
    pub part: Option<&'a [u32]>,
    /// The point and component of every free unknown, and back.
    pub dofs: &'a DofMap,
}

impl Layout<'_> {
    /// Spatial dimension.
    pub fn d(&self) -> usize {
        self.dofs.d
    }

    /// The point and component of free unknown `k`.
    pub fn unknown(&self, k: usize) -> (usize, usize) {
        let (i, c) = self.dofs.free_dofs[k];
        (i as usize, c as usize)
    }
}

/// The values one solve works with: `K`, and the symmetric positive definite
/// surrogate the `gmres` route factorises as its preconditioner (on the
/// pattern given to [`pipeline::Pipeline::analyse`]; the bond-based stiffness
/// for the shear model).
#[derive(Debug, Clone, Copy)]
pub struct Matrices<'a> {
    /// `K` on the pattern of the pipeline.
    pub k: &'a Stiffness,
    /// The surrogate, when the pipeline asked for one.
    pub surrogate: Option<&'a Stiffness>,
    /// The point columns of `K` whose values changed since the last solve
    /// (`None`: any may have), for a route that hands `K` over in place.
    pub changed: Option<&'a [bool]>,
}

/// Euclidean norm without overflow or underflow of the squares: scaled by the
/// largest magnitude first (a vector of 1e160s has a norm, not ∞; non-finite
/// entries give a non-finite norm).
pub fn norm2<I: Iterator<Item = f64> + Clone>(values: I) -> f64 {
    let mut largest = 0.0f64;
    for v in values.clone() {
        if v.is_nan() {
            return f64::NAN;
        }
        largest = largest.max(v.abs());
    }
    if largest == 0.0 || largest.is_infinite() {
        return largest;
    }
    largest
        * values
            .map(|v| (v / largest) * (v / largest))
            .sum::<f64>()
            .sqrt()
}

/// Relative residual `‖K x − b‖₂ / ‖b‖₂` (0 when `b = 0` and `K x = 0`).
pub fn relative_residual(kx: &[f64], b: &[f64]) -> f64 {
    let r = norm2(kx.iter().zip(b).map(|(a, c)| a - c));
    let nb = norm2(b.iter().copied());
    if nb > 0.0 {
        r / nb
    } else if r == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn norm2_neither_overflows_nor_underflows() {
        let big = [3e200, 4e200];
        assert!((norm2(big.iter().copied()) / 5e200 - 1.0).abs() < 1e-15);
        let small = [3e-200, 4e-200];
        assert!((norm2(small.iter().copied()) / 5e-200 - 1.0).abs() < 1e-15);
        assert_eq!(norm2([0.0, 0.0].iter().copied()), 0.0);
        assert!(norm2([1.0, f64::NAN, 2.0].iter().copied()).is_nan());
        assert_eq!(norm2([1.0, f64::INFINITY].iter().copied()), f64::INFINITY);
        assert!(
            (relative_residual(&[1e160, 2e160], &[1e160, 1e160]) - 0.5f64.sqrt()).abs() < 1e-15
        );
    }
}
