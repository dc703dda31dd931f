//! Sparse LU with partial pivoting (faer's COLAMD ordering): the route for a
//! small non-symmetric `K`, and the last fallback of the `gmres` route.

use super::cholesky::FactorError;
use crate::error::NumericalError;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::linalg::LuError;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut};

/// Sparse LU of `K`.
pub struct SparseLu {
    symbolic: SymbolicLu<usize>,
    numeric: Option<Lu<usize, f64>>,
}

impl SparseLu {
    /// Symbolic analysis of the pattern.
    pub fn analyse(structure: SymbolicSparseColMatRef<'_, usize>) -> Result<Self, NumericalError> {
        let symbolic =
            SymbolicLu::try_new(structure).map_err(|e| NumericalError::Solver(format!("{e:?}")))?;
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
