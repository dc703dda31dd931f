//! Sparse direct solvers (faer): Cholesky with the symbolic analysis kept for
//! reuse, LU as an explicit fallback, and the residual check.
//!
//! Pivot failures are reported as the free unknown they concern: faer reports
//! the pivot index in the permuted ordering, 1-based on the simplicial path and
//! 0-based on the supernodal path; it is mapped back through the fill-reducing
//! permutation here.

use crate::error::NumericalError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError as DenseLltError, LltRegularization};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::linalg::LuError;
use faer::sparse::SparseColMatRef;
use faer::{Conj, MatMut, Side};

/// A failed factorisation, by free unknown (the driver names the point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FactorError {
    /// Non-positive pivot at this free unknown.
    NonPositivePivot(usize),
    /// Structurally singular at this free unknown (LU).
    Singular(usize),
    /// Allocation or other generic failure.
    Generic,
}

/// Sparse Cholesky `K = L Lᵀ` with a fill-reducing (AMD) ordering.
pub struct Cholesky {
    symbolic: SymbolicCholesky<usize>,
    factor: Vec<f64>,
    factored: bool,
}

impl Cholesky {
    /// Symbolic analysis (ordering, elimination tree, supernodes) of the pattern.
    pub fn analyse(matrix: SparseColMatRef<'_, usize, f64>) -> Result<Self, NumericalError> {
        let symbolic = factorize_symbolic_cholesky(
            matrix.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            Default::default(),
        )
        .map_err(|e| NumericalError::Solver(format!("{e:?}")))?;
        Ok(Self {
            symbolic,
            factor: Vec::new(),
            factored: false,
        })
    }

    /// Number of stored entries of `L`.
    pub fn nnz_l(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Numeric factorisation for new values on the analysed pattern (reuses the factor's memory).
    pub fn factorize(
        &mut self,
        matrix: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), FactorError> {
        self.factored = false;
        let par = faer::get_global_parallelism();
        self.factor.resize(self.symbolic.len_val(), 0.0);
        let mut mem = MemBuffer::try_new(
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        )
        .map_err(|_| FactorError::Generic)?;
        let result = self.symbolic.factorize_numeric_llt(
            &mut self.factor,
            matrix,
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
        match result {
            Ok(_) => {
                self.factored = true;
                Ok(())
            }
            Err(DenseLltError::NonPositivePivot { index }) => {
                let permuted = match self.symbolic.raw() {
                    SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
                    SymbolicCholeskyRaw::Supernodal(_) => index,
                };
                let original = match self.symbolic.perm() {
                    Some(perm) => perm.arrays().0[permuted.min(perm.len() - 1)],
                    None => permuted,
                };
                Err(FactorError::NonPositivePivot(original))
            }
        }
    }

    /// Solves `K x = b` in place with the current factor.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        assert!(self.factored, "solve before a successful factorisation");
        let par = faer::get_global_parallelism();
        let n = b.len();
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, par));
        LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, n, 1),
            par,
            MemStack::new(&mut mem),
        );
    }
}

/// Sparse LU with partial pivoting (faer's COLAMD ordering).
pub struct SparseLu {
    symbolic: SymbolicLu<usize>,
    numeric: Option<Lu<usize, f64>>,
}

impl SparseLu {
    /// Symbolic analysis of the pattern.
    pub fn analyse(matrix: SparseColMatRef<'_, usize, f64>) -> Result<Self, NumericalError> {
        let symbolic = SymbolicLu::try_new(matrix.symbolic())
            .map_err(|e| NumericalError::Solver(format!("{e:?}")))?;
        Ok(Self {
            symbolic,
            numeric: None,
        })
    }

    /// Numeric factorisation.
    pub fn factorize(
        &mut self,
        matrix: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), FactorError> {
        self.numeric = None;
        match Lu::try_new_with_symbolic(self.symbolic.clone(), matrix) {
            Ok(lu) => {
                self.numeric = Some(lu);
                Ok(())
            }
            Err(LuError::SymbolicSingular { index }) => Err(FactorError::Singular(
                index.min(matrix.ncols().saturating_sub(1)),
            )),
            Err(LuError::Generic(_)) => Err(FactorError::Generic),
        }
    }

    /// Solves `K x = b` in place.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        use faer::linalg::solvers::SolveCore;
        let lu = self
            .numeric
            .as_ref()
            .expect("solve before a successful factorisation");
        let n = b.len();
        lu.solve_in_place_with_conj(Conj::No, MatMut::from_column_major_slice_mut(b, n, 1));
    }
}

/// Either solver behind one interface.
pub enum LinearSolver {
    /// Sparse Cholesky.
    Cholesky(Cholesky),
    /// Sparse LU.
    Lu(SparseLu),
}

impl LinearSolver {
    /// Numeric factorisation.
    pub fn factorize(
        &mut self,
        matrix: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), FactorError> {
        match self {
            LinearSolver::Cholesky(s) => s.factorize(matrix),
            LinearSolver::Lu(s) => s.factorize(matrix),
        }
    }

    /// Solves in place.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        match self {
            LinearSolver::Cholesky(s) => s.solve_in_place(b),
            LinearSolver::Lu(s) => s.solve_in_place(b),
        }
    }

    /// Stored entries of the factor(s), when known.
    pub fn nnz_factor(&self) -> Option<usize> {
        match self {
            LinearSolver::Cholesky(s) => Some(s.nnz_l()),
            LinearSolver::Lu(_) => None,
        }
    }
}

/// Relative residual `‖K x − b‖₂ / ‖b‖₂` (0 when `b = 0` and `K x = 0`).
pub fn relative_residual(kx: &[f64], b: &[f64]) -> f64 {
    let r: f64 = kx
        .iter()
        .zip(b)
        .map(|(a, c)| (a - c) * (a - c))
        .sum::<f64>()
        .sqrt();
    let nb: f64 = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    if nb > 0.0 {
        r / nb
    } else if r == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}
