//! Sparse Cholesky `K = L Lᵀ` (faer) with the symbolic analysis kept for reuse,
//! in double or single precision, and its pivot diagnostics.
//!
//! Pivot failures are reported as the free unknown they concern: faer reports
//! the pivot index in the permuted ordering, 1-based on the simplicial path and
//! 0-based on the supernodal path; it is mapped back through the fill-reducing
//! permutation here. A pivot below [`SINGULAR_PIVOT_RATIO`] of its diagonal
//! entry is reported as a nearly singular unknown.

use crate::error::NumericalError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError as DenseLltError, LltRegularization};
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Side};

/// Pivots of a Cholesky factor `P K Pᵀ = L Lᵀ`: a conditioning indicator.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PivotStats {
    /// Smallest pivot `L_jj²`.
    pub min: f64,
    /// Largest pivot `L_jj²`.
    pub max: f64,
    /// Smallest ratio `L_jj² / K_jj` (1 for a decoupled unknown, round-off for a singular one).
    pub min_ratio: f64,
    /// Free unknown (original numbering) where that ratio occurs.
    pub min_ratio_dof: usize,
}

/// Pivot ratio below which the matrix is treated as singular: the elimination
/// left less than this fraction of an unknown's own stiffness, i.e. the unknown
/// is (to round-off) a combination of the others.
pub const SINGULAR_PIVOT_RATIO: f64 = 1e-12;

/// A failed factorisation, by free unknown (the driver names the point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FactorError {
    /// Non-positive pivot at this free unknown.
    NonPositivePivot(usize),
    /// Structurally singular at this free unknown (LU).
    Singular(usize),
    /// Pivot ratio below [`SINGULAR_PIVOT_RATIO`] at this free unknown.
    NearlySingular(usize, f64),
    /// Allocation or other generic failure.
    Generic,
}

/// Sparse Cholesky `K = L Lᵀ` with a fill-reducing ordering, its values in
/// double precision or, for mixed precision, in single precision (half the
/// memory; the solves convert, and the caller recovers double-precision
/// accuracy with CG preconditioned by this factor).
pub struct Cholesky {
    symbolic: SymbolicCholesky<usize>,
    factor: Vec<f64>,
    /// Single precision: the factor of `K / scale`, `scale` the largest |K_ij|
    /// (so that no entry overflows or underflows single precision).
    single: Option<(Vec<f32>, f64)>,
    factored: bool,
    pivot_stats: Option<PivotStats>,
}

impl Cholesky {
    /// Symbolic analysis (ordering, elimination tree, supernodes) of the
    /// pattern, with AMD or the given elimination order (`order[k]`: the
    /// unknown eliminated `k`-th).
    pub fn analyse(
        structure: SymbolicSparseColMatRef<'_, usize>,
        order: Option<&[usize]>,
    ) -> Result<Self, NumericalError> {
        let inverse = order.map(|fwd| {
            let mut inv = vec![0usize; fwd.len()];
            fwd.iter().enumerate().for_each(|(k, &i)| inv[i] = k);
            inv
        });
        let ordering = match (order, &inverse) {
            (Some(fwd), Some(inv)) => {
                SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(fwd, inv, fwd.len()))
            }
            _ => SymmetricOrdering::Amd,
        };
        let symbolic =
            factorize_symbolic_cholesky(structure, Side::Lower, ordering, Default::default())
                .map_err(|e| NumericalError::Solver(format!("{e:?}")))?;
        Ok(Self {
            symbolic,
            factor: Vec::new(),
            single: None,
            factored: false,
            pivot_stats: None,
        })
    }

    /// Stores the factor in single precision from the next factorisation on.
    pub fn use_single_precision(&mut self) {
        self.factor = Vec::new();
        self.single = Some((Vec::new(), 1.0));
        self.factored = false;
    }

    /// Stores the factor in double precision from the next factorisation on.
    pub fn use_double_precision(&mut self) {
        self.single = None;
        self.factored = false;
    }

    /// Whether the factor is stored in single precision.
    pub fn is_single(&self) -> bool {
        self.single.is_some()
    }

    /// Number of stored entries of `L`.
    pub fn nnz_l(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Floating-point operations of the numeric factorisation, `Σ_j c_j²` over
    /// the column counts `c_j` of `L` (multiply-adds of the column updates;
    /// relaxed supernodes count their explicit zeros).
    pub fn flops(&self) -> f64 {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(sym) => sym
                .col_ptr()
                .windows(2)
                .map(|w| ((w[1] - w[0]) as f64).powi(2))
                .sum(),
            SymbolicCholeskyRaw::Supernodal(sym) => {
                let (begin, end, rows) = (
                    sym.supernode_begin(),
                    sym.supernode_end(),
                    sym.col_ptr_for_row_idx(),
                );
                (0..sym.n_supernodes())
                    .map(|s| {
                        let width = (end[s] - begin[s]) as f64;
                        let below = (rows[s + 1] - rows[s]) as f64;
                        // Σ_{k=1..w} (k + below)²
                        width * below * below
                            + below * width * (width + 1.0)
                            + width * (width + 1.0) * (2.0 * width + 1.0) / 6.0
                    })
                    .sum()
            }
        }
    }

    /// Bytes the numeric factorisation will allocate: the factor's values plus
    /// faer's workspace (and, in single precision, a single-precision copy of
    /// the matrix's values, `nnz_k` of them).
    pub fn factor_bytes(&self, nnz_k: usize) -> usize {
        let par = faer::get_global_parallelism();
        let sym = &self.symbolic;
        if self.is_single() {
            (sym.len_val() + nnz_k) * std::mem::size_of::<f32>()
                + sym
                    .factorize_numeric_llt_scratch::<f32>(par, Default::default())
                    .size_bytes()
        } else {
            sym.len_val() * std::mem::size_of::<f64>()
                + sym
                    .factorize_numeric_llt_scratch::<f64>(par, Default::default())
                    .size_bytes()
        }
    }

    /// Numeric factorisation for new values on the analysed pattern (reuses the factor's memory).
    pub fn factorize(
        &mut self,
        matrix: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), FactorError> {
        self.factored = false;
        let par = faer::get_global_parallelism();
        let result = if let Some((single, scale)) = &mut self.single {
            single.resize(self.symbolic.len_val(), 0.0);
            *scale = matrix.val().iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if !(*scale > 0.0 && scale.is_finite()) {
                return Err(FactorError::Generic);
            }
            let values: Vec<f32> = matrix.val().iter().map(|&v| (v / *scale) as f32).collect();
            let matrix32 = SparseColMatRef::new(matrix.symbolic(), &values);
            let mut mem = MemBuffer::try_new(
                self.symbolic
                    .factorize_numeric_llt_scratch::<f32>(par, Default::default()),
            )
            .map_err(|_| FactorError::Generic)?;
            self.symbolic
                .factorize_numeric_llt(
                    single,
                    matrix32,
                    Side::Lower,
                    LltRegularization::default(),
                    par,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .map(|_| ())
        } else {
            self.factor.resize(self.symbolic.len_val(), 0.0);
            let mut mem = MemBuffer::try_new(
                self.symbolic
                    .factorize_numeric_llt_scratch::<f64>(par, Default::default()),
            )
            .map_err(|_| FactorError::Generic)?;
            self.symbolic
                .factorize_numeric_llt(
                    &mut self.factor,
                    matrix,
                    Side::Lower,
                    LltRegularization::default(),
                    par,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .map(|_| ())
        };
        match result {
            Ok(_) => {
                self.factored = true;
                let pivots = self.pivots(matrix);
                self.pivot_stats = Some(pivots);
                if pivots.min_ratio < SINGULAR_PIVOT_RATIO {
                    self.factored = false;
                    return Err(FactorError::NearlySingular(
                        pivots.min_ratio_dof,
                        pivots.min_ratio,
                    ));
                }
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

    /// The pivots of the current factor, compared with the diagonal of `matrix`.
    pub fn pivots(&self, matrix: SparseColMatRef<'_, usize, f64>) -> PivotStats {
        let n = self.symbolic.nrows();
        let mut diag_l = vec![0.0; n];
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(sym) => {
                let (col_ptr, row_idx) = (sym.col_ptr(), sym.row_idx());
                for (j, d) in diag_l.iter_mut().enumerate() {
                    let k = (col_ptr[j]..col_ptr[j + 1])
                        .find(|&k| row_idx[k] == j)
                        .expect("factor stores its diagonal");
                    *d = match &self.single {
                        Some((single, scale)) => f64::from(single[k]) * scale.sqrt(),
                        None => self.factor[k],
                    };
                }
            }
            SymbolicCholeskyRaw::Supernodal(sym) => {
                for s in 0..sym.n_supernodes() {
                    match &self.single {
                        Some((single, scale)) => {
                            let node = SupernodalLltRef::new(sym, single).supernode(s);
                            let val = node.val();
                            for k in 0..val.ncols() {
                                diag_l[node.start() + k] = f64::from(val[(k, k)]) * scale.sqrt();
                            }
                        }
                        None => {
                            let node = SupernodalLltRef::new(sym, &self.factor).supernode(s);
                            let val = node.val();
                            for k in 0..val.ncols() {
                                diag_l[node.start() + k] = val[(k, k)];
                            }
                        }
                    }
                }
            }
        }
        let fwd: Vec<usize> = match self.symbolic.perm() {
            Some(perm) => perm.arrays().0.to_vec(),
            None => (0..n).collect(),
        };
        let (col_ptr, row_idx, values) = (
            matrix.symbolic().col_ptr(),
            matrix.symbolic().row_idx(),
            matrix.val(),
        );
        let mut stats = PivotStats {
            min: f64::INFINITY,
            max: 0.0,
            min_ratio: f64::INFINITY,
            min_ratio_dof: 0,
        };
        for (j, l) in diag_l.iter().enumerate() {
            let pivot = l * l;
            let col = fwd[j];
            let kjj = (col_ptr[col]..col_ptr[col + 1])
                .find(|&k| row_idx[k] == col)
                .map_or(0.0, |k| values[k]);
            let ratio = pivot / kjj;
            stats.min = stats.min.min(pivot);
            stats.max = stats.max.max(pivot);
            if ratio < stats.min_ratio {
                stats.min_ratio = ratio;
                stats.min_ratio_dof = col;
            }
        }
        stats
    }

    /// Pivot statistics of the last successful factorisation.
    pub fn pivot_stats(&self) -> Option<PivotStats> {
        self.pivot_stats
    }

    /// The current factor in double precision, for the halves of its solve
    /// ([`super::triangular`]); `None` before a factorisation or in single precision.
    pub fn double_factor(&self) -> Option<super::triangular::Llt<'_>> {
        (self.factored && self.single.is_none())
            .then(|| super::triangular::Llt::new(&self.symbolic, &self.factor))
    }

    /// Solves `K x = b` in place with the current factor.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        self.solve_columns_in_place(b, 1);
    }
}

impl Cholesky {
    /// Solves `K X = B` in place for the `columns` columns of `B`, stored one
    /// after the other in `b` (one blocked pass through the factor). A
    /// single-precision factor solves a copy of `B` scaled to its largest
    /// entry (so that single precision neither overflows nor underflows).
    pub fn solve_columns_in_place(&self, b: &mut [f64], columns: usize) {
        assert!(self.factored, "solve before a successful factorisation");
        let par = faer::get_global_parallelism();
        let n = b.len() / columns.max(1);
        match &self.single {
            Some((single, matrix_scale)) => {
                // (K / s)⁻¹ (b / t) = K⁻¹ b / (s t): solve the scaled copy, scale back.
                let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                if scale == 0.0 || !scale.is_finite() {
                    return;
                }
                let mut b32: Vec<f32> = b.iter().map(|&v| (v / scale) as f32).collect();
                let mut mem =
                    MemBuffer::new(self.symbolic.solve_in_place_scratch::<f32>(columns, par));
                LltRef::new(&self.symbolic, single).solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(&mut b32, n, columns),
                    par,
                    MemStack::new(&mut mem),
                );
                b.iter_mut()
                    .zip(&b32)
                    .for_each(|(v, w)| *v = f64::from(*w) * scale / matrix_scale);
            }
            None => {
                let mut mem =
                    MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(columns, par));
                LltRef::new(&self.symbolic, &self.factor).solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(b, n, columns),
                    par,
                    MemStack::new(&mut mem),
                );
            }
        }
    }
}

/// A 2D grid Laplacian plus identity (SPD, both triangles stored), with the
/// diagonal of unknown `bad` replaced by `bad_value` (shared by the tests of
/// the refinement).
#[cfg(test)]
pub(super) fn laplacian(
    m: usize,
    bad: usize,
    bad_value: f64,
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let n = m * m;
    let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
    for c in 0..n {
        let (i, j) = (c % m, c / m);
        let mut entries = vec![(c, if c == bad { bad_value } else { 5.0 })];
        if i > 0 {
            entries.push((c - 1, -1.0));
        }
        if i + 1 < m {
            entries.push((c + 1, -1.0));
        }
        if j > 0 {
            entries.push((c - m, -1.0));
        }
        if j + 1 < m {
            entries.push((c + m, -1.0));
        }
        entries.sort_by_key(|e| e.0);
        for (r, v) in entries {
            row_idx.push(r);
            values.push(v);
        }
        col_ptr.push(row_idx.len());
    }
    (col_ptr, row_idx, values)
}

/// The AMD analysis of `structure` on the factor layout (simplicial or
/// supernodal) that `threshold` forces, for the tests of both layouts.
#[cfg(test)]
pub(super) fn analyse_forced(
    structure: SymbolicSparseColMatRef<'_, usize>,
    threshold: faer::sparse::linalg::SupernodalThreshold,
) -> Cholesky {
    let params = faer::sparse::linalg::cholesky::CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: threshold,
        ..Default::default()
    };
    let symbolic =
        factorize_symbolic_cholesky(structure, Side::Lower, SymmetricOrdering::Amd, params)
            .expect("symbolic analysis of a test matrix");
    Cholesky {
        symbolic,
        factor: Vec::new(),
        single: None,
        factored: false,
        pivot_stats: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::relative_residual;
    use faer::sparse::linalg::SupernodalThreshold;

    /// The reported unknown is the one with the negative diagonal, on both of
    /// faer's paths (simplicial reports 1-based, supernodal 0-based pivots).
    #[test]
    fn non_positive_pivot_names_the_right_unknown() {
        for (m, threshold) in [
            (6, SupernodalThreshold::FORCE_SIMPLICIAL),
            (30, SupernodalThreshold::FORCE_SUPERNODAL),
        ] {
            for bad in [0, 7, m * m / 2 + 3, m * m - 1] {
                let (col_ptr, row_idx, values) = laplacian(m, bad, -100.0);
                let n = m * m;
                let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
                let matrix = SparseColMatRef::new(sym, &values);
                let mut chol = analyse_forced(sym, threshold);
                assert_eq!(
                    chol.factorize(matrix),
                    Err(FactorError::NonPositivePivot(bad)),
                    "m = {m}, bad = {bad}"
                );
            }
        }
    }

    /// Pivots of an SPD matrix are positive and bounded by the diagonal; the
    /// solve satisfies the system to round-off.
    #[test]
    fn pivot_stats_and_solve() {
        let (col_ptr, row_idx, values) = laplacian(20, 0, 5.0);
        let n = 400;
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let matrix = SparseColMatRef::new(sym, &values);
        let mut chol = Cholesky::analyse(sym, None).unwrap();
        chol.factorize(matrix).unwrap();
        let stats = chol.pivot_stats.unwrap();
        assert!(
            stats.min > 0.0
                && stats.max <= 5.0 + 1e-12
                && stats.min_ratio > 0.2
                && stats.min_ratio <= 1.0
        );
        let b: Vec<f64> = (0..n).map(|k| (k as f64).sin()).collect();
        let mut x = b.clone();
        chol.solve_in_place(&mut x);
        let mut kx = vec![0.0; n];
        for c in 0..n {
            for k in col_ptr[c]..col_ptr[c + 1] {
                kx[row_idx[k]] += values[k] * x[c];
            }
        }
        assert!(relative_residual(&kx, &b) < 1e-14);
    }
}
